// The server's device source: the specular-only view renders the specular part alone for the
// device and the reference, keeps the material the user set, and survives a scene change; it
// offers only the scenes a client can select, and refuses a scene file that is no longer one.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "server/device_source.hpp"

namespace tp::server {
namespace {

// Sum of all channels, and whether every channel of a is at most b's.
struct Compared {
  long long sum_a = 0, sum_b = 0;
  bool a_at_most_b = true;
};
Compared compare(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  Compared c;
  EXPECT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    c.sum_a += a[i];
    c.sum_b += b[i];
    c.a_at_most_b = c.a_at_most_b && a[i] <= b[i];
  }
  return c;
}

// With ka = kd = 0 only non-negative specular terms remain, so every channel of the specular-only
// frame is at most the full frame's (the clamp at 1 keeps that), and the frame is darker. The
// same holds for the double reference, rendered from the same settings.
TEST(DeviceSource, SpecularOnlyRendersTheSpecularPartAlone) {
  DeviceSource src(TP_SCENES_DIR, "sphere-32", 96, 96, "quadratic");
  const RenderedFrame full = src.render(0.0);
  const Image full_ref = src.reference_task(0.0)();
  ViewSettings s = src.settings();
  const double ka = s.ka, kd = s.kd;
  ASSERT_GT(ka, 0);
  ASSERT_GT(kd, 0);
  s.specular_only = true;
  ASSERT_TRUE(src.apply(s).ok());
  EXPECT_TRUE(src.settings().specular_only);
  EXPECT_EQ(src.settings().ka, ka);  // the user's material, kept for when the view is left
  EXPECT_EQ(src.settings().kd, kd);
  const RenderedFrame spec = src.render(0.0);
  const Compared d = compare(spec.image.rgb, full.image.rgb);
  EXPECT_TRUE(d.a_at_most_b);
  EXPECT_LT(2 * d.sum_a, d.sum_b);
  EXPECT_GT(d.sum_a, 0);  // the highlight is there
  const Compared r = compare(src.reference_task(0.0)().rgb, full_ref.rgb);
  EXPECT_TRUE(r.a_at_most_b);
  EXPECT_LT(2 * r.sum_a, r.sum_b);

  // A scene change keeps the view; leaving it gives the full frame back, byte for byte.
  ASSERT_TRUE(src.load_scene("triangle").ok());
  EXPECT_TRUE(src.settings().specular_only);
  ASSERT_TRUE(src.load_scene("sphere-32").ok());
  s = src.settings();
  s.width = s.height = 96;
  s.method = "quadratic";
  ASSERT_TRUE(src.apply(s).ok());
  EXPECT_EQ(src.render(0.0).image.rgb, spec.image.rgb);
  s.specular_only = false;
  ASSERT_TRUE(src.apply(s).ok());
  EXPECT_EQ(src.render(0.0).image.rgb, full.image.rgb);
}

// A scenes folder of the test's own, removed however the test ends.
struct TempFolder {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("tp-scenes-" + std::to_string(::getpid()));
  TempFolder() {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempFolder() { std::filesystem::remove_all(path); }
};

// Found by review, 2026-12-07: the page was offered a scene whose name is longer than set_scene
// takes (64 bytes) or not UTF-8, which the server then refused; and a scene file replaced by a
// FIFO blocked the render loop in its read, every client and the server's stop with it.
TEST(DeviceSource, OffersOnlySelectableScenesAndReadsOnlyRegularFiles) {
  namespace fs = std::filesystem;
  const TempFolder folder;
  const fs::path& dir = folder.path;
  for (const std::string name : {"triangle", "sphere-32"})
    fs::copy_file(fs::path(TP_SCENES_DIR) / (name + ".json"), dir / (name + ".json"));
  const std::string long_name(65, 'a'), not_utf8 = "bad\xff";
  fs::copy_file(dir / "triangle.json", dir / (long_name + ".json"));
  fs::copy_file(dir / "triangle.json", dir / (not_utf8 + ".json"));
  fs::copy_file(dir / "triangle.json", dir / (std::string(64, 'b') + ".json"));

  DeviceSource src(dir, "triangle", 32, 32, "gouraud");
  const std::vector<std::string> offered = src.scenes();
  EXPECT_EQ(offered, (std::vector<std::string>{std::string(64, 'b'), "sphere-32", "triangle"}));

  const fs::path fifo = dir / "sphere-32.json";
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // Should the load block on the FIFO after all, a writer opened and closed after a while ends
  // it with an empty file, so that the test fails on the message instead of hanging.
  std::thread unblock([&fifo] {
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    if (const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK); fd >= 0) ::close(fd);
  });
  const Result r = src.load_scene("sphere-32");
  unblock.join();
  EXPECT_FALSE(r.ok());
  EXPECT_NE(r.message().find("not a regular file (a FIFO, a device or a folder)"),
            std::string::npos)
      << r.message();
  EXPECT_TRUE(src.load_scene("triangle").ok());
}

}  // namespace
}  // namespace tp::server
