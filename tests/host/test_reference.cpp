// The double reference on cases with known answers: a flat quad (exact values), a finely
// tessellated sphere against the analytic sphere, coverage rules, clipping, the angular scheme.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "host/metrics.hpp"
#include "host/reference.hpp"

using namespace tp::host;

namespace {

FrameSetup ortho_frame(int w, int h, double extent) {
  FrameSetup f;
  f.width = w;
  f.height = h;
  f.projection = glm::ortho(-extent, extent, -extent, extent, -10.0, 10.0);
  f.eye_at_infinity = true;
  f.material.colour = {0.2, 0.4, 1.0};
  return f;
}

// Screen = world: x right, y down, pixel centres at (i + 0.5, j + 0.5). Facing is flipped by
// the y-flip, so coverage tests turn culling off.
FrameSetup pixel_frame(int w, int h) {
  FrameSetup f = ortho_frame(w, h, 1);
  f.projection = glm::ortho(0.0, double(w), double(h), 0.0, -1.0, 1.0);
  f.cull_backfaces = false;
  f.lights = {{LightKind::Directional, {0, 0, 1}, {1, 1, 1}}};
  return f;
}

Mesh square(double x0, double y0, double x1, double y1) {
  Mesh m;
  m.positions = {{x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}};
  m.normals.assign(4, glm::dvec3(0, 0, 1));
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

std::size_t idx(const FrameSetup& f, int i, int j) {
  return static_cast<std::size_t>(j * f.width + i);
}

}  // namespace

TEST(Reference, FlatQuadFacingADirectionalLightHasTheExactValue) {
  FrameSetup f = ortho_frame(64, 64, 1.25);
  f.lights = {{LightKind::Directional, {0, 0, 1}, {1, 1, 1}}};
  const Mesh q = quad(1);
  const ReferenceImage r = render_reference(f, {{&q, glm::dmat4(1)}});
  // N·L = N·H = 1: I = ka·O + kd·O + ks = 0.7·O + 0.4.
  const glm::dvec3 want = 0.7 * f.material.colour + glm::dvec3(0.4);
  const float* c = r.linear.at(32, 32);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], want[k], 1e-6);  // float storage
  EXPECT_EQ(r.rgb8.at(32, 32)[0], 138);                          // round(255·0.54) = round(137.7)
  EXPECT_EQ(r.rgb8.at(32, 32)[1], 173);                          // round(255·0.68) = round(173.4)
  EXPECT_EQ(r.rgb8.at(32, 32)[2], 255);                          // 1.1 clamped
  EXPECT_FLOAT_EQ(r.clamped.at(32, 32)[2], 1.0f);
  EXPECT_FLOAT_EQ(r.linear.at(32, 32)[2], 1.1f);
  EXPECT_EQ(r.mask[idx(f, 0, 0)], 0);  // outside the quad (|x| > 1): background
  EXPECT_EQ(r.rgb8.at(0, 0)[0], 0);
}

TEST(Reference, FlatQuadUnderAPointLightMatchesTheClosedForm) {
  FrameSetup f = ortho_frame(64, 64, 1.25);
  f.lights = {{LightKind::Point, {0.3, -0.2, 1.5}, {1, 1, 1}}};
  // Half-size 0.9375 puts the corners on screen 8 and 56 exactly, so snapping to 1/16 moves
  // nothing and the interpolated eye position is the true one (attributes are interpolated
  // over the snapped triangle, as on the device).
  const Mesh q = quad(0.9375);
  const ReferenceImage r = render_reference(f, {{&q, glm::dmat4(1)}});
  for (auto [i, j] : {std::pair{10, 40}, std::pair{32, 32}, std::pair{50, 13}}) {
    // Pixel centre -> eye space: x = −1.25 + 2.5(i + 0.5)/64, y = 1.25 − 2.5(j + 0.5)/64.
    const glm::dvec3 p(-1.25 + 2.5 * (i + 0.5) / 64, 1.25 - 2.5 * (j + 0.5) / 64, 0);
    const glm::dvec3 l = glm::normalize(glm::dvec3(0.3, -0.2, 1.5) - p);
    const double nl = l.z, nh = glm::normalize(l + glm::dvec3(0, 0, 1)).z;
    const glm::dvec3 want =
        (0.1 + 0.6 * nl) * f.material.colour + glm::dvec3(0.4 * std::pow(nh, 20));
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.linear.at(i, j)[k], want[k], 1e-6) << i << "," << j;
  }
}

