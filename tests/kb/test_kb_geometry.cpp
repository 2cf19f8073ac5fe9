// Span geometry of the Kuijk-Blake method (firmware/kb/kb_geometry.hpp) against the double
// model (kb_model.hpp): equal-angle arcs, the span's great circle (s, φ_L, θ), φ along the
// pixels, and the degenerate cases the paper lists (docs/KUIJK-BLAKE.md, "Degenerate cases").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>

#include "firmware/kb/kb_geometry.hpp"
#include "kb_model.hpp"

namespace kb = tp::fw::kb;
using namespace tp::kbtest;

namespace {

constexpr double kPi = std::numbers::pi;

dvec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  for (;;) {
    const dvec3 v{g(rng), g(rng), g(rng)};
    if (glm::length(v) > 1e-3) return glm::normalize(v);
  }
}

// A unit vector at angle `angle` from a, in a random direction.
dvec3 at_angle(std::mt19937_64& rng, dvec3 a, double angle) {
  dvec3 t = random_unit(rng);
  t = glm::normalize(t - glm::dot(t, a) * a);
  return std::cos(angle) * a + std::sin(angle) * t;
}

double max_abs(dvec3 d) { return std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)}); }

}  // namespace

// Points along an arc agree with textbook slerp, from 1e-6 rad to nearly π. The tangent is
// the normalised orthogonal part of the far end, of length sin θ, so its direction carries
// ~1 LSB / sin θ of rounding: the error is reported relative to (1 + 1/sin θ) LSB.
TEST(KbGeometry, ArcMatchesSlerp) {
  std::mt19937_64 rng(4);
  double worst = 0;
  const double angles[] = {1e-6, 1e-4, 0.01, 0.3, 1.0, 1.5, 2.0, 3.0, 3.1};
  for (int trial = 0; trial < 400; ++trial) {
    const double angle = angles[trial % 9];
    const dvec3 a = random_unit(rng);
    const dvec3 b = at_angle(rng, a, angle);
    const kb::Unit fa = unit(a), fb = unit(b);
    const kb::Arc arc = kb::make_arc(fa, fb);
    const dvec3 ad = to_d(fa), bd = to_d(fb);
    const double lsb_scale = std::ldexp(1.0 + 1.0 / std::sin(angle), -30);
    for (int k = 0; k <= 16; ++k) {
      const double t = k / 16.0;
      const dvec3 got = to_d(kb::arc_at_fraction(arc, q30(t)));
      worst = std::max(worst, max_abs(got - slerp(ad, bd, t)) / lsb_scale);
    }
  }
  std::printf("arc vs slerp: max component error %.2f x (1 + 1/sin θ) LSB of q1_30\n", worst);
  // Measured 1.28 (`kb_geometry_test --gtest_filter=*ArcMatches*`); pinned at 3.
  EXPECT_LT(worst, 3.0);
}

// eq. 4 holds along the span: cos(φ_L + tθ)·cos s equals O·slerp(V_L, V_R, t).
TEST(KbGeometry, SpanCircleReproducesCosAlpha) {
  std::mt19937_64 rng(5);
  double worst_cos = 0, worst_s = 0, worst_theta = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const dvec3 a = random_unit(rng);
    const dvec3 b = at_angle(rng, a, 0.001 + 2.0 * (trial % 100) / 100.0);
    const kb::Unit fa = unit(a), fb = unit(b);
    const dvec3 ad = to_d(fa), bd = to_d(fb);
    const kb::SpanCircle c = kb::span_circle(fa, fb);
    const CircleD ref = circle(ad, bd);
    // s comes from the pole of a short arc: conditioned like 1 LSB / θ; scaled back to θ = 1.
    worst_s = std::max(worst_s, std::fabs(to_d(c.s) - ref.s) * std::min(1.0, ref.theta));
    worst_theta = std::max(worst_theta, std::fabs(to_d(c.theta) - ref.theta));
    for (int k = 0; k <= 8; ++k) {
      const double t = k / 8.0;
      const double got = std::cos(to_d(c.phi_left) + t * to_d(c.theta)) * std::cos(to_d(c.s));
      worst_cos = std::max(worst_cos, std::fabs(got - slerp(ad, bd, t).z));
    }
  }
  std::printf("span circle: max |cos α err| %.3g, |s err| %.3g, |θ err| %.3g rad\n", worst_cos,
              worst_s, worst_theta);
  // Measured 2.4e-9 / 2.3e-9 / 1.9e-9 rad (`kb_geometry_test --gtest_filter=*SpanCircle*`);
  // pinned at about four times that.
  EXPECT_LT(worst_cos, 1e-8);
  EXPECT_LT(worst_s, 1e-8);
  EXPECT_LT(worst_theta, 8e-9);
}

