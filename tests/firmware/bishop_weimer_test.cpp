// Bishop & Weimer's Taylor coefficients (firmware/shade_bishop_weimer.cpp) against a numerical
// expansion of the exact function they approximate, f(u, v) = D·N(u, v) / |N(u, v)| with the
// screen-linear normal N(u, v) = C + A u + B v, and of their finite-eye form
// f(u, v) = N(u, v)·D(u, v) / (|N(u, v)| |D(u, v)|) with D screen-linear too: the expansion is
// exact at the centre, and its six coefficients are f's derivatives there (central differences
// in double).
#include <gtest/gtest.h>

#include <array>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>

#include <glm/glm.hpp>

#include "firmware/methods.hpp"

namespace tp::fw {
namespace {

using glm::dvec3;
constexpr int kF = BishopWeimerMethod::kCoeffFrac;
constexpr double kUnit = static_cast<double>(std::int64_t{1} << kF);

std::int64_t fixed(double v) { return std::llround(v * kUnit); }

// A direction uniformly distributed on the sphere (rejection from the cube).
dvec3 random_direction(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  dvec3 v;
  do v = dvec3(unit(rng), unit(rng), unit(rng));
  while (glm::length(v) < 0.2 || glm::length(v) > 1.0);
  return glm::normalize(v);
}

struct Case {
  dvec3 c, a, b, d;
};

double f(const Case& k, double u, double v) {
  const dvec3 n = k.c + u * k.a + v * k.b;
  return glm::dot(k.d, n) / glm::length(n);
}

// f's second-order Taylor coefficients at (0, 0) by central differences, {f, f_u, f_v, f_uu / 2,
// f_uv, f_vv / 2}: steps h for the first derivatives, g for the second (their rounding error
// ~eps/g² would otherwise dominate; the truncation error is g² times the fourth derivatives).
template <class F>
std::array<double, 6> numerical_taylor(const F& f, double h, double g) {
  const double f00 = f(0, 0);
  return {f00,
          (f(h, 0) - f(-h, 0)) / (2 * h),
          (f(0, h) - f(0, -h)) / (2 * h),
          (f(g, 0) - 2 * f00 + f(-g, 0)) / (2 * g * g),
          (f(g, g) - f(g, -g) - f(-g, g) + f(-g, -g)) / (4 * g * g),
          (f(0, g) - 2 * f00 + f(0, -g)) / (2 * g * g)};
}

// The largest error of the six coefficients against the numerical ones, relative to the size
// of each derivative's scale (|A|, |A|² ...) over random cases of the given curvature.
TEST(BishopWeimer, CoefficientsMatchANumericalTaylorExpansion) {
  std::mt19937_64 rng(20261203);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto random_unit = [&rng] { return random_direction(rng); };
  double worst[6] = {0, 0, 0, 0, 0, 0};
  for (int i = 0; i < 2000; ++i) {
    // Curvature: the normal turns by up to ~0.05 rad per pixel (a 20-pixel triangle whose
    // normals are a radian apart); the centre's normal a mean of unit normals (|C| in [0.8, 1]).
    const double step = 0.05 * (i % 10 + 1) / 10.0;
    Case k{random_unit() * (0.8 + 0.2 * (unit(rng) + 1) / 2), random_unit() * step,
           random_unit() * step, random_unit()};
    BishopWeimerMethod::VectorField field{};
    for (int c = 0; c < 3; ++c) {
      field.c[c] = fixed(k.c[c]);
      field.a[c] = fixed(k.a[c]);
      field.b[c] = fixed(k.b[c]);
    }
    const std::int64_t d[3] = {fixed(k.d.x), fixed(k.d.y), fixed(k.d.z)};
    bool saturated = false;
    const BishopWeimerMethod::Taylor t = BishopWeimerMethod::expand(field, d, true, saturated);
    ASSERT_FALSE(saturated);
    // Steps: 1e-3 pixel for the first derivatives, 2e-2 for the second.
    const std::array<double, 6> want =
        numerical_taylor([&k](double u, double v) { return f(k, u, v); }, 1e-3, 2e-2);
    const double got[6] = {t.c0 / kUnit,  t.c1 / kUnit,  t.c2 / kUnit,
                           t.c11 / kUnit, t.c12 / kUnit, t.c22 / kUnit};
    const double scale[6] = {1, step, step, step * step, step * step, step * step};
    for (int j = 0; j < 6; ++j)
      worst[j] = std::max(worst[j], std::abs(got[j] - want[j]) / scale[j]);
  }
  std::printf("worst error / scale: c0 %.3g, c1 %.3g, c2 %.3g, c11 %.3g, c12 %.3g, c22 %.3g\n",
              worst[0], worst[1], worst[2], worst[3], worst[4], worst[5]);
  // c0 is the exact value at the centre (one rsqrt and a product in Q.40): within 2^-30.
  EXPECT_LT(worst[0], std::ldexp(1.0, -30));
  // The others: measured 2026-12-03 2.3e-9 (first order) and 0.8e-6 / 4.4e-6 (second order) of
  // their scale, which is the differences' own truncation error (g² times the fourth
  // derivatives); pinned at 1e-5.
  for (int j = 1; j < 6; ++j) EXPECT_LT(worst[j], 1e-5) << j;
}

// The finite-eye expansion (expand_pair): both vectors vary. D's centre has any length (the
// unnormalised L of a point light; H interpolated between unit vectors is a little short) and
// turns by up to ~0.05 rad per pixel like N.
struct PairCase {
  dvec3 nc, na, nb, dc, da, db;
};

double f_pair(const PairCase& k, double u, double v) {
  const dvec3 n = k.nc + u * k.na + v * k.nb, d = k.dc + u * k.da + v * k.db;
  return glm::dot(n, d) / (glm::length(n) * glm::length(d));
}

BishopWeimerMethod::VectorField field_of(const dvec3& c, const dvec3& a, const dvec3& b) {
  BishopWeimerMethod::VectorField f{};
  for (int k = 0; k < 3; ++k) {
    f.c[k] = fixed(c[k]);
    f.a[k] = fixed(a[k]);
    f.b[k] = fixed(b[k]);
  }
  return f;
}

TEST(BishopWeimerFinite, CoefficientsMatchANumericalTaylorExpansion) {
  std::mt19937_64 rng(20261204);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto random_unit = [&rng] { return random_direction(rng); };
  double worst[6] = {0, 0, 0, 0, 0, 0};
  for (int i = 0; i < 2000; ++i) {
    const double step = 0.05 * (i % 10 + 1) / 10.0;
    const double length = 0.5 + 0.75 * (unit(rng) + 1);  // D's centre: 0.5 .. 2
    const PairCase k{random_unit() * (0.8 + 0.2 * (unit(rng) + 1) / 2),
                     random_unit() * step,
                     random_unit() * step,
                     random_unit() * length,
                     random_unit() * step * length,
                     random_unit() * step * length};
    bool saturated = false;
    const BishopWeimerMethod::Taylor t = BishopWeimerMethod::expand_pair(
        field_of(k.nc, k.na, k.nb), field_of(k.dc, k.da, k.db), true, saturated);
    ASSERT_FALSE(saturated);
    // g smaller than above: with both vectors turning, f's fourth derivatives are larger, and
    // at g = 2e-2 the differences' own truncation error reached 1.2e-5 of c12's scale (it fell
    // 16-fold at g = 5e-3: truncation, g²).
    const std::array<double, 6> want =
        numerical_taylor([&k](double u, double v) { return f_pair(k, u, v); }, 1e-3, 5e-3);
    const double got[6] = {t.c0 / kUnit,  t.c1 / kUnit,  t.c2 / kUnit,
                           t.c11 / kUnit, t.c12 / kUnit, t.c22 / kUnit};
    const double scale[6] = {1, step, step, step * step, step * step, step * step};
    for (int j = 0; j < 6; ++j)
      worst[j] = std::max(worst[j], std::abs(got[j] - want[j]) / scale[j]);
  }
  std::printf("worst error / scale: c0 %.3g, c1 %.3g, c2 %.3g, c11 %.3g, c12 %.3g, c22 %.3g\n",
              worst[0], worst[1], worst[2], worst[3], worst[4], worst[5]);
  EXPECT_LT(worst[0], std::ldexp(1.0, -30));
  // Measured 2026-12-03: 4.4e-9 (first order) and 0.5e-6 / 0.7e-6 (second order) of their
  // scale; pinned at 1e-5 as the single expansion's.
  for (int j = 1; j < 6; ++j) EXPECT_LT(worst[j], 1e-5) << j;
}

// The paper's own finite-eye coefficients T0..T5, in double, against the numerical expansion:
// with its definitions of a..r as printed except m = D·D, n = 2 D·E, o = E·E (the list permutes
// them) and the two errata of its last page applied to T4 (− fjlqr → + fjlqr, − 2f²nr →
// − 2fl²nr), all six agree; as printed, T4 does not. (The firmware does not transcribe them:
// expand_pair derives the same expansion, tested above.)
struct PaperT {
  double t[6];  // T0 .. T5: constant, y, x, y², xy, x²
};
PaperT paper_coefficients(const PairCase& k, bool errata) {
  const dvec3 A = k.na, B = k.nb, C = k.nc, D = k.da, E = k.db, F = k.dc;
  const double a = glm::dot(A, D), b = glm::dot(A, E) + glm::dot(B, D), c = glm::dot(B, E),
               d = glm::dot(A, F) + glm::dot(C, D), e = glm::dot(B, F) + glm::dot(C, E),
               f = glm::dot(C, F), g = glm::dot(A, A), h = 2 * glm::dot(A, B), i = glm::dot(B, B),
               j = 2 * glm::dot(A, C), kk = 2 * glm::dot(B, C), l = glm::dot(C, C),
               m = glm::dot(D, D), n = 2 * glm::dot(D, E), o = glm::dot(E, E),
               p = 2 * glm::dot(D, F), q = 2 * glm::dot(E, F), r = glm::dot(F, F);
  const double root = std::sqrt(l * r);
  PaperT out;
  out.t[0] = f / root;
  out.t[1] = (2 * e * l * r - f * kk * r - f * l * q) / (2 * l * r * root);
  out.t[2] = (2 * d * l * r - f * j * r - f * l * p) / (2 * l * r * root);
  out.t[3] = (8 * c * l * l * r * r - 4 * e * kk * l * r * r - 4 * f * i * l * r * r +
              3 * f * kk * kk * r * r - 4 * e * l * l * q * r + 2 * f * kk * l * q * r -
              4 * f * l * l * o * r + 3 * f * l * l * q * q) /
             (8 * l * l * r * r * root);
  const double fjlqr = f * j * l * q * r;
  const double last = errata ? -2 * f * l * l * n * r : -2 * f * f * n * r;
  out.t[4] = (4 * b * l * l * r * r - 2 * d * kk * l * r * r - 2 * e * j * l * r * r -
              2 * f * h * l * r * r + 3 * f * j * kk * r * r - 2 * d * l * l * q * r +
              (errata ? fjlqr : -fjlqr) - 2 * e * l * l * p * r + f * kk * l * p * r + last +
              3 * f * l * l * p * q) /
             (4 * l * l * r * r * root);
  out.t[5] = (8 * a * l * l * r * r - 4 * d * j * l * r * r - 4 * f * g * l * r * r +
              3 * f * j * j * r * r - 4 * d * l * l * p * r + 2 * f * j * l * p * r -
              4 * f * l * l * m * r + 3 * f * l * l * p * p) /
             (8 * l * l * r * r * root);
  return out;
}

TEST(BishopWeimerFinite, ThePapersCoefficientsNeedItsErrata) {
  std::mt19937_64 rng(1986);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto random_unit = [&rng] { return random_direction(rng); };
  double worst[6] = {0, 0, 0, 0, 0, 0}, printed_t4 = 0;
  for (int s = 0; s < 500; ++s) {
    const double step = 0.05;
    const PairCase k{random_unit(),       random_unit() * step, random_unit() * step,
                     random_unit() * 1.3, random_unit() * step, random_unit() * step};
    // The paper's T1 and T3 are the v terms, T2 and T5 the u terms (its order puts v first).
    const std::array<double, 6> uv =
        numerical_taylor([&k](double u, double v) { return f_pair(k, u, v); }, 1e-3, 5e-3);
    const double want[6] = {uv[0], uv[2], uv[1], uv[5], uv[4], uv[3]};
    const PaperT with = paper_coefficients(k, true), without = paper_coefficients(k, false);
    const double scale[6] = {1, step, step, step * step, step * step, step * step};
    for (int j = 0; j < 6; ++j)
      worst[j] = std::max(worst[j], std::abs(with.t[j] - want[j]) / scale[j]);
    printed_t4 = std::max(printed_t4, std::abs(without.t[4] - want[4]) / scale[4]);
  }
  std::printf(
      "paper's T with errata, worst error / scale: %.3g %.3g %.3g %.3g %.3g %.3g; "
      "printed T4: %.3g\n",
      worst[0], worst[1], worst[2], worst[3], worst[4], worst[5], printed_t4);
  for (int j = 0; j < 6; ++j) EXPECT_LT(worst[j], 1e-5) << j;
  EXPECT_GT(printed_t4, 1e-2);  // as printed, T4 is wrong by far more than the differences' error
}

// With D the same everywhere the pair expansion is the single one (to rounding: it scales the
// fields to unit length first, the single one divides by |N|).
TEST(BishopWeimerFinite, AConstantVectorGivesTheSingleExpansion) {
  const dvec3 c = glm::normalize(dvec3(0.2, 0.3, 0.9)), a(0.01, -0.02, 0.005),
              b(-0.015, 0.01, 0.02);
  const dvec3 dir = glm::normalize(dvec3(0.5, 0.5, 0.7));
  const std::int64_t d[3] = {fixed(dir.x), fixed(dir.y), fixed(dir.z)};
  bool saturated = false;
  const auto single = BishopWeimerMethod::expand(field_of(c, a, b), d, true, saturated);
  // D of length 1.7: the quotient does not see it.
  const auto pair = BishopWeimerMethod::expand_pair(
      field_of(c, a, b), field_of(1.7 * dir, dvec3(0), dvec3(0)), true, saturated);
  EXPECT_FALSE(saturated);
  const std::int64_t one[6] = {single.c0, single.c1, single.c2, single.c11, single.c12, single.c22};
  const std::int64_t two[6] = {pair.c0, pair.c1, pair.c2, pair.c11, pair.c12, pair.c22};
  for (int j = 0; j < 6; ++j)
    EXPECT_NEAR(static_cast<double>(two[j]), static_cast<double>(one[j]), 1024.0) << j;  // 2^-30
}

// A D that turns by more than a unit per pixel (a point light within a pixel of the triangle)
// gets the first-order expansion only, like a steep normal.
TEST(BishopWeimerFinite, ASteepVectorGivesTheFirstOrderOnly) {
  const dvec3 c = glm::normalize(dvec3(0.2, 0.3, 0.9)), a(0.01, -0.02, 0.005),
              b(-0.015, 0.01, 0.02);
  bool saturated = false;
  const auto t = BishopWeimerMethod::expand_pair(
      field_of(c, a, b), field_of(dvec3(0, 0, 0.5), dvec3(0.8, 0, 0), dvec3(0, 0.1, 0)), true,
      saturated);
  EXPECT_EQ(t.c11, 0);
  EXPECT_EQ(t.c12, 0);
  EXPECT_EQ(t.c22, 0);
  EXPECT_NE(t.c1, 0);
  EXPECT_FALSE(saturated);
}

// The seed's printed T5 numerator "3ig² − 4cdi − 4agi" does not scale with the numerator's
// (a, b, c): doubling D must double every coefficient, and does.
TEST(BishopWeimer, CoefficientsScaleWithTheNumerator) {
  BishopWeimerMethod::VectorField field{};
  const dvec3 c = glm::normalize(dvec3(0.2, 0.3, 0.9)), a(0.01, -0.02, 0.005),
              b(-0.015, 0.01, 0.02);
  for (int k = 0; k < 3; ++k) {
    field.c[k] = fixed(c[k]);
    field.a[k] = fixed(a[k]);
    field.b[k] = fixed(b[k]);
  }
  const dvec3 dir = glm::normalize(dvec3(0.5, 0.5, 0.7));
  const std::int64_t d1[3] = {fixed(dir.x / 2), fixed(dir.y / 2), fixed(dir.z / 2)};
  const std::int64_t d2[3] = {2 * d1[0], 2 * d1[1], 2 * d1[2]};
  bool saturated = false;
  const auto t1 = BishopWeimerMethod::expand(field, d1, true, saturated);
  const auto t2 = BishopWeimerMethod::expand(field, d2, true, saturated);
  EXPECT_FALSE(saturated);
  const std::int64_t one[6] = {t1.c0, t1.c1, t1.c2, t1.c11, t1.c12, t1.c22};
  const std::int64_t two[6] = {t2.c0, t2.c1, t2.c2, t2.c11, t2.c12, t2.c22};
  for (int j = 0; j < 6; ++j) EXPECT_NEAR(static_cast<double>(two[j]), 2.0 * one[j], 8.0) << j;
}

}  // namespace
}  // namespace tp::fw
