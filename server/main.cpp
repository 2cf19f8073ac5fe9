// tinyphong-server: streams the emulated device's framebuffer to browsers (docs/SERVER.md).
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>

#include <CLI/CLI.hpp>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "host/cli_numbers.hpp"
#include "server/pattern_source.hpp"
#ifdef TP_HAVE_DEVICE
#include "server/device_source.hpp"
#endif
#include "server/server.hpp"

namespace {

// glibc raises its mmap threshold to the size of each large block freed (up to 32 MiB), after
// which frames, references and send queues of a few hundred KiB to a few MiB are carved from the
// threads' heaps, where the holes they leave keep the pages resident: the soak test measured
// +3.6 MiB after its storms with the dynamic threshold and +0.5 MiB with a fixed one (same seed,
// docs/SERVER.md "Soak test"). Fixing the threshold at glibc's default keeps such blocks in
// their own mappings, which go back to the system when freed.
void keep_large_blocks_out_of_the_heaps() {
#ifdef __GLIBC__
  mallopt(M_MMAP_THRESHOLD, 128 * 1024);
#endif
}

// A number of seconds or frames per second within [lo, hi]. CLI::Range let NaN through (every
// comparison with it is false), which then became a duration: undefined behaviour, an unpaced
// loop for --max-fps and every client cut off at once for --deadline.
CLI::Validator finite_within(double lo, double hi) {
  std::ostringstream range;
  range << "[" << lo << " - " << hi << "]";
  return CLI::Validator(
      [lo, hi, text = range.str()](std::string& value) {
        double v = 0;
        if (!CLI::detail::lexical_cast(value, v) || !(v >= lo && v <= hi))
          return "a number in " + text + ", got '" + value + "'";
        return std::string();
      },
      "FLOAT in " + range.str());
}

}  // namespace

int main(int argc, char** argv) {
  keep_large_blocks_out_of_the_heaps();
  CLI::App app{"tinyphong-server: the emulated device, live in a browser"};
  tp::server::ServerOptions opt;
#ifdef TP_HAVE_DEVICE
  std::string source = "device";
#else
  std::string source = "pattern";
#endif
  std::string scene = "teapot", scenes_dir, method = "kb-adaptive";
#ifdef TP_SCENES_DIR
  scenes_dir = TP_SCENES_DIR;
#endif
  double max_fps = 60, deadline_s = 5;
  int width = 0, height = 0;
  app.add_option("--bind", opt.bind, "address to listen on")->capture_default_str();
  app.add_option(
      "--allow-host", opt.allow_hosts,
      "extra host name accepted in Host/Origin (besides 127.0.0.1, localhost, [::1], --bind)");
  app.add_option("--port", opt.port, "TCP port (0 = pick a free one)")
      ->transform(tp::host::whole_number(0, 65535))
      ->capture_default_str();
  app.add_option("--scene", scene, "scene name (scenes/<name>.json)")->capture_default_str();
  app.add_option("--scenes-dir", scenes_dir, "directory of the shipped scenes")
      ->capture_default_str();
  app.add_option("--method", method, "shading method to start with (empty: the scene file's)")
      ->capture_default_str();
  app.add_option("--source", source, "frame source: device or pattern (transport tests)")
      ->check(CLI::IsMember({"device", "pattern"}))
      ->capture_default_str();
  app.add_option("--width", width, "initial width (default: the scene's)")
      ->transform(tp::host::whole_number(16, 2048));
  app.add_option("--height", height, "initial height (default: the scene's)")
      ->transform(tp::host::whole_number(16, 2048));
  app.add_option("--max-fps", max_fps, "render-loop pacing cap")
      ->check(finite_within(1.0, 1000.0))
      ->capture_default_str();
  app.add_option("--deadline", deadline_s,
                 "seconds a client may leave a write or a frame unacknowledged")
      ->check(finite_within(0.2, 600.0))
      ->capture_default_str();
  app.add_option("--io-threads", opt.io_threads, "I/O threads")
      ->transform(tp::host::whole_number(1, 16))
      ->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // CLI11's own codes (104 to 114) for a bad option, as the tinyphong CLI: 2; 0 for --help.
    return app.exit(e) == 0 ? 0 : 2;
  }
  opt.loop.max_fps = max_fps;
  opt.limits.deadline = std::chrono::milliseconds(static_cast<long>(deadline_s * 1000));

  std::unique_ptr<tp::server::FrameSource> src;
  try {
    if (source == "device") {
#ifdef TP_HAVE_DEVICE
      src = std::make_unique<tp::server::DeviceSource>(scenes_dir, scene, width, height, method);
#else
      throw std::runtime_error("built without the device (host driver missing)");
#endif
    } else {
      auto p = std::make_unique<tp::server::PatternSource>();
      auto s = p->settings();
      if (width) s.width = width;
      if (height) s.height = height;
      // Only a method it does not know is refused, and this is its own default.
      if (auto r = p->apply(s); !r.ok()) throw std::runtime_error(r.message());
      src = std::move(p);
    }
    tp::server::Server server(opt, std::move(src));
    std::cout << "tinyphong: serving " << server.url() << std::endl;
    return server.run();
  } catch (const std::exception& e) {
    std::cerr << "tinyphong-server: " << e.what() << "\n";
    return 1;
  }
}
