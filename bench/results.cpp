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

// One scene's table: every method (and the peer) in `reps` interleaved rounds. Throws on a scene
// that does not load or fit the device.
void print_scene(const std::string& name, const std::optional<Size>& resolution,
                 const std::vector<std::string>& methods, int reps, const std::string& peer) {
  Scene scene = load_scene(std::string(TP_SCENES_DIR) + "/" + name + ".json");
  if (resolution) {
    scene.width = resolution->width;
    scene.height = resolution->height;
  }
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
    std::printf("| %s | %.4f | %.1f | %.3f | %d | %.3f / %d | %.2f | %.2f |\n", m.c_str(),
                r.phong.color_correctness, r.phong.psnr_db, r.phong.mean_abs, r.phong.max_abs,
                r.angular.mean_abs, r.angular.max_abs, ms, ms / gouraud);
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
      ->check(CLI::Range(1, 1000));
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
  std::vector<std::string> methods = list_items(methods_arg);
  if (methods.empty())
    for (const auto& m : method_names()) methods.emplace_back(m.name);
  if (std::find(methods.begin(), methods.end(), "gouraud") == methods.end())
    methods.insert(methods.begin(), "gouraud");  // the yardstick of every ratio

  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d", std::gmtime(&now));
  std::cout << "Measured " << date
            << "; error against the double Phong reference (and the "
               "angular one), time = median frame time / Gouraud's in the same run ("
            << reps << " interleaved rounds).\n\n";

  try {
    for (const std::string& name : scenes) print_scene(name, resolution, methods, reps, peer);
  } catch (const std::exception& e) {  // a scene that does not load or does not fit the device
    std::cerr << "tinyphong-results: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
