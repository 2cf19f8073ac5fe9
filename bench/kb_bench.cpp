// tinyphong-kb-bench: the measured tables of docs/KUIJK-BLAKE.md.
//
//   build/release/bench/tinyphong-kb-bench [--reps 5] [--quick]
//
// 1. Time and error per scene × lights (1, 2, 4, 8) × method: frame time through the device
//    (host/device_renderer) as a ratio to Gouraud measured in the same run (methods interleaved
//    round-robin, median of --reps rounds), colour correctness against the double Phong
//    reference, mean / max level error against the angular reference. For the one-vector
//    method also the split of its own work (a replay of the frame's triangles through the method
//    alone, outside the device): triangle setup, span setup (prepare_span), per-pixel stepping.
// 2. The speed targets: triangle and sphere-32 at 1024×1024, teapot at 640×480.
// 3. The exponent sweep n in {1, 5, 20, 50, 125, 500, 2000}: colour correctness of kb.
// 4. Coherent span setup against the exact setup of every span: level differences.
// 5. Diffuse f(n = 1) against the clamped cosine max(0, cos θ).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "firmware/geometry.hpp"
#include "firmware/kb/kb_methods.hpp"
#include "firmware/raster.hpp"
#include "host/cli_options.hpp"
#include "host/device_renderer.hpp"
#include "host/metrics.hpp"
#include "host/scene.hpp"
#include "host/standard_output.hpp"
#include "kb_replay.hpp"
#include "tables/cosn_reference.hpp"