TEST(Reference, FineSphereMatchesTheAnalyticSphere) {
  // Octahedron subdivided 5× (8192 triangles) vs the exact sphere normal (x, y, √(1−x²−y²))
  // at pixel centres with r < 0.9. Measured max |Δ| (linear intensity) 0.00179 at 128×128
  // (build/release/tests/host/host_reference_test prints it); pinned at 0.005 (2.8× margin).
  FrameSetup f = ortho_frame(128, 128, 1.25);
  f.lights = {{LightKind::Point, 4.0 * glm::normalize(glm::dvec3(1, 1.2, 1.5)), {1, 1, 1}}};
  const Mesh s = octa_sphere(5);
  const ReferenceImage r = render_reference(f, {{&s, glm::dmat4(1)}});
  double worst = 0;
  int n = 0;
  for (int j = 0; j < 128; ++j)
    for (int i = 0; i < 128; ++i) {
      const double x = -1.25 + 2.5 * (i + 0.5) / 128, y = 1.25 - 2.5 * (j + 0.5) / 128;
      if (x * x + y * y > 0.81) continue;
      ASSERT_TRUE(r.mask[idx(f, i, j)]);
      const glm::dvec3 p(x, y, std::sqrt(1 - x * x - y * y));
      const glm::dvec3 want = blinn_phong(p, p, f);
      for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(r.linear.at(i, j)[k] - want[k]));
      ++n;
    }
  std::printf("fine sphere: max |linear error| = %.6f over %d pixels\n", worst, n);
  EXPECT_LT(worst, 0.005);
}

TEST(Coverage, TopLeftRuleOnPixelCentres) {
  const FrameSetup f = pixel_frame(8, 8);
  // Edges exactly through pixel centres 2.5 and 5.5: the left and top edges own them.
  const Mesh m = square(2.5, 2.5, 5.5, 5.5);
  const ReferenceImage r = render_reference(f, {{&m, glm::dmat4(1)}});
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) {
      const bool in = i >= 2 && i <= 4 && j >= 2 && j <= 4;
      EXPECT_EQ(r.coverage[idx(f, i, j)], in ? 1 : 0) << i << "," << j;  // the shared diagonal once
    }
}

TEST(Coverage, SnappingToSixteenthsDecidesTies) {
  const FrameSetup f = pixel_frame(8, 8);
  // 2.5 + 1/40 snaps back to 2.5 (40/16 ... round(16·2.525) = 40 = 16·2.5): left edge owns it.
  const Mesh a = square(2.525, 2.5, 5.5, 5.5);
  EXPECT_EQ(render_reference(f, {{&a, glm::dmat4(1)}}).coverage[idx(f, 2, 3)], 1);
  // 2.5 + 1/20 snaps to 2.5625 (round(41.6) = 42 → 42/16): centre 2.5 now outside.
  const Mesh b = square(2.55, 2.5, 5.5, 5.5);
  EXPECT_EQ(render_reference(f, {{&b, glm::dmat4(1)}}).coverage[idx(f, 2, 3)], 0);
}

TEST(Coverage, ClosedSphereHasNoCracksAndNoDoubleWrites) {
  FrameSetup f = ortho_frame(200, 200, 1.25);
  f.lights = {{LightKind::Directional, {0, 0, 1}, {1, 1, 1}}};
  const Mesh s = octa_sphere(3);
  const ReferenceImage front = render_reference(f, {{&s, glm::dmat4(1)}});
  f.cull_backfaces = false;
  const ReferenceImage both = render_reference(f, {{&s, glm::dmat4(1)}});
  int inner = 0;
  for (int j = 0; j < 200; ++j)
    for (int i = 0; i < 200; ++i) {
      const std::size_t p = idx(f, i, j);
      EXPECT_LE(front.coverage[p], 1);  // front faces of a convex mesh never overlap
      // Every pixel the mesh covers is covered exactly once from the front and once from the
      // back: no cracks along shared edges, no double writes.
      if (both.coverage[p]) {
        EXPECT_EQ(both.coverage[p], 2) << i << "," << j;
      }
      EXPECT_EQ(front.coverage[p] == 1, both.coverage[p] == 2);
      const double x = -1.25 + 2.5 * (i + 0.5) / 200, y = 1.25 - 2.5 * (j + 0.5) / 200;
      if (x * x + y * y < 0.8) {
        EXPECT_EQ(front.coverage[p], 1);
        ++inner;
      }
    }
  EXPECT_GT(inner, 10000);
}

TEST(Coverage, BackFacesAreCulledByDefault) {
  FrameSetup f = ortho_frame(32, 32, 1.25);
  Mesh q = quad(1);
  for (auto& t : q.triangles) std::swap(t[1], t[2]);  // now CW in NDC: a back face
  EXPECT_EQ(render_reference(f, {{&q, glm::dmat4(1)}}).coverage[idx(f, 16, 16)], 0);
  f.cull_backfaces = false;
  EXPECT_EQ(render_reference(f, {{&q, glm::dmat4(1)}}).coverage[idx(f, 16, 16)], 1);
}

