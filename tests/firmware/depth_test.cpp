// Depth test and clear: nearer wins in either drawing order, equal depth keeps the first
// (strictly-less test), the depth word mapping, and that a depth-tested sphere with culling off
// gives the same image as culling on. Without a depth buffer (ViewportCmd::depth_buffer false):
// the block needs one row of depth words, the test passes every pixel, and the image is the
// depth-test-off image.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "helpers.hpp"

namespace tp::fw::test {
namespace {

Mesh two_quads(double z_first, double z_second) {
  Mesh m;
  for (double z : {z_first, z_second})
    for (glm::dvec3 p : {glm::dvec3(-0.8, -0.8, z), glm::dvec3(0.8, -0.8, z),
                         glm::dvec3(0.8, 0.8, z), glm::dvec3(-0.8, 0.8, z)}) {
      m.positions.push_back(p);
      m.normals.push_back({0, 0, 1});
    }
  for (std::uint32_t b : {0u, 4u})
    m.indices.insert(m.indices.end(), {b, b + 1, b + 2, b, b + 2, b + 3});
  return m;
}

// Draws the first quad in colour A (material colour), the second in colour B.
Rgb8 centre_after(double z_first, double z_second, bool depth_buffer = true,
                  bool depth_test = true) {
  Rig rig(32, 32);
  auto& d = rig.dev;
  EXPECT_EQ(d.set_viewport(ViewportCmd{32, 32, PixelFormat::kRgb888, true, depth_buffer}),
            Error::kOk);
  EXPECT_EQ(d.set_depth_test(depth_test), Error::kOk);
  const Mesh m = two_quads(z_first, z_second);
  EXPECT_EQ(d.set_method(Method::kFlat), Error::kOk);
  LightCmd l;
  l.index = 0;
  l.type = LightType::kDirectional;
  l.color[0] = l.color[1] = l.color[2] = q16(1);
  l.direction = Vec3u{q30(0), q30(0), q30(1)};
  EXPECT_EQ(d.set_light(l), Error::kOk);
  EXPECT_EQ(d.clear(Rgb8{0, 0, 0}), Error::kOk);
  EXPECT_EQ(rig.load(m), Error::kOk);
  MaterialCmd a;
  a.color[0] = q30(1);
  a.color[1] = a.color[2] = q30(0);
  a.kd = q30(1);
  EXPECT_EQ(d.set_material(a), Error::kOk);
  EXPECT_EQ(d.draw(DrawCmd{0, 6}), Error::kOk);
  MaterialCmd b = a;
  b.color[0] = q30(0);
  b.color[2] = q30(1);
  EXPECT_EQ(d.set_material(b), Error::kOk);
  EXPECT_EQ(d.draw(DrawCmd{6, 6}), Error::kOk);
  return rig.pixel(16, 16);
}

TEST(Depth, NearerWinsInEitherOrder) {
  // Identity projection: NDC z = model z, smaller is nearer.
  EXPECT_EQ(centre_after(-0.5, 0.5).r, 255);   // first is nearer: stays red
  EXPECT_EQ(centre_after(0.5, -0.5).b, 255);   // second is nearer: becomes blue
  EXPECT_EQ(centre_after(0.25, 0.25).r, 255);  // equal depth: strictly-less keeps the first
}

TEST(Depth, WordMappingAndClear) {
  Rig rig(8, 8);
  auto& d = rig.dev;
  Mesh m = two_quads(0.0, 0.0);
  m.indices.resize(6);
  ASSERT_EQ(d.clear(Rgb8{10, 20, 30}), Error::kOk);
  EXPECT_EQ(d.depth_buffer()[0], 0xffffffffu);
  EXPECT_EQ(rig.pixel(0, 0).g, 20);
  ASSERT_EQ(rig.load(m), Error::kOk);
  ASSERT_EQ(rig.draw_all(m), Error::kOk);
  EXPECT_EQ(d.depth_buffer()[4 * 8 + 4], 1u << 31);  // NDC z = 0 -> 2^31
  EXPECT_EQ(rig.count(4, 4), 1);
  EXPECT_EQ(rig.pixel(0, 0).g, 20);  // outside the quad: the clear colour stays
  ASSERT_EQ(d.clear(Rgb8{0, 0, 0}), Error::kOk);
  EXPECT_EQ(rig.count(4, 4), 0);
  EXPECT_EQ(d.counters().pixels_written, 0u);
}

TEST(Depth, DepthTestedSphereWithoutCullingEqualsCulled) {
  const Mesh m = octasphere(3);
  std::vector<std::uint8_t> images[2];
  for (int cull = 0; cull < 2; ++cull) {
    Rig rig(80, 64);
    auto& d = rig.dev;
    ASSERT_EQ(d.set_projection(to_mat4(glm::perspective(0.9, 80.0 / 64.0, 1.0, 10.0))), Error::kOk);
    ASSERT_EQ(d.set_modelview(to_mat4(glm::translate(glm::dmat4(1), glm::dvec3(0.2, 0.1, -3.5)))),
              Error::kOk);
    ASSERT_EQ(d.set_culling(cull == 1), Error::kOk);
    ASSERT_EQ(d.set_method(Method::kGouraud), Error::kOk);
    LightCmd l;
    l.index = 0;
    l.type = LightType::kPoint;
    l.color[0] = l.color[1] = l.color[2] = q16(1);
    l.position = Vec3q16{q16(2), q16(2), q16(0)};
    ASSERT_EQ(d.set_light(l), Error::kOk);
    ASSERT_EQ(d.clear(Rgb8{0, 0, 0}), Error::kOk);
    ASSERT_EQ(rig.load(m), Error::kOk);
    ASSERT_EQ(rig.draw_all(m), Error::kOk);
    const FramebufferView fb = d.framebuffer();
    images[cull].assign(fb.data, fb.data + fb.stride * fb.height);
    if (cull == 0) {
      EXPECT_EQ(d.counters().triangles_culled, 0u);
    } else {
      EXPECT_GT(d.counters().triangles_culled, 200u);
    }
  }
  EXPECT_TRUE(images[0] == images[1]);
}

}  // namespace
}  // namespace tp::fw::test