namespace {

using namespace tp;
using Clock = std::chrono::steady_clock;
using kbbench::CoherenceDiff;
using kbbench::compare_coherent_with_exact;
using kbbench::Frame;
using kbbench::replay_frame;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

host::Scene load(const std::string& name, int size = 0) {
  host::Scene s = host::load_scene(std::string(TP_SCENES_DIR) + "/" + name + ".json");
  if (size > 0) s.width = s.height = size;
  return s;
}

// Calls prepare_span only, or the whole shade_span, for every span.
struct KbTarget final : fw::SpanTarget {
  fw::kb::KbOneVectorMethod* m = nullptr;
  bool full = true;
  fw::Rgb8 out[fw::kMaxDimension];
  void span(const fw::Span& s) override {
    if (full)
      m->shade_span(s, out);
    else
      m->prepare_span(s);
  }
};

struct Split {
  double triangle_ms = 0, span_setup_ms = 0, pixel_ms = 0;
};

Split time_split(Frame& f, int reps) {
  auto method = std::make_unique<fw::kb::KbOneVectorMethod>(true);
  auto target = std::make_unique<KbTarget>();
  target->m = method.get();
  std::vector<double> a, b, c;
  for (int r = 0; r < reps; ++r) {
    auto t0 = Clock::now();
    for (const auto& t : f.tris) method->setup(t, f.ctx);
    a.push_back(ms_since(t0));
    target->full = false;
    t0 = Clock::now();
    for (const auto& t : f.tris)
      if (method->setup(t, f.ctx)) fw::rasterize(t, f.width, f.height, *target);
    b.push_back(ms_since(t0));
    target->full = true;
    t0 = Clock::now();
    for (const auto& t : f.tris)
      if (method->setup(t, f.ctx)) fw::rasterize(t, f.width, f.height, *target);
    c.push_back(ms_since(t0));
  }
  const double ma = median(a), mb = median(b), mc = median(c);
  return {ma, std::max(0.0, mb - ma), std::max(0.0, mc - mb)};
}

void coherence_row(const std::string& name, Frame& f) {
  const CoherenceDiff d = compare_coherent_with_exact(f);
  std::printf("| %s | %lld | %lld (%.3f %%) | %.4f | %d |\n", name.c_str(), d.pixels, d.differing,
              100.0 * static_cast<double>(d.differing) / static_cast<double>(d.pixels),
              static_cast<double>(d.sum) / static_cast<double>(d.pixels), d.max);
}

struct Errors {
  double cc = 0, ang_mean = 0;
  int ang_max = 0;
};
Errors errors(const host::DeviceFrame& f, const host::ReferenceFrame& phong,
              const host::ReferenceFrame& angular) {
  const auto p = host::compare(phong.image(), phong.covered, f.image(), f.covered);
  const auto a = host::compare(angular.image(), angular.covered, f.image(), f.covered);
  return {p.color_correctness, a.mean_abs, a.max_abs};
}

void time_table(const std::string& base, const std::vector<int>& lights, int size, int reps,
                const std::vector<std::string>& methods) {
  for (int l : lights) {
    const std::string name = l == 1 ? base : base + "-l" + std::to_string(l);
    host::Scene scene = load(name, size);
    host::DeviceRenderer r(scene.width, scene.height);
    r.set_scene(scene);
    const host::ReferenceFrame phong = r.render_reference(0.0, host::Interpolation::Phong);
    const host::ReferenceFrame angular = r.render_reference(0.0, host::Interpolation::Angular);
    std::vector<std::vector<double>> times(methods.size());
    std::vector<Errors> err(methods.size());
    for (int rep = 0; rep < reps; ++rep)
      for (std::size_t m = 0; m < methods.size(); ++m) {
        if (methods[m] == "kb-exact" && rep > 0 && l > 2) continue;  // minutes per frame
        scene.method = methods[m];
        r.set_scene(scene);
        const host::DeviceFrame f = r.render(0.0);
        times[m].push_back(f.render_ms);
        if (rep == 0) err[m] = errors(f, phong, angular);
      }
    scene.method = "kb";
    r.set_scene(scene);
    (void)r.render(0.0);
    Frame frame = replay_frame(r, scene);
    const Split split = time_split(frame, reps);
    const double total = split.triangle_ms + split.span_setup_ms + split.pixel_ms;
    const double gouraud = median(times[0]);
    for (std::size_t m = 0; m < methods.size(); ++m) {
      std::printf("| %s | %dx%d | %d | %s | %.2f | %.2f |", base.c_str(), scene.width, scene.height,
                  l, methods[m].c_str(), median(times[m]), median(times[m]) / gouraud);
      if (methods[m] == "kb")
        std::printf(" %.0f / %.0f / %.0f |", 100 * split.triangle_ms / total,
                    100 * split.span_setup_ms / total, 100 * split.pixel_ms / total);
      else
        std::printf(" |");
      std::printf(" %.4f | %.3f / %d |\n", err[m].cc, err[m].ang_mean, err[m].ang_max);
    }
    std::fflush(stdout);
  }
}

void exponent_sweep(const std::vector<std::string>& scenes) {
  std::printf(
      "\n| scene | n=1 | n=5 | n=20 | n=50 | n=125 | n=500 | n=2000 "
      "|\n|---|---|---|---|---|---|---|---|\n");
  for (const auto& name : scenes) {
    std::printf("| %s |", name.c_str());
    for (int n : {1, 5, 20, 50, 125, 500, 2000}) {
      host::Scene scene = load(name);
      scene.material.n = n;
      scene.method = "kb";
      host::DeviceRenderer r(scene.width, scene.height);
      r.set_scene(scene);
      const host::DeviceFrame f = r.render(0.0);
      const host::ReferenceFrame phong = r.render_reference(0.0, host::Interpolation::Phong);
      const auto p = host::compare(phong.image(), phong.covered, f.image(), f.covered);
      std::printf(" %.4f |", p.color_correctness);
    }
    std::printf("\n");
    std::fflush(stdout);
  }
}

void diffuse_vs_cosine() {
  const auto p = fw::kb::kDiffuseParams;
  const double a = std::ldexp(static_cast<double>(p.a.raw()), -29);
  const double b = std::ldexp(static_cast<double>(p.b.raw()), -29);
  double worst = 0, at = 0, tail = 0, cos_area = 0;
  const int steps = 200000;
  for (int i = 0; i <= steps; ++i) {
    const double t = std::numbers::pi * i / steps;
    const double f = tables::cosn::f_quad(t, a, b), c = std::max(0.0, std::cos(t));
    if (std::fabs(f - c) > worst) worst = std::fabs(f - c), at = t;
    if (t > std::numbers::pi / 2) tail += f * std::numbers::pi / steps;
    cos_area += c * std::numbers::pi / steps;
  }
  std::printf(
      "\nDiffuse f(n = 1), least-squares (a, b) = (%.5f, %.5f) rad: max |f − max(0, cos)| = %.4f "
      "at θ = %.3f rad (%.1f°); f > 0 up to b = %.1f°; light past the terminator "
      "∫_{π/2}^{b} f = %.4f (%.2f %% of ∫ max(0, cos) = %.4f).\n",
      a, b, worst, at, at * 180 / std::numbers::pi, b * 180 / std::numbers::pi, tail,
      100 * tail / cos_area, cos_area);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tinyphong-kb-bench: Kuijk-Blake time, error and setup-share tables"};
  int reps = 5;
  bool quick = false;
  app.add_option("--reps", reps, "timing rounds (median taken)")
      ->transform(tp::host::whole_number(1, 100));
  app.add_flag("--quick", quick, "one light count and no sweep (smoke run)");
  if (const std::optional<int> status = tp::host::parse_options(app, argc, argv)) return *status;
  const std::vector<std::string> scenes = {"sphere-32",       "sphere-40", "sphere-512",
                                           "dodecahedron-30", "triangle",  "teapot"};
  const std::vector<int> lights = quick ? std::vector<int>{1} : std::vector<int>{1, 2, 4, 8};
  std::printf(
      "| scene | size | lights | method | frame ms | time / Gouraud | kb work: triangle / span "
      "setup / pixels %% | colour correctness (Phong ref) | vs angular: mean / max |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  const std::vector<std::string> methods = {"gouraud", "phong", "kb", "kb-decomposition",
                                            "kb-exact"};
  for (const auto& s : scenes) time_table(s, lights, 0, reps, methods);
  std::printf("\nSpeed targets (same columns):\n\n");
  time_table("triangle", {1, 8}, 1024, reps, {"gouraud", "phong", "kb"});
  time_table("sphere-32", {1, 8}, 1024, reps, {"gouraud", "phong", "kb"});
  std::printf("\nCoherent span setup against the exact setup of every span (1 light):\n\n");
  std::printf(
      "| scene | pixels | differing | mean |Δ| levels | max |Δ| |\n|---|---|---|---|---|\n");
  for (const auto& s : scenes) {
    host::Scene scene = load(s);
    scene.method = "kb";
    host::DeviceRenderer r(scene.width, scene.height);
    r.set_scene(scene);
    (void)r.render(0.0);
    Frame f = replay_frame(r, scene);
    coherence_row(s, f);
  }
  if (!quick) exponent_sweep(scenes);
  diffuse_vs_cosine();
  return tp::host::standard_output_written("tinyphong-kb-bench") ? 0 : 1;
}
