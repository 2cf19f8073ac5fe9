// Coverage: every pixel inside a closed mesh's silhouette is written exactly once (top-left
// rule, no cracks, no double writes); clipping of vertices behind the eye; degenerate input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "firmware/interp.hpp"
#include "helpers.hpp"

namespace tp::fw::test {
namespace {

using P2 = glm::dvec2;

double cross2(P2 o, P2 a, P2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

// Andrew's monotone chain; counter-clockwise hull.
std::vector<P2> hull(std::vector<P2> p) {
  std::sort(p.begin(), p.end(), [](P2 a, P2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  std::vector<P2> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross2(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross2(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  return h;
}

// Signed distance (pixels) of q inside a CCW convex polygon: > 0 inside.
double inside_distance(const std::vector<P2>& poly, P2 q) {
  double d = 1e300;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const P2 a = poly[i], b = poly[(i + 1) % poly.size()];
    d = std::min(d, cross2(a, b, q) / glm::length(b - a));
  }
  return d;
}

// Screen position (pixels, y down) of a model point, in double.
P2 to_screen(const glm::dmat4& pmv, glm::dvec3 p, double w, double h) {
  const glm::dvec4 c = pmv * glm::dvec4(p, 1.0);
  return P2{(c.x / c.w + 1) / 2 * w, (1 - c.y / c.w) / 2 * h};
}

// Snapping moves vertices by <= 1/32 pixel: pixels further than this from the outline are
// classified for sure.
constexpr double kMargin = 0.05;

struct CoverResult {
  int inside_bad = 0, outside_bad = 0, inside = 0;
};

// Renders the mesh with depth test off and checks each pixel's write count against the
// silhouette (convex hull of the projected vertices; the meshes here are convex).
CoverResult check_convex_cover(Rig& rig, const Mesh& m, const glm::dmat4& mv,
                               const glm::dmat4& proj, bool cull, int expected_inside) {
  auto& d = rig.dev;
  const auto w = d.state().viewport.width, h = d.state().viewport.height;
  EXPECT_EQ(d.set_modelview(to_mat4(mv)), Error::kOk);
  EXPECT_EQ(d.set_projection(to_mat4(proj)), Error::kOk);
  EXPECT_EQ(d.set_culling(cull), Error::kOk);
  EXPECT_EQ(d.set_depth_test(false), Error::kOk);
  EXPECT_EQ(d.set_method(Method::kFlat), Error::kOk);
  EXPECT_EQ(d.clear(Rgb8{0, 0, 0}), Error::kOk);
  EXPECT_EQ(rig.load(m), Error::kOk);
  EXPECT_EQ(rig.draw_all(m), Error::kOk);
  std::vector<P2> pts;
  for (const auto& p : m.positions) pts.push_back(to_screen(proj * mv, p, w, h));
  const std::vector<P2> sil = hull(pts);
  CoverResult r;
  for (std::uint32_t y = 0; y < h; ++y)
    for (std::uint32_t x = 0; x < w; ++x) {
      const double dist = inside_distance(sil, P2{x + 0.5, y + 0.5});
      const int c = rig.count(x, y);
      if (dist > kMargin) {
        ++r.inside;
        if (c != expected_inside) ++r.inside_bad;
      } else if (dist < -kMargin) {
        if (c != 0) ++r.outside_bad;
      } else if (c != 0 && c != expected_inside) {
        ++r.inside_bad;  // on the outline: either state is fine, a double write is not
      }
    }
  return r;
}

TEST(Cover, SphereEveryInteriorPixelOnceWithCulling) {
  Rig rig(160, 120);
  const Mesh m = octasphere(3);  // 512 triangles
  const glm::dmat4 proj = glm::ortho(-1.6, 1.6, -1.2, 1.2, -10.0, 10.0);
  for (int rot = 0; rot < 8; ++rot) {
    const glm::dmat4 mv =
        glm::rotate(glm::dmat4(1), 0.37 * rot, glm::normalize(glm::dvec3(1, 2, 0.5)));
    const CoverResult r = check_convex_cover(rig, m, mv, proj, true, 1);
    EXPECT_GT(r.inside, 5000);
    EXPECT_EQ(r.inside_bad, 0) << "rotation " << rot;
    EXPECT_EQ(r.outside_bad, 0) << "rotation " << rot;
  }
}

TEST(Cover, SphereFrontAndBackTwiceWithoutCulling) {
  Rig rig(160, 120);
  const Mesh m = octasphere(2);
  const glm::dmat4 proj = glm::perspective(0.8, 160.0 / 120.0, 0.5, 20.0);
  const glm::dmat4 mv = glm::translate(glm::dmat4(1), glm::dvec3(0.3, -0.2, -4.0));
  const CoverResult r = check_convex_cover(rig, m, mv, proj, false, 2);
  EXPECT_GT(r.inside, 3000);
  EXPECT_EQ(r.inside_bad, 0);
  EXPECT_EQ(r.outside_bad, 0);
}

TEST(Cover, SphereStraddlingScreenEdgesAndGuardBand) {
  // Centred on a corner, and large enough that vertices leave the 3w guard band: guard-band
  // clipping (|x| > 64 w) must not open cracks inside the screen.
  Rig rig(128, 96);
  const Mesh m = octasphere(3);
  const glm::dmat4 proj = glm::ortho(-1.0, 1.0, -0.75, 0.75, -1000.0, 1000.0);
  for (double scale : {1.0, 5.0, 150.0}) {
    const glm::dmat4 mv =
        glm::scale(glm::translate(glm::dmat4(1), glm::dvec3(0.9, 0.7, 0.0)), glm::dvec3(scale)) *
        glm::rotate(glm::dmat4(1), 0.3, glm::dvec3(0, 1, 0));
    const CoverResult r = check_convex_cover(rig, m, mv, proj, true, 1);
    EXPECT_GT(r.inside, 1000);
    EXPECT_EQ(r.inside_bad, 0) << "scale " << scale;
    EXPECT_EQ(r.outside_bad, 0) << "scale " << scale;
    if (scale > 100) {
      EXPECT_GT(rig.dev.counters().triangles_clipped, 0u);
    }
  }
}

// A star-shaped polygon around a centre, drawn as a fan with slivers and zero-area pieces.
// Vertices are generated on the 1/16-pixel grid (so the device's snapping is exact and the
// fan's orientation is known exactly): every piece has cross >= 0, slivers have a width of
// one subpixel, zero-area pieces have cross == 0.
TEST(Cover, RandomFansWithSliversAndZeroArea) {
  const int W = 97, H = 83;  // odd sizes on purpose
  Rig rig(W, H);
  std::mt19937 rng(1234);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  using I2 = glm::i64vec2;
  const auto cross = [](I2 a, I2 b) { return a.x * b.y - a.y * b.x; };
  std::uint64_t guard_clipped = 0;
  for (int trial = 0; trial < 60; ++trial) {
    const I2 c{static_cast<long>(16 * W * (0.2 + 0.6 * u(rng))),
               static_cast<long>(16 * H * (0.2 + 0.6 * u(rng)))};
    std::vector<double> angles;
    for (int i = 0; i < 3; ++i) angles.push_back(0.1 + i * 2 * M_PI / 3);  // every gap < pi
    const int n = static_cast<int>(u(rng) * 40);
    for (int i = 0; i < n; ++i) angles.push_back(u(rng) * 2 * M_PI);
    std::sort(angles.begin(), angles.end());
    std::vector<I2> rim;  // offsets from c, in angular order (y down: increasing angle is CW)
    for (double a : angles) {
      // Rims leave the screen; every third trial they also leave the 64 w guard band (3000 px).
      const double r = 16 * (10 + (trial % 3 == 0 ? 1500 : 80) * u(rng));
      const I2 p{std::llround(r * std::cos(a)), std::llround(r * std::sin(a))};
      if (!rim.empty() && cross(rim.back(), p) <= 0) continue;  // rounding reordered: drop
      rim.push_back(p);
      if (u(rng) < 0.3) {  // a zero-area piece along the same ray, then a sliver
        rim.push_back(p * std::int64_t{3});
        const I2 d =
            std::abs(p.x) > std::abs(p.y) ? I2{0, p.x > 0 ? 1 : -1} : I2{p.y > 0 ? -1 : 1, 0};
        rim.push_back(p * std::int64_t{2} + d);
      }
    }
    while (rim.size() > 3 && cross(rim.back(), rim.front()) <= 0) rim.pop_back();
    Mesh m;
    const auto to_ndc = [&](I2 s) {
      return glm::dvec3(s.x / (8.0 * W) - 1, 1 - s.y / (8.0 * H), 0);
    };
    m.positions.push_back(to_ndc(c));
    for (const I2& p : rim) m.positions.push_back(to_ndc(c + p));
    m.normals.assign(m.positions.size(), {0, 0, 1});
    const auto k = static_cast<std::uint32_t>(rim.size());
    for (std::uint32_t i = 0; i < k; ++i)
      m.indices.insert(m.indices.end(), {0u, 1 + i, 1 + (i + 1) % k});
    auto& d = rig.dev;
    ASSERT_EQ(d.set_modelview(to_mat4(glm::dmat4(1))), Error::kOk);
    ASSERT_EQ(d.set_projection(to_mat4(glm::dmat4(1))), Error::kOk);
    ASSERT_EQ(d.set_culling(false), Error::kOk);
    ASSERT_EQ(d.set_depth_test(false), Error::kOk);
    ASSERT_EQ(d.clear(Rgb8{0, 0, 0}), Error::kOk);
    ASSERT_EQ(rig.load(m), Error::kOk);
    ASSERT_EQ(rig.draw_all(m), Error::kOk);
    // Classify pixel centres against the star polygon in exact subpixel integers.
    int bad = 0, inside = 0;
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const I2 q{16 * x + 8 - c.x, 16 * y + 8 - c.y};
        bool strictly_inside = false, on_edge = false;
        for (std::uint32_t i = 0; i < k; ++i) {
          const I2 a = rim[i], b = rim[(i + 1) % k];
          if (cross(a, b) == 0) continue;
          const std::int64_t e0 = cross(a, q), e1 = cross(b - a, q - a), e2 = cross(-b, q - b);
          if (e0 > 0 && e1 > 0 && e2 > 0) strictly_inside = true;
          if (e0 >= 0 && e1 >= 0 && e2 >= 0 && (e0 == 0 || e1 == 0 || e2 == 0)) on_edge = true;
        }
        const int cnt = rig.count(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y));
        const bool ok =
            cnt <= 1 && (!strictly_inside || cnt == 1) && (strictly_inside || on_edge || cnt == 0);
        if (!ok) {
          ++bad;
          ADD_FAILURE() << "pixel " << x << "," << y << " count " << cnt;
        }
        inside += strictly_inside ? 1 : 0;
      }
    EXPECT_EQ(bad, 0) << "trial " << trial;
    EXPECT_GT(inside, 0);
    guard_clipped += d.counters().triangles_clipped;
  }
  EXPECT_GT(guard_clipped, 10u);  // the far rims did exercise guard-band clipping
}

// A ground plane from behind the eye (w < 0) to far ahead: the visible part must render.
TEST(Clip, GroundPlaneThroughTheEye) {
  const std::uint32_t W = 120, H = 90;
  Rig rig(W, H);
  Mesh m;
  for (glm::dvec3 p : {glm::dvec3(-100, -1, 10), glm::dvec3(100, -1, 10), glm::dvec3(100, -1, -100),
                       glm::dvec3(-100, -1, -100)}) {
    m.positions.push_back(p);
    m.normals.push_back({0, 1, 0});
  }
  m.indices = {0, 1, 2, 0, 2, 3};  // CCW seen from above
  auto& d = rig.dev;
  ASSERT_EQ(d.set_modelview(to_mat4(glm::dmat4(1))), Error::kOk);
  ASSERT_EQ(d.set_projection(to_mat4(glm::perspective(M_PI / 2, double(W) / H, 0.1, 200.0))),
            Error::kOk);
  ASSERT_EQ(d.set_depth_test(false), Error::kOk);
  ASSERT_EQ(d.set_method(Method::kFlat), Error::kOk);
  ASSERT_EQ(d.clear(Rgb8{0, 0, 0}), Error::kOk);
  ASSERT_EQ(rig.load(m), Error::kOk);
  ASSERT_EQ(rig.draw_all(m), Error::kOk);
  EXPECT_EQ(d.counters().triangles_clipped, 2u);
  EXPECT_EQ(d.counters().triangles_culled, 0u);
  // Far edge at z = -100 projects to y_ndc = -0.01, i.e. screen row 0.505 H; the horizon is 0.5 H.
  for (std::uint32_t y = 0; y < H; ++y)
    for (std::uint32_t x = 0; x < W; ++x) {
      const double yc = y + 0.5;
      if (yc > 0.505 * H + kMargin) {
        EXPECT_EQ(rig.count(x, y), 1) << x << "," << y;
      } else if (yc < 0.505 * H - kMargin) {
        EXPECT_EQ(rig.count(x, y), 0) << x << "," << y;
      }
    }
}

TEST(Clip, TriangleEntirelyBehindTheEyeDrawsNothing) {
  Rig rig(64, 64);
  Mesh m;
  m.positions = {{-1, -1, 1}, {1, -1, 1}, {0, 1, 1}};
  m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  m.indices = {0, 1, 2};
  auto& d = rig.dev;
  ASSERT_EQ(d.set_projection(to_mat4(glm::perspective(1.0, 1.0, 0.1, 10.0))), Error::kOk);
  ASSERT_EQ(d.set_culling(false), Error::kOk);
  ASSERT_EQ(d.clear(Rgb8{0, 0, 0}), Error::kOk);
  ASSERT_EQ(rig.load(m), Error::kOk);
  ASSERT_EQ(rig.draw_all(m), Error::kOk);
  EXPECT_EQ(d.counters().triangles_rejected, 1u);
  EXPECT_EQ(d.counters().pixels_written, 0u);
}

TEST(Degenerate, ZeroAreaAndSubPixelTrianglesDrawNothing) {
  Rig rig(64, 64);
  Mesh m;
  m.positions = {{-0.5, -0.5, 0}, {0.5, 0.5, 0}, {0.0, 0.0, 0},   // collinear
                 {0.2, 0.3, 0},   {0.2, 0.3, 0}, {0.7, -0.1, 0},  // repeated vertex
                 {0.1, 0.1, 0},   {0.1, 0.1, 0}, {0.1, 0.1, 0}};  // a point
  for (int i = 0; i < 9; ++i) m.normals.push_back({0, 0, 1});
  for (std::uint32_t i = 0; i < 9; ++i) m.indices.push_back(i);
  auto& d = rig.dev;
  ASSERT_EQ(d.set_culling(false), Error::kOk);
  ASSERT_EQ(d.clear(Rgb8{0, 0, 0}), Error::kOk);
  ASSERT_EQ(rig.load(m), Error::kOk);
  ASSERT_EQ(rig.draw_all(m), Error::kOk);
  EXPECT_EQ(d.counters().triangles_degenerate, 3u);
  EXPECT_EQ(d.counters().pixels_written, 0u);
}

// Facing: CCW in NDC (y up) is front; the same triangle CW is culled.
TEST(Facing, CounterClockwiseInNdcIsFront) {
  Rig rig(32, 32);
  Mesh m;
  m.positions = {{-0.5, -0.5, 0}, {0.5, -0.5, 0}, {0, 0.5, 0}};
  m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  m.indices = {0, 1, 2, 0, 2, 1};
  auto& d = rig.dev;
  ASSERT_EQ(d.clear(Rgb8{0, 0, 0}), Error::kOk);
  ASSERT_EQ(rig.load(m), Error::kOk);
  ASSERT_EQ(d.draw(DrawCmd{0, 3}), Error::kOk);
  EXPECT_EQ(d.counters().triangles_culled, 0u);
  EXPECT_GT(d.counters().pixels_written, 0u);
  ASSERT_EQ(d.draw(DrawCmd{3, 3}), Error::kOk);
  EXPECT_EQ(d.counters().triangles_culled, 1u);
}

// Top-left rule on exact pixel centres: two triangles splitting a square along its diagonal,
// with every edge through pixel centres, cover the square's pixels once (left/top edges in,
// right/bottom edges out).
TEST(Cover, EdgesThroughPixelCentresFollowTopLeft) {
  Rig rig(16, 16);
  // Screen square from centre (2.5, 2.5) to (10.5, 10.5): NDC = pixel / 8 - 1, y flipped.
  const auto ndc = [](double px, double py) { return glm::dvec3(px / 8 - 1, 1 - py / 8, 0); };
  Mesh m;
  m.positions = {ndc(2.5, 2.5), ndc(10.5, 2.5), ndc(10.5, 10.5), ndc(2.5, 10.5)};
  m.normals.assign(4, {0, 0, 1});
  m.indices = {0, 3, 2, 0, 2, 1};  // CCW in NDC
  auto& d = rig.dev;
  ASSERT_EQ(d.set_depth_test(false), Error::kOk);
  ASSERT_EQ(d.clear(Rgb8{0, 0, 0}), Error::kOk);
  ASSERT_EQ(rig.load(m), Error::kOk);
  ASSERT_EQ(rig.draw_all(m), Error::kOk);
  for (std::uint32_t y = 0; y < 16; ++y)
    for (std::uint32_t x = 0; x < 16; ++x) {
      const int expected = (x >= 2 && x < 10 && y >= 2 && y < 10) ? 1 : 0;
      EXPECT_EQ(rig.count(x, y), expected) << x << "," << y;
    }
}

// The draw skips its per-vertex validation pass where transform_cannot_fail proves that every
// position transforms: the proof must hold at the worst vertices of the bound, the corners of
// the box |x|, |y|, |z| <= bound (a linear map's largest components are there), for random
// matrices of every scale; and it must hold for an ordinary camera, else it saves nothing.
TEST(Transform, CannotFailIsABoundOnEveryVertexInTheBox) {
  std::mt19937_64 rng(20261202);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> matrix_scale(-3, 3), coordinate_scale(-4, 13);
  long proven = 0, refused = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    // Scales drawn per matrix and per bound, so that the eye and clip coordinates land on both
    // sides of Q15.16's limit.
    Mat4 mv, proj;
    for (Mat4* m : {&mv, &proj}) {
      const double e = std::ldexp(1.0, matrix_scale(rng));
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m->m[c][r] = q16(unit(rng) * e);
    }
    const auto bound = static_cast<std::uint32_t>(std::ldexp(1.0, 16 + coordinate_scale(rng)) *
                                                  (0.5 + 0.25 * (unit(rng) + 1.0)));
    if (!transform_cannot_fail(mv, proj, bound)) {
      ++refused;
      continue;
    }
    ++proven;
    const std::int32_t b = static_cast<std::int32_t>(bound);
    for (int corner = 0; corner < 8; ++corner) {
      Vertex v{};
      v.position =
          Vec3q16{q15_16::from_raw(corner & 1 ? b : -b), q15_16::from_raw(corner & 2 ? b : -b),
                  q15_16::from_raw(corner & 4 ? b : -b)};
      ClipVertex out;
      ASSERT_TRUE(transform_position(mv, proj, v, out))
          << "trial " << trial << " corner " << corner;
    }
  }
  std::printf("transform_cannot_fail: %ld proven, %ld left to the per-vertex check\n", proven,
              refused);
  EXPECT_GT(proven, 1000);
  EXPECT_GT(refused, 1000);
  // The teapot's camera: coordinates up to 4, 30 degrees of perspective, 5 units away.
  const glm::dmat4 view = glm::lookAt(glm::dvec3(0, 2, 8), glm::dvec3(0), glm::dvec3(0, 1, 0));
  const glm::dmat4 persp = glm::perspective(glm::radians(30.0), 4.0 / 3.0, 0.1, 100.0);
  EXPECT_TRUE(transform_cannot_fail(to_mat4(view), to_mat4(persp), 4u << 16));
  // The matrix of Commands.BadIndexAndTransformOverflowRefuseTheDraw is not proven.
  Mat4 big = to_mat4(glm::dmat4(1));
  for (int c = 0; c < 4; ++c) big.m[c][0] = q16(16000);
  EXPECT_FALSE(transform_cannot_fail(big, to_mat4(glm::dmat4(1)), 46341));
}

// ScreenPlane::at divides once, inline, with fx::div's rounding (half away from zero) for the
// positive area: the same value as v0 + fx::div<int_q>(l1·d1 + l2·d2, area) over random
// triangles, vertex values of either sign up to 2^33 (and small ones, for exact ties) and points
// inside and outside.
TEST(Interp, ScreenPlaneAtRoundsAsFxDiv) {
  std::mt19937_64 rng(12);
  std::uniform_int_distribution<std::int32_t> coord(-4096 * 16, 4096 * 16);
  std::uniform_int_distribution<std::int64_t> value(-(std::int64_t{1} << 33),
                                                    std::int64_t{1} << 33);
  int checked = 0;
  for (int t = 0; t < 20000; ++t) {
    Triangle tri;
    for (ShadeVertex& v : tri.v) {
      v.sx = coord(rng) >> (t % 12);
      v.sy = coord(rng) >> (t % 12);
    }
    tri.area2 = edge_function(tri.v[0], tri.v[1], tri.v[2].sx, tri.v[2].sy);
    if (tri.area2 <= 0) continue;
    // Every other triangle with small values, so that exact ties (a remainder of half the
    // area) occur and the rounding direction is checked.
    const std::int64_t scale = t % 2 == 0 ? std::int64_t{1} << 30 : 1;
    const std::int64_t v0 = value(rng) / scale, v1 = value(rng) / scale, v2 = value(rng) / scale;
    ScreenPlane plane;
    plane.setup(tri, v0, v1, v2);
    const int shift = shift_to_fit(static_cast<std::uint64_t>(tri.area2), 27);
    for (int k = 0; k < 4; ++k) {
      const Lambdas lam = lambdas_at(tri, coord(rng) >> (t % 12), coord(rng) >> (t % 12));
      constexpr std::int64_t lim = std::int64_t{1} << 27;
      const auto cut = [&](std::int64_t l) { return std::clamp(l >> shift, -lim, lim); };
      const std::int64_t num = cut(lam.l[1]) * (v1 - v0) + cut(lam.l[2]) * (v2 - v0);
      const std::int64_t expected =
          v0 + fx::div<fx::int_q>(fx::int_q::from_raw(num), fx::int_q::from_raw(tri.area2 >> shift))
                   .raw();
      ASSERT_EQ(plane.at(lam), expected) << "triangle " << t;
      ++checked;
    }
  }
  EXPECT_GT(checked, 20000);
}

}  // namespace
}  // namespace tp::fw::test
