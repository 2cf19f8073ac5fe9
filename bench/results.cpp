// Regenerates the tables of docs/RESULTS.md: for every paper scene and every shading method,
// the error against the double references and the frame time as a ratio to Gouraud measured
// in the same run (docs/RESULTS.md). Timing: the methods are interleaved round-robin, `--reps`
// rounds, and each method's median frame time is taken, so that machine noise hits all
// methods alike. `--peer llvmpipe` adds Mesa's llvmpipe (host/llvmpipe.hpp: per-pixel float
// Blinn-Phong in GLSL, one thread) as one more row, timed in the same rounds.
//
//   build/release/bench/tinyphong-results [--scenes a,b] [--methods x,y] [--reps 7] [--size WxH]
//                                         [--peer llvmpipe]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <exception>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "host/cli_options.hpp"
#include "host/device_renderer.hpp"
#include "host/llvmpipe.hpp"
#include "host/metrics.hpp"
#include "host/scene.hpp"
#include "host/size_text.hpp"
#include "host/standard_output.hpp"

namespace {

using namespace tp::host;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

constexpr const char* kPeerName = "llvmpipe";

struct Row {
  std::string method;
  Comparison phong, angular;
  double ms = 0;
  std::uint64_t pixels = 0;
};

// A name, not a path: "../x" and "/etc/passwd" were joined to scenes/ and read.
bool is_scene_name(const std::string& name) {
  return name.find_first_of("/\\") == std::string::npos && !name.starts_with('.');
}

// A scene of scenes/ by name, at the resolution given: throws naming it if it does not load, or
// does not fit the device (its checks, as a render's).
Scene load_named_scene(const std::string& name, const std::optional<Size>& resolution) {
  Scene scene = load_scene(std::string(TP_SCENES_DIR) + "/" + name + ".json");
  if (resolution) {
    scene.width = resolution->width;
    scene.height = resolution->height;
  }
  DeviceRenderer(scene.width, scene.height).set_scene(scene);
  return scene;
}

// A measure printed by `format`, or "–" where no pixel is covered in both images
// (Comparison::measured).
std::string cell(const Comparison& c, const char* format, double value) {
  if (!c.measured()) return "–";
  char text[32];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

// One scene's table: every method (and the peer) in `reps` interleaved rounds.
void print_scene(const std::string& name, const Scene& scene,
                 const std::vector<std::string>& methods, int reps, const std::string& peer) {
  DeviceRenderer device(scene.width, scene.height);
  device.set_scene(scene);
  const ReferenceFrame ref = device.render_reference(0.0, Interpolation::Phong);
  const ReferenceFrame ang = device.render_reference(0.0, Interpolation::Angular);

  std::map<std::string, std::vector<double>> times;
  std::map<std::string, Row> rows;
  std::unique_ptr<LlvmpipePeer> llvmpipe;
  if (!peer.empty()) {  // a PeerError ends the run, as a scene's error does (main)
    llvmpipe = std::make_unique<LlvmpipePeer>(scene.width, scene.height);
    llvmpipe->set_scene(scene);
  }
  for (int round = 0; round < reps; ++round) {
    if (llvmpipe) {  // first in the round, so that no method always follows it
      const PeerFrame f = llvmpipe->render(0.0);
      times[kPeerName].push_back(f.render_ms);
      if (round == 0) {
        Row& r = rows[kPeerName];
        r.method = kPeerName;
        r.phong = compare(ref.image(), ref.covered, f.image(), f.covered);
        r.angular = compare(ang.image(), ang.covered, f.image(), f.covered);
      }
    }
    for (const std::string& m : methods) {
      Scene s = scene;
      s.method = m;
      device.set_scene(s);
      const DeviceFrame f = device.render(0.0);
      times[m].push_back(f.render_ms);
      if (round == 0) {
        Row& r = rows[m];
        r.method = m;
        r.phong = compare(ref.image(), ref.covered, f.image(), f.covered);
        r.angular = compare(ang.image(), ang.covered, f.image(), f.covered);
        for (const auto& [k, v] : f.counters)
          if (k == "pixels_written") r.pixels = v;
      }
    }
  }
  const double gouraud = median(times["gouraud"]);
  std::printf("### %s (%dx%d, %zu light%s)\n\n", name.c_str(), scene.width, scene.height,
              scene.lights.size(), scene.lights.size() == 1 ? "" : "s");
  std::printf(
      "| method | colour correctness | PSNR dB | mean abs | max abs | vs angular: mean / max | "
      "frame ms | time / Gouraud |\n|---|---|---|---|---|---|---|---|\n");
  std::vector<std::string> shown = methods;
  if (llvmpipe) shown.emplace_back(kPeerName);
  for (const std::string& m : shown) {
    const Row& r = rows[m];
    const double ms = median(times[m]);
    std::printf("| %s | %s | %s | %s | %s | %s / %s | %.2f | %.2f |\n", m.c_str(),
                cell(r.phong, "%.4f", r.phong.color_correctness).c_str(),
                cell(r.phong, "%.1f", r.phong.psnr_db).c_str(),
                cell(r.phong, "%.3f", r.phong.mean_abs).c_str(),
                cell(r.phong, "%.0f", r.phong.max_abs).c_str(),
                cell(r.angular, "%.3f", r.angular.mean_abs).c_str(),
                cell(r.angular, "%.0f", r.angular.max_abs).c_str(), ms, ms / gouraud);
  }
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tinyphong results: error and time ratio per scene and method"};
  std::string scenes_arg = "sphere-32,sphere-40,sphere-512,dodecahedron-30,triangle,teapot";
  std::string methods_arg, size, peer;
  int reps = 7;
  app.add_option("--scenes", scenes_arg, "comma-separated scene names from scenes/");
  app.add_option("--methods", methods_arg, "comma-separated methods (default: all)")
      ->check(method_list_check());
  app.add_option("--reps", reps, "timing rounds per method (median taken)")
      ->transform(whole_number(1, 1000));
  app.add_option("--size", size, "override the resolution, WIDTHxHEIGHT")->check(size_check());
  app.add_option("--peer", peer, "also time a peer renderer in the same rounds")
      ->check(CLI::IsMember({std::string(kPeerName)}));
  // The options are checked as options: a bad method or size ended in an uncaught exception
  // (SIGABRT), the method blamed on a scene file's line 0.
  if (const std::optional<int> status = parse_options(app, argc, argv)) return *status;
  const std::optional<Size> resolution = parse_size(size);  // none without --size
  const std::vector<std::string> scenes = list_items(scenes_arg);
  if (scenes.empty()) {  // printed the header alone and exited 0
    std::cerr << "--scenes: no scene named in '" << scenes_arg << "'\n";
    return 2;
  }
  for (const std::string& name : scenes)
    if (!is_scene_name(name)) {
      std::cerr << "--scenes: '" << name << "' is not a scene name (a file of scenes/ without "
                << ".json)\n";
      return 2;
    }
  std::vector<std::string> methods = list_items(methods_arg);
  if (methods.empty())
    for (const auto& m : method_names()) methods.emplace_back(m.name);
  if (std::find(methods.begin(), methods.end(), "gouraud") == methods.end())
    methods.insert(methods.begin(), "gouraud");  // the yardstick of every ratio

  // Every scene is read and checked before any is measured: a bad name last in the list ended
  // the run after the others' tables (minutes of rounds) with a partial report.
  std::vector<Scene> loaded;
  try {
    for (const std::string& name : scenes) loaded.push_back(load_named_scene(name, resolution));
  } catch (const std::exception& e) {
    std::cerr << "tinyphong-results: " << e.what() << "\n";
    return 1;
  }

  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d", std::gmtime(&now));
  std::cout << "Measured " << date
            << "; error against the double Phong reference (and the "
               "angular one), time = median frame time / Gouraud's in the same run ("
            << reps << " interleaved rounds).\n\n";

  try {
    for (std::size_t i = 0; i < scenes.size(); ++i)
      print_scene(scenes[i], loaded[i], methods, reps, peer);
  } catch (const std::exception& e) {  // the peer's error (PeerError)
    std::cerr << "tinyphong-results: " << e.what() << "\n";
    return 1;
  }
  return standard_output_written("tinyphong-results") ? 0 : 1;
}