namespace tp::fw::test {
namespace {

// Two quads at depths z_near (x in [-0.8, 0.0]) and z_far (x in [-0.8, 0.8]) of the same height:
// the near one hides the left half of every span of the far one.
Mesh near_and_far_quads(double z_near, double z_far) {
  Mesh m;
  const double right[2] = {0.0, 0.8};
  const double z[2] = {z_near, z_far};
  for (int q = 0; q < 2; ++q)
    for (glm::dvec3 p : {glm::dvec3(-0.8, -0.8, z[q]), glm::dvec3(right[q], -0.8, z[q]),
                         glm::dvec3(right[q], 0.8, z[q]), glm::dvec3(-0.8, 0.8, z[q])}) {
      m.positions.push_back(p);
      m.normals.push_back({0, 0, 1});
    }
  for (std::uint32_t b : {0u, 4u})
    m.indices.insert(m.indices.end(), {b, b + 1, b + 2, b, b + 2, b + 3});
  return m;
}

struct DrawCounts {
  std::uint64_t spans, spans_hidden, shaded, written;
};

DrawCounts counts_of_draw(Rig& rig, DrawCmd draw) {
  const Counters before = rig.dev.counters();
  EXPECT_EQ(rig.dev.draw(draw), Error::kOk);
  const Counters& after = rig.dev.counters();
  return {after.spans - before.spans, after.spans_hidden - before.spans_hidden,
          after.pixels_shaded - before.pixels_shaded, after.pixels_written - before.pixels_written};
}

// Early depth (draw.cpp, PixelWriter::visible_part): a method that declares kSkipsHiddenPixels is
// asked for the visible part of a span only and not at all for a hidden span; the others shade
// every pixel. The image is the same either way (docs/DECISIONS.md, "Early depth").
TEST(EarlyDepth, HiddenSpansAndEndsAreNotShaded) {
  for (const Method method : kImplementedMethods) {
    SCOPED_TRACE(static_cast<int>(method));
    const bool early = method == Method::kPhong || method == Method::kDuff ||
                       method == Method::kKuijkBlakeAdaptive ||
                       method == Method::kKuijkBlakeAdaptiveNoSkip ||
                       method == Method::kKuijkBlakeAdaptiveExact;
    Rig rig(32, 32);
    ASSERT_EQ(rig.dev.set_method(method), Error::kOk);
    LightCmd l;
    l.index = 0;
    l.type = LightType::kDirectional;
    l.color[0] = l.color[1] = l.color[2] = q16(1);
    l.direction = Vec3u{q30(0), q30(0), q30(1)};
    ASSERT_EQ(rig.dev.set_light(l), Error::kOk);
    MaterialCmd mat;
    mat.color[0] = mat.color[1] = mat.color[2] = q30(0.5);
    mat.kd = q30(0.6);
    mat.ks = q30(0.4);
    mat.n = 20;
    ASSERT_EQ(rig.dev.set_material(mat), Error::kOk);
    ASSERT_EQ(rig.dev.clear(Rgb8{0, 0, 0}), Error::kOk);
    const Mesh m = near_and_far_quads(-0.5, 0.5);
    ASSERT_EQ(rig.load(m), Error::kOk);
    const DrawCounts near = counts_of_draw(rig, DrawCmd{0, 6});
    EXPECT_EQ(near.spans_hidden, 0u);
    EXPECT_EQ(near.shaded, near.written);  // nothing was there yet
    const FramebufferView fb = rig.dev.framebuffer();
    const std::vector<std::uint8_t> image(fb.data, fb.data + fb.stride * 32);
    // The far quad again over the near one's pixels only (its left half): every span hidden.
    Mesh hidden = near_and_far_quads(-0.5, 0.5);
    for (int i = 4; i < 8; ++i) hidden.positions[i].x = std::min(hidden.positions[i].x, 0.0);
    ASSERT_EQ(rig.load(hidden), Error::kOk);
    const DrawCounts all_hidden = counts_of_draw(rig, DrawCmd{6, 6});
    EXPECT_EQ(all_hidden.written, 0u);
    EXPECT_GT(all_hidden.spans, 0u);
    EXPECT_EQ(all_hidden.spans_hidden, early ? all_hidden.spans : 0u);
    EXPECT_EQ(all_hidden.shaded, early ? 0u : near.written);
    EXPECT_TRUE(std::equal(image.begin(), image.end(), rig.dev.framebuffer().data));
    // The whole far quad: the left half of each span hidden, the right half written.
    ASSERT_EQ(rig.load(m), Error::kOk);
    const DrawCounts half = counts_of_draw(rig, DrawCmd{6, 6});
    EXPECT_GT(half.written, 0u);
    // The quad's upper-left triangle has rows wholly left of x = 0.
    EXPECT_EQ(half.spans_hidden > 0, early);
    if (early)
      EXPECT_EQ(half.shaded, half.written);
    else
      EXPECT_EQ(half.shaded, half.written + near.written);
  }
}

TEST(Depth, WithoutABufferEveryPixelPasses) {
  // The later quad wins whatever its depth, as with the test off.
  EXPECT_EQ(centre_after(-0.5, 0.5, false).b, 255);
  EXPECT_EQ(centre_after(0.5, -0.5, false).b, 255);
  EXPECT_EQ(centre_after(0.25, 0.25, false).b, 255);
  EXPECT_EQ(centre_after(-0.5, 0.5, true, false).b, 255);
}

TEST(Depth, WithoutABufferTheBlockHoldsOneRow) {
  const BufferCapacityCmd cap{64, 192};
  const ViewportCmd with{40, 30, PixelFormat::kRgb565, false, true};
  const ViewportCmd without{40, 30, PixelFormat::kRgb565, false, false};
  const std::size_t a = Device::memory_required(with, cap, Method::kGouraud);
  const std::size_t b = Device::memory_required(without, cap, Method::kGouraud);
  EXPECT_EQ(a - b, (40u * 30u - 40u) * sizeof(std::uint32_t));  // both multiples of 8
  // A block of exactly that size takes the viewport without depth and refuses the one with it,
  // changing nothing.
  std::vector<std::byte> memory(b);
  Device d(memory);
  ASSERT_EQ(d.set_buffer_capacity(cap), Error::kOk);
  ASSERT_EQ(d.set_method(Method::kGouraud), Error::kOk);
  ASSERT_EQ(d.set_viewport(without), Error::kOk);
  EXPECT_EQ(d.depth_buffer(), nullptr);
  EXPECT_EQ(d.set_viewport(with), Error::kOutOfMemory);
  EXPECT_FALSE(d.state().viewport.depth_buffer);
  EXPECT_EQ(d.depth_buffer(), nullptr);
}

// A closed convex mesh with back faces culled covers each pixel once: the depth buffer changes
// nothing, byte for byte.
TEST(Depth, ConvexMeshIsTheSameWithoutABuffer) {
  const Mesh m = octasphere(3);
  std::vector<std::uint8_t> images[2];
  for (const bool depth : {true, false}) {
    Rig rig(64, 48);
    auto& d = rig.dev;
    ASSERT_EQ(d.set_viewport(ViewportCmd{64, 48, PixelFormat::kRgb888, true, depth}), Error::kOk);
    ASSERT_EQ(d.set_projection(to_mat4(glm::perspective(1.0, 64.0 / 48.0, 0.5, 10.0))), Error::kOk);
    ASSERT_EQ(d.set_modelview(to_mat4(glm::translate(glm::dmat4(1), glm::dvec3(0, 0, -3)))),
              Error::kOk);
    LightCmd l;
    l.type = LightType::kDirectional;
    l.color[0] = l.color[1] = l.color[2] = q16(1);
    l.direction = Vec3u{q30(0), q30(0.6), q30(0.8)};
    ASSERT_EQ(d.set_light(l), Error::kOk);
    MaterialCmd mat;
    mat.color[0] = mat.color[1] = mat.color[2] = q30(0.8);
    mat.kd = q30(0.7);
    mat.ks = q30(0.3);
    mat.n = 20;
    ASSERT_EQ(d.set_material(mat), Error::kOk);
    ASSERT_EQ(d.set_method(Method::kPhong), Error::kOk);
    ASSERT_EQ(d.clear(Rgb8{0, 0, 0}), Error::kOk);
    ASSERT_EQ(rig.load(m), Error::kOk);
    ASSERT_EQ(rig.draw_all(m), Error::kOk);
    const FramebufferView fb = d.framebuffer();
    images[depth ? 0 : 1].assign(fb.data, fb.data + std::size_t{fb.stride} * fb.height);
    EXPECT_GT(d.counters().pixels_written, 500u);
  }
  EXPECT_EQ(images[0], images[1]);
}

}  // namespace
}  // namespace tp::fw::test