TEST(KbGeometry, IdenticalEndsGiveConstantPhi) {
  const kb::Unit v = unit({0.3, -0.4, 0.8});
  const kb::SpanCircle c = kb::span_circle(v, v);
  EXPECT_TRUE(c.constant);
  EXPECT_EQ(c.s.raw(), 0);
  EXPECT_EQ(c.theta.raw(), 0);
  EXPECT_NEAR(to_d(c.phi_left), std::acos(to_d(v).z), 4e-9);
  const kb::SpanLine line = kb::span_line(c, kb::xpos_t::from_int(3), kb::xpos_t::from_int(40),
                                          kb::xpos_t::from_ratio(7, 2));
  EXPECT_EQ(line.dphi.raw(), 0);
  EXPECT_EQ(line.phi_first, c.phi_left);
}

// O on the span's great circle (both ends in the plane x = 0): s is exactly zero.
TEST(KbGeometry, OOnTheCircleGivesZeroS) {
  const kb::Unit a = unit({0, 0.6, 0.8}), b = unit({0, -0.7, 0.5});
  const kb::SpanCircle c = kb::span_circle(a, b);
  EXPECT_EQ(c.s.raw(), 0);
  EXPECT_NEAR(std::cos(to_d(c.phi_left)), 0.8, 1e-8);
  EXPECT_NEAR(std::cos(to_d(c.phi_left) + to_d(c.theta)), to_d(b).z, 1e-8);
}

// O perpendicular to the circle (both ends on the equator): s = π/2, cos α = 0 everywhere.
TEST(KbGeometry, OPerpendicularGivesRightAngle) {
  const kb::Unit a = unit({1, 0, 0}), b = unit({0.6, 0.8, 0});
  const kb::SpanCircle c = kb::span_circle(a, b);
  EXPECT_NEAR(to_d(c.s), kPi / 2, 4e-9);
  EXPECT_EQ(c.phi_left.raw(), 0);  // atan2(0, 0) = 0 (documented)
  EXPECT_NEAR(to_d(c.theta), std::acos(0.6), 4e-9);
}

// Antipodal ends: a half turn through a fixed perpendicular; the midpoint is orthogonal to both.
TEST(KbGeometry, AntipodalArcIsAHalfTurn) {
  const kb::Unit a = unit({0.2, 0.3, 0.9});
  const kb::Unit b{tp::fx::neg_sat(a.x), tp::fx::neg_sat(a.y), tp::fx::neg_sat(a.z)};
  const kb::Arc arc = kb::make_arc(a, b);
  EXPECT_TRUE(arc.has_direction());
  EXPECT_NEAR(to_d(arc.angle), kPi, 4e-9);
  const dvec3 mid = to_d(kb::arc_at_fraction(arc, q30(0.5)));
  EXPECT_NEAR(glm::length(mid), 1.0, 1e-8);
  EXPECT_NEAR(glm::dot(mid, to_d(a)), 0.0, 1e-8);
  EXPECT_LT(max_abs(to_d(kb::arc_at_fraction(arc, q30(1.0))) - to_d(b)), 1e-8);
}

// More than 90° of rotation across a span still follows the great circle (the one-vector
// method's weak case, which only the interpolation, not the geometry, gets wrong).
TEST(KbGeometry, LargeRotationStaysOnTheCircle) {
  const dvec3 a = glm::normalize(dvec3{0.9, 0.1, 0.4}), b = glm::normalize(dvec3{-0.8, 0.3, 0.5});
  const kb::Unit fa = unit(a), fb = unit(b);
  const kb::SpanCircle c = kb::span_circle(fa, fb);
  ASSERT_GT(to_d(c.theta), kPi / 2);
  for (int k = 0; k <= 10; ++k) {
    const double t = k / 10.0;
    const double got = std::cos(to_d(c.phi_left) + t * to_d(c.theta)) * std::cos(to_d(c.s));
    EXPECT_NEAR(got, slerp(to_d(fa), to_d(fb), t).z, 2e-8) << t;
  }
}

