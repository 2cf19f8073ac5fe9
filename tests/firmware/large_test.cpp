// The largest framebuffer (kMaxDimension x kMaxDimension = 4096 x 4096): coverage stays exact
// and no intermediate overflows (the sanitize build turns any signed overflow into a failure)
// with vertices at the edge of the guard band, where coordinates are largest (raster.hpp).
#include <gtest/gtest.h>

#include "helpers.hpp"

namespace tp::fw::test {
namespace {

constexpr std::uint32_t kN = kMaxDimension;

// A grid of (cols x rows) quads over [-extent, extent]^2 in NDC, two triangles each, CCW.
Mesh grid(int cols, int rows, double extent, double z_tilt) {
  Mesh m;
  for (int j = 0; j <= rows; ++j)
    for (int i = 0; i <= cols; ++i) {
      const double x = -extent + 2 * extent * i / cols, y = -extent + 2 * extent * j / rows;
      m.positions.push_back({x, y, z_tilt * (x - y) / extent});
      m.normals.push_back(glm::normalize(glm::dvec3(0.3 * x / extent, 0.2 * y / extent, 1)));
    }
  const auto at = [&](int i, int j) { return static_cast<std::uint32_t>(j * (cols + 1) + i); };
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i)
      m.indices.insert(m.indices.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j),
                                         at(i + 1, j + 1), at(i, j + 1)});
  return m;
}

void render_and_expect_every_pixel_once(Rig& rig, const Mesh& m, Method method) {
  auto& d = rig.dev;
  ASSERT_EQ(d.set_depth_test(false), Error::kOk);
  ASSERT_EQ(d.set_method(method), Error::kOk);
  LightCmd l;
  l.index = 0;
  l.type = LightType::kPoint;
  l.color[0] = l.color[1] = l.color[2] = q16(16);  // the largest intensity: saturating sums
  l.position = Vec3q16{q16(0.2), q16(0.3), q16(0.5)};
  ASSERT_EQ(d.set_light(l), Error::kOk);
  ASSERT_EQ(d.clear(Rgb8{0, 0, 0}), Error::kOk);
  ASSERT_EQ(rig.load(m), Error::kOk);
  ASSERT_EQ(rig.draw_all(m), Error::kOk);
  const std::uint8_t* counts = d.write_counts();
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < std::size_t{kN} * kN; ++i) wrong += counts[i] != 1 ? 1 : 0;
  EXPECT_EQ(wrong, 0u);
  EXPECT_EQ(d.counters().pixels_written, std::uint64_t{kN} * kN);
}

TEST(Largest, FineGridCoversEveryPixelOnce) {
  Rig rig(kN, kN, 2048, 6 * 1024);
  render_and_expect_every_pixel_once(rig, grid(31, 29, 1.3, 0.5), Method::kGouraud);
}

TEST(Largest, VerticesAtTheGuardBandCoverEveryPixelOnce) {
  // |NDC| = 63 < 64: the largest coordinates that reach the rasterizer unclipped; the second
  // grid goes past the guard band, so its triangles are clipped.
  Rig rig(kN, kN, 2048, 6 * 1024);
  render_and_expect_every_pixel_once(rig, grid(3, 5, 63.0, 0.5), Method::kFlat);
  render_and_expect_every_pixel_once(rig, grid(4, 4, 200.0, 0.5), Method::kGouraud);
  EXPECT_GT(rig.dev.counters().triangles_clipped, 0u);
}

}  // namespace
}  // namespace tp::fw::test
