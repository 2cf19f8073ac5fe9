// Flat, Gouraud and Phong against a double-precision computation of the same formulas
// (docs/CONVENTIONS.md) at every pixel the device covered inside a single triangle.
#include <gtest/gtest.h>

#include <array>

#include <algorithm>
#include <cstdio>

#include "firmware/lighting.hpp"
#include "helpers.hpp"

namespace tp::fw::test {
namespace {

using glm::dvec3;

struct Light {
  bool point;
  dvec3 v;  // eye space: direction toward the light, or position
  dvec3 colour;
};

struct Scene {
  dvec3 colour{1.0, 0.8, 0.6};
  double ka = 0.1, kd = 0.6, ks = 0.4;
  int n = 20;
  bool finite_eye = true;
  std::vector<Light> lights;
};

// The Blinn-Phong formula of docs/CONVENTIONS.md, in double.
dvec3 blinn_phong(const Scene& s, dvec3 p, dvec3 n) {
  dvec3 out = s.ka * s.colour;
  const dvec3 v = s.finite_eye ? glm::normalize(-p) : dvec3(0, 0, 1);
  for (const Light& l : s.lights) {
    const dvec3 L = l.point ? glm::normalize(l.v - p) : l.v;
    const dvec3 H = glm::normalize(L + v);
    const double ndl = std::max(0.0, glm::dot(n, L)), ndh = std::max(0.0, glm::dot(n, H));
    out += l.colour * (s.kd * s.colour * ndl + dvec3(s.ks * std::pow(ndh, s.n)));
  }
  return out;
}
dvec3 clamp01(dvec3 c) { return glm::clamp(c, dvec3(0), dvec3(1)); }
int level(double c) { return static_cast<int>(std::floor(255 * std::clamp(c, 0.0, 1.0) + 0.5)); }

struct Expected {
  dvec3 eye[3], normal[3];
  glm::dvec2 screen[3];
  double w[3];
};

void configure(Device& d, const Scene& s, const glm::dmat4& mv, const glm::dmat4& proj) {
  ASSERT_EQ(d.set_modelview(to_mat4(mv)), Error::kOk);
  ASSERT_EQ(d.set_projection(to_mat4(proj)), Error::kOk);
  ASSERT_EQ(d.set_eye(s.finite_eye ? EyeMode::kFinite : EyeMode::kInfinite), Error::kOk);
  MaterialCmd m;
  for (int c = 0; c < 3; ++c) m.color[c] = q30(s.colour[c]);
  m.ka = q30(s.ka);
  m.kd = q30(s.kd);
  m.ks = q30(s.ks);
  m.n = static_cast<std::uint32_t>(s.n);
  ASSERT_EQ(d.set_material(m), Error::kOk);
  for (std::uint32_t i = 0; i < kMaxLights; ++i) {
    LightCmd l;
    l.index = i;
    if (i < s.lights.size()) {
      const Light& src = s.lights[i];
      l.type = src.point ? LightType::kPoint : LightType::kDirectional;
      for (int c = 0; c < 3; ++c) l.color[c] = q16(src.colour[c]);
      if (src.point) {
        l.position = Vec3q16{q16(src.v.x), q16(src.v.y), q16(src.v.z)};
      } else {
        const dvec3 n = glm::normalize(src.v);
        l.direction = Vec3u{q30(n.x), q30(n.y), q30(n.z)};
      }
    }
    ASSERT_EQ(d.set_light(l), Error::kOk);
  }
}

struct Diff {
  int max = 0;
  long pixels = 0;
  long off = 0;  // pixels with any channel off by >= 1 level
};

// Twice the signed area of triangle (o, a, b): the edge function in double.
double cross2(glm::dvec2 o, glm::dvec2 a, glm::dvec2 b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// The six points of Vlasic's quadratic triangle (vertices, then the midpoints of edges 0-1, 1-2
// and 2-0) and their clamped colours, in double.
constexpr int kEdges[3][2] = {{0, 1}, {1, 2}, {2, 0}};
std::array<dvec3, 6> six_colours(const Expected& e, const Scene& s) {
  std::array<dvec3, 6> c;
  for (int i = 0; i < 3; ++i) c[i] = clamp01(blinn_phong(s, e.eye[i], e.normal[i]));
  for (int k = 0; k < 3; ++k) {
    const int a = kEdges[k][0], b = kEdges[k][1];
    c[3 + k] = clamp01(
        blinn_phong(s, (e.eye[a] + e.eye[b]) / 2.0, glm::normalize(e.normal[a] + e.normal[b])));
  }
  return c;
}

// Vlasic's quadratic (eq. 4.1 through the six colours, written as the interpolating quadratic
// in barycentrics, independently of eq. 4.2) at the perspective-correct (or, screen: the
// screen-linear) barycentrics of screen barycentrics lam.
dvec3 quadratic(const Expected& e, const Scene& s, const double lam[3], bool screen) {
  double b[3], sum = 0;
  for (int i = 0; i < 3; ++i) sum += b[i] = screen ? lam[i] : lam[i] / e.w[i];
  for (double& v : b) v /= sum;
  const std::array<dvec3, 6> c = six_colours(e, s);
  dvec3 r(0);
  for (int i = 0; i < 3; ++i) r += b[i] * (2 * b[i] - 1) * c[i];
  for (int k = 0; k < 3; ++k) r += 4 * b[kEdges[k][0]] * b[kEdges[k][1]] * c[3 + k];
  return clamp01(r);
}

// Gouraud on the four sub-triangles, their corners where the eye-space midpoints project.
dvec3 subdivided(const Expected& e, const Scene& s, glm::dvec2 q, bool snap) {
  glm::dvec2 p[6];
  for (int i = 0; i < 3; ++i) p[i] = e.screen[i];
  for (int k = 0; k < 3; ++k) {
    const int a = kEdges[k][0], b = kEdges[k][1];
    p[3 + k] = (e.w[a] * e.screen[a] + e.w[b] * e.screen[b]) / (e.w[a] + e.w[b]);
    if (snap) p[3 + k] = glm::round(p[3 + k] * 16.0) / 16.0;
  }
  const std::array<dvec3, 6> c = six_colours(e, s);
  constexpr int kParts[4][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}, {3, 4, 5}};
  for (const auto& part : kParts) {
    const glm::dvec2 a = p[part[0]], b = p[part[1]], d = p[part[2]];
    const double area = cross2(a, b, d);
    const double l[3] = {cross2(b, d, q) / area, cross2(d, a, q) / area, cross2(a, b, q) / area};
    if (l[0] < 0 || l[1] < 0 || l[2] < 0) continue;
    return l[0] * c[part[0]] + l[1] * c[part[1]] + l[2] * c[part[2]];
  }
  return dvec3(-1);  // outside every part: no pixel compared here is
}

// Renders the triangle with method m and compares every covered pixel at least `margin`
// pixels inside the (double) triangle with the double computation of the same method.
// snap: interpolate from vertex positions snapped to 1/16 pixel like the device's (otherwise
// the exact projected positions, as a reference renderer that does not snap would).
Diff compare(Method method, const Scene& s, const glm::dmat4& mv, const glm::dmat4& proj,
             bool snap) {
  const std::uint32_t W = 96, H = 80;
  Rig rig(W, H);
  Mesh m;
  m.positions = {{-1, -0.9, 0}, {1, -0.9, 0}, {0, 1, 0}};
  for (const dvec3& p : m.positions) m.normals.push_back(glm::normalize(0.6 * p + dvec3(0, 0, 1)));
  m.indices = {0, 1, 2};
  configure(rig.dev, s, mv, proj);
  EXPECT_EQ(rig.dev.set_method(method), Error::kOk);
  EXPECT_EQ(rig.dev.clear(Rgb8{0, 0, 0}), Error::kOk);
  EXPECT_EQ(rig.load(m), Error::kOk);
  EXPECT_EQ(rig.draw_all(m), Error::kOk);

  Expected e;
  const glm::dmat3 nm(mv);
  for (int i = 0; i < 3; ++i) {
    e.eye[i] = dvec3(mv * glm::dvec4(m.positions[i], 1));
    e.normal[i] = glm::normalize(nm * m.normals[i]);
    const glm::dvec4 c = proj * glm::dvec4(e.eye[i], 1);
    e.w[i] = c.w;
    e.screen[i] = {(c.x / c.w + 1) / 2 * W, (1 - c.y / c.w) / 2 * H};
    if (snap) e.screen[i] = glm::round(e.screen[i] * 16.0) / 16.0;
  }
  const double area = cross2(e.screen[0], e.screen[1], e.screen[2]);
  dvec3 vc[3];
  for (int i = 0; i < 3; ++i) vc[i] = clamp01(blinn_phong(s, e.eye[i], e.normal[i]));
  const dvec3 flat = blinn_phong(s, (e.eye[0] + e.eye[1] + e.eye[2]) / 3.0,
                                 glm::normalize(e.normal[0] + e.normal[1] + e.normal[2]));
  Diff d;
  for (std::uint32_t y = 0; y < H; ++y)
    for (std::uint32_t x = 0; x < W; ++x) {
      const glm::dvec2 q{x + 0.5, y + 0.5};
      double lam[3] = {cross2(e.screen[1], e.screen[2], q) / area,
                       cross2(e.screen[2], e.screen[0], q) / area,
                       cross2(e.screen[0], e.screen[1], q) / area};
      // Half a pixel inside every edge (in barycentric terms, roughly): away from coverage
      // differences caused by snapping.
      bool inside = true;
      for (int i = 0; i < 3; ++i) {
        const glm::dvec2 a = e.screen[(i + 1) % 3], b = e.screen[(i + 2) % 3];
        inside = inside && lam[i] * std::abs(area) / glm::length(b - a) > 0.5;
      }
      if (!inside) continue;
      EXPECT_EQ(rig.count(x, y), 1) << x << "," << y;
      dvec3 want;
      if (method == Method::kFlat) {
        want = flat;
      } else if (method == Method::kGouraud) {
        want = lam[0] * vc[0] + lam[1] * vc[1] + lam[2] * vc[2];
      } else if (method == Method::kDuff) {
        // Phong's normal, screen-linear; L, V and H at the eye-space centroid.
        const dvec3 n = lam[0] * e.normal[0] + lam[1] * e.normal[1] + lam[2] * e.normal[2];
        want = blinn_phong(s, (e.eye[0] + e.eye[1] + e.eye[2]) / 3.0, glm::normalize(n));
      } else if (method == Method::kQuadratic || method == Method::kQuadraticScreen) {
        want = quadratic(e, s, lam, method == Method::kQuadraticScreen);
      } else if (method == Method::kGouraudSubdivided) {
        want = subdivided(e, s, q, snap);
      } else {
        double b[3], sum = 0;
        for (int i = 0; i < 3; ++i) sum += b[i] = lam[i] / e.w[i];
        dvec3 p(0), n(0);
        for (int i = 0; i < 3; ++i) {
          p += b[i] / sum * e.eye[i];
          n += b[i] / sum * e.normal[i];
        }
        want = blinn_phong(s, p, glm::normalize(n));
      }
      const Rgb8 got = rig.pixel(x, y);
      const int diffs[3] = {std::abs(got.r - level(want.r)), std::abs(got.g - level(want.g)),
                            std::abs(got.b - level(want.b))};
      d.max = std::max({d.max, diffs[0], diffs[1], diffs[2]});
      d.off += std::max({diffs[0], diffs[1], diffs[2]}) > 0 ? 1 : 0;
      ++d.pixels;
    }
  std::printf("method %d snap %d: %ld pixels, max |diff| %d levels, %ld pixels off\n",
              static_cast<int>(method), snap ? 1 : 0, d.pixels, d.max, d.off);
  return d;
}

Scene point_light_scene() {
  Scene s;
  s.lights = {{true, dvec3(0.1, -0.1, 1.5), dvec3(1, 1, 1)},
              {false, glm::normalize(dvec3(-0.5, 0.4, 1)), dvec3(0.5, 0.6, 0.7)}};
  return s;
}

const glm::dmat4 kView = glm::lookAt(dvec3(0.3, -0.4, 2.5), dvec3(0, 0, 0), dvec3(0, 1, 0));
const glm::dmat4 kPerspective = glm::perspective(0.9, 96.0 / 80.0, 0.5, 10.0);

// Bounds: measured with ./build/release/tests/firmware/firmware_shading_test (the printed lines:
// "method M snap S: P pixels, max |diff| D levels, K pixels off"), then pinned with margin.
// Against a double computation from the same snapped vertex positions the device is off by at
// most one level, on the few pixels whose double value lies near a rounding boundary
// (measured: flat 0, Gouraud 2, Phong 3 of ~1980 pixels; pinned at 1 % of the pixels). Against
// unsnapped positions the 1/32-pixel snapping shifts the interpolation: still at most one
// level, but on more pixels (measured: Gouraud 10, Phong 237 of 1979 = 12 %; pinned at 20 %).
void expect_close(const Diff& d, double max_off_fraction) {
  EXPECT_GT(d.pixels, 1000);
  EXPECT_LE(d.max, 1);
  EXPECT_LE(static_cast<double>(d.off), max_off_fraction * static_cast<double>(d.pixels));
}

TEST(Shading, FlatMatchesDoubleCentroidEvaluation) {
  expect_close(compare(Method::kFlat, point_light_scene(), kView, kPerspective, true), 0.01);
  expect_close(compare(Method::kFlat, point_light_scene(), kView, kPerspective, false), 0.01);
}

TEST(Shading, GouraudMatchesDoubleScreenLinearInterpolation) {
  expect_close(compare(Method::kGouraud, point_light_scene(), kView, kPerspective, true), 0.01);
  expect_close(compare(Method::kGouraud, point_light_scene(), kView, kPerspective, false), 0.20);
}

// Duff's identity: the forward-differenced numerators over the root of the forward-differenced
// radicand are the diffuse and specular cosines of the screen-linear normal, so the device's
// pixels are the double Blinn-Phong of that normal (with L and H at the centroid) within
// rounding. Measured 2026-12-03 (the printed lines): 4 of 1977 pixels one level off from the
// snapped positions, 152 of 1979 (7.7 %) from unsnapped ones, 3 with the eye at infinity and
// n = 60; never more than one level. Pinned as for the other methods.
TEST(Shading, DuffMatchesDoubleScreenLinearPhong) {
  expect_close(compare(Method::kDuff, point_light_scene(), kView, kPerspective, true), 0.01);
  expect_close(compare(Method::kDuff, point_light_scene(), kView, kPerspective, false), 0.20);
  Scene far = point_light_scene();
  far.finite_eye = false;
  far.n = 60;
  expect_close(compare(Method::kDuff, far, kView, kPerspective, true), 0.01);
}

// Vlasic's quadratic shading and Gouraud on the subdivided triangle against the same methods in
// double, from the same six colours (the double quadratic written in barycentrics, not by
// eq. 4.2), under perspective (quadratic: eq. 4.1 per pixel; quadratic-screen: forward
// differences) and orthographic (both forward-differenced). Measured 2026-12-03 (the printed
// lines): at most one level off, on at most 4 of 1977 (perspective) and 2 of 2874 (orthographic)
// pixels from the snapped positions and 137 of 1979 (6.9 %) from unsnapped ones. Pinned as for
// the other methods.
TEST(Shading, QuadraticAndSubdividedGouraudMatchTheirDoubleForms) {
  const glm::dmat4 ortho = glm::ortho(-1.2, 1.2, -1.0, 1.0, -5.0, 5.0);
  for (Method m : {Method::kQuadratic, Method::kQuadraticScreen, Method::kGouraudSubdivided}) {
    expect_close(compare(m, point_light_scene(), kView, kPerspective, true), 0.01);
    expect_close(compare(m, point_light_scene(), kView, kPerspective, false), 0.20);
    expect_close(compare(m, point_light_scene(), glm::dmat4(1), ortho, true), 0.01);
  }
}

TEST(Shading, PhongMatchesDoublePerspectiveCorrectReference) {
  expect_close(compare(Method::kPhong, point_light_scene(), kView, kPerspective, true), 0.01);
  expect_close(compare(Method::kPhong, point_light_scene(), kView, kPerspective, false), 0.20);
}

TEST(Shading, PhongOrthographicEyeAtInfinityHighExponent) {
  Scene s = point_light_scene();
  s.finite_eye = false;
  s.n = 200;
  const glm::dmat4 ortho = glm::ortho(-1.2, 1.2, -1.0, 1.0, -5.0, 5.0);
  expect_close(compare(Method::kPhong, s, glm::dmat4(1), ortho, true), 0.01);
  expect_close(compare(Method::kPhong, s, glm::dmat4(1), ortho, false), 0.20);
}

// Gouraud lights each vertex once per draw (the draw's lit-vertex cache, docs/CONVENTIONS.md
// "Memory"), and afresh in the next draw: two triangles sharing an edge cost four evaluations, not
// six; a light changed between two draws reaches the second one exactly as it reaches a fresh
// device.
TEST(Shading, GouraudLightsEachVertexOncePerDraw) {
  Mesh quad;
  quad.positions = {{-1, -0.9, 0}, {1, -0.9, 0}, {1, 0.9, 0}, {-1, 0.9, 0}};
  for (const dvec3& p : quad.positions)
    quad.normals.push_back(glm::normalize(0.6 * p + dvec3(0, 0, 1)));
  quad.indices = {0, 1, 2, 0, 2, 3};
  const auto render = [&](Rig& rig, const Scene& s) {
    configure(rig.dev, s, kView, kPerspective);
    EXPECT_EQ(rig.dev.set_method(Method::kGouraud), Error::kOk);
    EXPECT_EQ(rig.dev.clear(Rgb8{0, 0, 0}), Error::kOk);
    EXPECT_EQ(rig.load(quad), Error::kOk);
    EXPECT_EQ(rig.draw_all(quad), Error::kOk);
  };
  Rig a(96, 80);
  const Scene first = point_light_scene();
  render(a, first);
  EXPECT_EQ(a.dev.counters().triangles_drawn, 2u);
  EXPECT_EQ(a.dev.counters().lighting_evaluations, 4u);
  EXPECT_EQ(a.draw_all(quad), Error::kOk);  // the same draw again: lit again, once per vertex
  EXPECT_EQ(a.dev.counters().lighting_evaluations, 8u);

  Scene second = first;
  second.lights[0].colour = {0.3, 0.9, 0.5};
  second.lights[0].v += dvec3(0.5, -0.25, 0.0);
  render(a, second);
  Rig fresh(96, 80);
  render(fresh, second);
  long differing = 0, lit = 0;
  for (std::uint32_t y = 0; y < 80; ++y)
    for (std::uint32_t x = 0; x < 96; ++x) {
      const Rgb8 p = a.pixel(x, y), q = fresh.pixel(x, y);
      differing += (p.r != q.r || p.g != q.g || p.b != q.b) ? 1 : 0;
      lit += a.count(x, y) > 0 ? 1 : 0;
    }
  EXPECT_GT(lit, 1000);
  EXPECT_EQ(differing, 0);
}

// Caches that outlive a draw (kb-adaptive's boundary samples, keyed on ShadeContext::revision)
// or a triangle (Gouraud's lit vertices) must follow a light, material or eye changed between
// two draws: for every method, a sphere rendered after the change equals the same sphere on a
// fresh device. (A re-sent scene would not test this: its viewport command rebuilds the method.)
TEST(Shading, CachesFollowAChangedLightMaterialOrEye) {
  const Mesh sphere = octasphere(1, 0.9);  // triangles of a few hundred pixels: sampled
  const Scene first = point_light_scene();
  // Light colours and material only: the same lights where N·L changes sign, so that a stale
  // memo entry would match its key (a moved or added light changes that set, and with it the
  // key). Then moved and added lights, the exponent and the eye.
  Scene second = first;
  for (Light& l : second.lights) l.colour = dvec3(0.9, 0.5, 0.2) * l.colour;
  second.ks = 0.7;
  second.colour = dvec3(0.4, 0.9, 0.7);
  Scene third = second;
  third.lights[0].v = dvec3(-1.5, 1.0, 2.0);
  third.lights.push_back({false, glm::normalize(dvec3(0.3, 0.8, 0.5)), {0.6, 0.6, 0.9}});
  third.n = 60;
  third.finite_eye = !first.finite_eye;
  const auto render = [&](Rig& rig, const Scene& s, Method m) {
    configure(rig.dev, s, kView, kPerspective);
    EXPECT_EQ(rig.dev.set_method(m), Error::kOk);
    EXPECT_EQ(rig.dev.clear(Rgb8{0, 0, 0}), Error::kOk);
    EXPECT_EQ(rig.draw_all(sphere), Error::kOk);
    const FramebufferView fb = rig.dev.framebuffer();
    return std::vector<std::uint8_t>(fb.data, fb.data + std::size_t{fb.stride} * fb.height);
  };
  for (const Method m : kImplementedMethods) {
    Rig reused(160, 120), fresh(160, 120);
    ASSERT_EQ(reused.load(sphere), Error::kOk);
    ASSERT_EQ(fresh.load(sphere), Error::kOk);
    const auto before = render(reused, first, m);
    for (const Scene* s : {&second, &third}) {
      const auto after = render(reused, *s, m);
      const auto expected = render(fresh, *s, m);
      EXPECT_FALSE(before == expected) << static_cast<int>(m) << ": the change must show";
      EXPECT_TRUE(after == expected) << static_cast<int>(m);
    }
  }
}

TEST(Shading, PowerByRepeatedSquaring) {
  // x^n against the double power of the same (rounded) input. Measured worst 4.63e-08
  // (~2^-24.4) over this sweep; pinned at 2^-22 (5x margin).
  double worst = 0;
  for (std::uint32_t n : {1u, 2u, 3u, 7u, 20u, 64u, 125u, 1000u, 4096u})
    for (int k = 0; k <= 1000; ++k) {
      const double x = k / 1000.0;
      const double got = d30(power(q30(x), n));
      worst = std::max(worst, std::abs(got - std::pow(d30(q30(x)), n)));
    }
  std::printf("power: worst abs error %.3g\n", worst);
  EXPECT_LT(worst, 1.0 / (1 << 22));
}

TEST(Shading, UnrolledPowerIsPowerBitForBit) {
  // The unrolled powers (lighting.hpp, unrolled_power) must take power()'s products in power()'s
  // order: the same bits for every exponent they cover, at every input the callers give (N·H in
  // [0, 1] plus the few LSB a dot of unit vectors may exceed it by). Above the table, none.
  std::uint32_t covered = 0;
  for (std::uint32_t n = 1; n <= 70; ++n) {
    const PowerFn fn = unrolled_power(n);
    if (n > kUnrolledPowers) {
      EXPECT_EQ(fn, nullptr) << n;
      continue;
    }
    ASSERT_NE(fn, nullptr) << n;
    ++covered;
    std::uint64_t state = 0x9e3779b97f4a7c15u * n;
    for (int k = 0; k < 20000; ++k) {
      state = state * 6364136223846793005u + 1442695040888963407u;
      const auto x = static_cast<std::int64_t>((state >> 33) % ((std::int64_t{1} << 30) + 5));
      ASSERT_EQ(fn(x), power(q1_30::from_raw(static_cast<std::int32_t>(x)), n).raw())
          << "n = " << n << ", x = " << x;
    }
    for (std::int64_t x :
         {std::int64_t{0}, std::int64_t{1}, std::int64_t{1} << 29, (std::int64_t{1} << 30) - 1,
          std::int64_t{1} << 30, (std::int64_t{1} << 30) + 4})
      ASSERT_EQ(fn(x), power(q1_30::from_raw(static_cast<std::int32_t>(x)), n).raw()) << n;
  }
  EXPECT_EQ(covered, kUnrolledPowers);
  EXPECT_EQ(unrolled_power(0), nullptr);
}

}  // namespace
}  // namespace tp::fw::test