// φ at pixel centres: φ_L + (x − x_L)·θ/(x_R − x_L), against double over a 4,096-pixel span.
TEST(KbGeometry, SpanLineStepsPhiPerPixel) {
  const kb::Unit a = unit({0.5, 0.2, 0.8}), b = unit({-0.4, 0.1, 0.9});
  const kb::SpanCircle c = kb::span_circle(a, b);
  const double xl = 10.3125, xr = 4106.75;  // 1/16-pixel positions
  const kb::SpanLine line =
      kb::span_line(c, kb::xpos_t::from_ratio(165, 16), kb::xpos_t::from_ratio(65708, 16),
                    kb::xpos_t::from_ratio(21, 2));
  const double th = to_d(c.theta), pl = to_d(c.phi_left);
  double worst = 0;
  for (int k = 0; k < 4096; ++k) {
    const double x = 10.5 + k;
    const double want = pl + (x - xl) * th / (xr - xl);
    const double got = to_d(line.phi_first) + k * to_d(line.dphi);
    worst = std::max(worst, std::fabs(got - want));
  }
  // Measured 1.6e-10 rad (`kb_geometry_test --gtest_filter=*SpanLine*`: the first centre's
  // rounding, below 0.5 LSB of angle_t, plus 4,096 × 2^-41 of step rounding); pinned at 1e-9.
  std::printf("span line: max |φ err| over 4096 px %.3g rad\n", worst);
  EXPECT_LT(worst, 1e-9);
}

// Any fixed O works (the methods may take one per triangle): rotating V_L, V_R and O together
// leaves s, φ_L and θ unchanged.
TEST(KbGeometry, SpanCircleForAnyO) {
  std::mt19937_64 rng(6);
  double worst = 0;
  for (int trial = 0; trial < 500; ++trial) {
    const dvec3 a = random_unit(rng);
    const dvec3 b = at_angle(rng, a, 0.01 + 1.5 * (trial % 50) / 50.0);
    const dvec3 o = random_unit(rng);
    // The rotation taking o to z, applied to all three.
    const dvec3 ar = rotate_n_to_o(o, a), br = rotate_n_to_o(o, b);
    const kb::SpanCircle general = kb::span_circle(unit(a), unit(b), unit(o));
    const kb::SpanCircle paper = kb::span_circle(unit(ar), unit(br));
    // Compare cos α = cos φ·cos s at both ends (φ alone is ill-conditioned when cos s → 0).
    for (double t : {0.0, 1.0}) {
      const auto cos_alpha = [t](const kb::SpanCircle& c) {
        return std::cos(to_d(c.phi_left) + t * to_d(c.theta)) * std::cos(to_d(c.s));
      };
      worst = std::max(worst, std::fabs(cos_alpha(general) - cos_alpha(paper)));
    }
    worst = std::max(worst, std::fabs(to_d(general.theta) - to_d(paper.theta)));
  }
  std::printf("span circle, general O vs rotated to z: max |Δ cos α|, |Δθ| %.3g\n", worst);
  // Measured 3.5e-9 (`kb_geometry_test --gtest_filter=*AnyO*`): both sides round their inputs
  // to q1_30 separately. Pinned at 1.5e-8.
  EXPECT_LT(worst, 1.5e-8);
}

// R(N→O): takes N onto O and keeps angles, so angle(R·L, O) = angle(N, L) (the one-vector
// identity, Kuijk-Blake Figure 9); including N = O, N = −O and N near −O.
TEST(KbGeometry, RotationToOKeepsTheAngle) {
  std::mt19937_64 rng(7);
  double worst_map = 0, worst_angle = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    dvec3 n = random_unit(rng);
    const dvec3 o = trial % 4 == 0 ? dvec3{0, 0, 1} : random_unit(rng);
    if (trial % 50 == 1) n = o;
    if (trial % 50 == 2) n = -o;
    if (trial % 50 == 3) n = glm::normalize(-o + dvec3{1e-7, -2e-7, 0});
    const dvec3 l = random_unit(rng);
    const kb::Rotation r = kb::rotation_to(unit(n), unit(o));
    worst_map = std::max(worst_map, max_abs(to_d(kb::rotate(r, unit(n))) - to_d(unit(o))));
    const dvec3 v = to_d(kb::rotate(r, unit(l)));
    worst_angle = std::max(worst_angle, std::fabs(glm::dot(v, to_d(unit(o))) -
                                                  glm::dot(to_d(unit(n)), to_d(unit(l)))));
    EXPECT_NEAR(glm::length(v), 1.0, 1e-8);
  }
  std::printf("rotation to O: max |R·N − O| %.3g, max |Δ cos| %.3g\n", worst_map, worst_angle);
  // Measured 2.8e-9 and 2.7e-9 (`kb_geometry_test --gtest_filter=*RotationToO*`); pinned at 1e-8.
  EXPECT_LT(worst_map, 1e-8);
  EXPECT_LT(worst_angle, 1e-8);
}
