// tinyphong-draw: renders a scene once with the device and prints its counters, nothing else —
// the program scripts/instructions.sh runs under callgrind. It links no image library (the
// linker drops what it does not use), so that valgrind never loads OpenImageIO's dependencies:
// libhwy's start-up code executes rdtscp, which valgrind rejects on processors that do not
// advertise it.
//
//   tinyphong-draw scenes/teapot.json --method kb-adaptive [--size 1024x1024] [--budget B]
//
// --frames N renders the frame N times back to back and prints the median frame time: the loop
// to run under `perf record` when profiling the frame alone (warm caches, no peer in between,
// unlike tinyphong-results' interleaved rounds; docs/DECISIONS.md, "The vertex cache projects").
#include <algorithm>
#include <exception>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "firmware/types.hpp"
#include "host/cli_options.hpp"
#include "host/device_renderer.hpp"
#include "host/scene.hpp"
#include "host/size_text.hpp"
#include "host/standard_output.hpp"

int main(int argc, char** argv) {
  using namespace tp::host;
  CLI::App app{"render a scene once with the device and print its counters"};
  std::string scene_file, method, size;
  int budget = 0;
  int frames = 1;
  app.add_option("scene", scene_file, "scene file (JSON)")->required()->check(CLI::ExistingFile);
  app.add_option("--method", method, "shading method (tinyphong methods)")->check(method_check());
  app.add_option("--size", size, "override the resolution, WIDTHxHEIGHT")->check(size_check());
  app.add_option("--budget", budget,
                 "kb-adaptive's error budget in output levels (default: the scene's)")
      ->transform(whole_number(1, tp::fw::kMaxBudgetLevels));
  app.add_option("--frames", frames, "render this many frames and print the median frame time")
      ->transform(whole_number(1, 100000));
  if (const std::optional<int> status = parse_options(app, argc, argv)) return *status;
  try {
    Scene scene = load_scene(scene_file);
    if (!method.empty()) scene.method = method;
    if (budget != 0) scene.budget = budget;
    if (const std::optional<Size> resolution = parse_size(size)) {  // checked by size_check
      scene.width = resolution->width;
      scene.height = resolution->height;
    }
    DeviceRenderer device(scene.width, scene.height);
    device.set_scene(scene);
    std::vector<double> ms;
    DeviceFrame frame = device.render();
    ms.push_back(frame.render_ms);
    for (int i = 1; i < frames; ++i) ms.push_back(device.render().render_ms);
    std::cout << "drew " << scene.name << " (" << frame.width << "x" << frame.height << ", "
              << scene.method << ")\n";
    if (frames > 1) {
      std::nth_element(ms.begin(), ms.begin() + frames / 2, ms.end());
      std::cout << "median frame time over " << frames << " frames: " << ms[ms.size() / 2]
                << " ms\n";
    }
    std::cout << "counters:\n";
    for (const auto& [name, value] : frame.counters)
      std::cout << "  " << name << " = " << value << "\n";
  } catch (const std::exception& e) {
    std::cerr << "tinyphong-draw: " << e.what() << "\n";
    return 1;
  }
  return standard_output_written("tinyphong-draw") ? 0 : 1;
}