TEST(Clipping, NearPlaneClipsInHomogeneousSpace) {
  FrameSetup f;
  f.width = f.height = 64;
  f.projection = glm::perspective(glm::radians(60.0), 1.0, 1.0, 10.0);
  f.eye_at_infinity = false;
  f.lights = {{LightKind::Directional, {0, 0, 1}, {1, 1, 1}}};
  f.cull_backfaces = false;
  // A floor y = −1 from z = +3 (behind the eye) to z = −8: only the part beyond z = −1 is drawn.
  Mesh floor;
  floor.positions = {{-2, -1, 3}, {2, -1, 3}, {2, -1, -8}, {-2, -1, -8}};
  floor.normals.assign(4, glm::dvec3(0, 1, 0));
  floor.triangles = {{0, 1, 2}, {0, 2, 3}};
  const ReferenceImage r = render_reference(f, {{&floor, glm::dmat4(1)}});
  int covered = 0;
  for (std::size_t p = 0; p < r.mask.size(); ++p)
    if (r.mask[p]) {
      ++covered;
      EXPECT_GE(r.depth[p], -1.0);
      EXPECT_LT(r.depth[p], 1.0);
    }
  EXPECT_GT(covered, 100);
  // The near edge of the clipped floor is at z = −1, y = −1: 45° below the axis, outside the
  // 30° half-field, so the bottom row is covered; the horizon (z = −8) stays below the centre.
  EXPECT_TRUE(r.mask[idx(f, 32, 63)]);
  EXPECT_FALSE(r.mask[idx(f, 32, 31)]);
  // Entirely behind the eye: nothing.
  Mesh behind = floor;
  for (auto& p : behind.positions) p.z = 3 + (p.z > 0 ? 1 : 0);
  const ReferenceImage none = render_reference(f, {{&behind, glm::dmat4(1)}});
  for (auto m : none.mask) EXPECT_EQ(m, 0);
}

TEST(Angular, SlerpKeepsUnitLengthAndEqualAngles) {
  const glm::dvec3 a(1, 0, 0), b = glm::normalize(glm::dvec3(1, 1, 0));
  const glm::dvec3 m = slerp(a, b, 0.5);
  EXPECT_NEAR(glm::length(m), 1, 1e-15);
  EXPECT_NEAR(std::acos(glm::dot(a, m)), std::acos(glm::dot(m, b)), 1e-12);
  EXPECT_NEAR(glm::length(slerp(a, b, 0) - a), 0, 1e-15);
  EXPECT_NEAR(glm::length(slerp(a, b, 1) - b), 0, 1e-15);
  EXPECT_NEAR(glm::length(slerp(a, a, 0.3) - a), 0, 1e-15);
}

TEST(Angular, EqualsPhongWhenNormalsAreEqual) {
  FrameSetup f = ortho_frame(32, 32, 1.25);
  f.lights = {{LightKind::Point, {0.3, -0.2, 1.5}, {1, 1, 1}}};
  const Mesh q = quad(1);
  const ReferenceImage a = render_reference(f, {{&q, glm::dmat4(1)}}, Interpolation::Angular);
  const ReferenceImage p = render_reference(f, {{&q, glm::dmat4(1)}}, Interpolation::Phong);
  EXPECT_EQ(a.mask, p.mask);
  for (std::size_t k = 0; k < a.linear.rgb.size(); ++k)
    EXPECT_NEAR(a.linear.rgb[k], p.linear.rgb[k], 1e-6);
}

TEST(Angular, DiffersFromPhongOnACoarseSphereButNotMuch) {
  // sphere-32 scene setup at 256×256. Measured colour correctness (eq. 6.1) of Angular vs
  // Phong 0.99782, max 5 levels (printed by this test); pinned at > 0.98 (the schemes differ
  // visibly on 32 triangles, by far less than Gouraud's 0.94 in docs/RESULTS.md).
  FrameSetup f = ortho_frame(256, 256, 1.25);
  f.lights = {{LightKind::Point, 4.0 * glm::normalize(glm::dvec3(1, 1.2, 1.5)), {1, 1, 1}}};
  const Mesh s = octa_sphere(1);
  const ReferenceImage a = render_reference(f, {{&s, glm::dmat4(1)}}, Interpolation::Angular);
  const ReferenceImage p = render_reference(f, {{&s, glm::dmat4(1)}}, Interpolation::Phong);
  EXPECT_EQ(a.mask, p.mask);
  const Comparison c = compare(p.rgb8, p.mask, a.rgb8, a.mask);
  std::printf("sphere-32 angular vs phong: c = %.5f, max %d, mean %.3f\n", c.color_correctness,
              c.max_abs, c.mean_abs);
  EXPECT_LT(c.color_correctness, 1.0);
  EXPECT_GT(c.color_correctness, 0.98);
}
