// Brown's Bézier triangle of N·H (firmware/shade_brown.cpp): the control points reproduce the six
// cosines they are built from, exactly; the evaluation is Brown's eq. 2 to within a rounding;
// the smoothstep's range is the least-squares fit it claims to track, and the cosine format has
// the precision Brown's rule asks for.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>

#include "firmware/lighting.hpp"
#include "firmware/methods.hpp"

namespace tp::fw {
namespace {

constexpr std::int64_t kOne = std::int64_t{1} << 30;
constexpr double kUnit = 1073741824.0;

std::int64_t random_cosine(std::mt19937_64& rng) {
  return std::uniform_int_distribution<std::int64_t>(-kOne, kOne)(rng);
}

// The six points: vertices (1,0,0), (0,1,0), (0,0,1), then the edge midpoints in the order of
// the cosines (edges 0-1, 1-2, 2-0).
constexpr std::int64_t kHalf = kOne / 2;
constexpr std::int64_t kPoints[6][3] = {{kOne, 0, 0},      {0, kOne, 0},      {0, 0, kOne},
                                        {kHalf, kHalf, 0}, {0, kHalf, kHalf}, {kHalf, 0, kHalf}};

TEST(Brown, TheBezierTriangleReproducesItsSixCosinesExactly) {
  std::mt19937_64 rng(20261203);
  for (int i = 0; i < 10000; ++i) {
    std::int64_t c[6];
    for (std::int64_t& v : c) v = random_cosine(rng);
    const BrownMethod::Bezier z = BrownMethod::control_points(c);
    for (int k = 0; k < 6; ++k) ASSERT_EQ(BrownMethod::evaluate(z, kPoints[k]), c[k]) << k;
  }
}

// Brown's eq. 2 in double at random barycentrics: eq. 18's exact sums round once.
TEST(Brown, TheEvaluationIsEquation2) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::int64_t> weight(0, kOne);
  double worst = 0;
  for (int i = 0; i < 10000; ++i) {
    std::int64_t c[6];
    for (std::int64_t& v : c) v = random_cosine(rng);
    const BrownMethod::Bezier z = BrownMethod::control_points(c);
    std::int64_t b[3];
    b[0] = weight(rng);
    b[1] = std::uniform_int_distribution<std::int64_t>(0, kOne - b[0])(rng);
    b[2] = kOne - b[0] - b[1];
    const double b0 = b[0] / kUnit, b1 = b[1] / kUnit, b2 = b[2] / kUnit;
    const double want = (z.c200 * b0 * b0 + z.c020 * b1 * b1 + z.c002 * b2 * b2 + z.d110 * b0 * b1 +
                         z.d011 * b1 * b2 + z.d101 * b2 * b0);
    worst = std::max(worst, std::abs(BrownMethod::evaluate(z, b) - want));
  }
  EXPECT_LE(worst, 0.5 + 1e-6);  // in Q.30 units: one rounding (the double sum's own ~1e-7)
}

// The fitted range: the mean square of s((c − c_lo) / (c_hi − c_lo)) − cos^n over 0..90° is
// within 1 % of the least square that moving c_lo or c_hi finds (a local search in steps of
// 1/64 of the range, down to 2^-12 of it), for exponents across the device's range.
double smoothstep(double c, double lo, double hi) {
  const double t = std::clamp((c - lo) / (hi - lo), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}
double mean_square(std::uint32_t n, double lo, double hi) {
  // The angles where cos^n or the smoothstep can be non-zero, densely: up to 12 / sqrt(n) rad.
  const double top = std::min(1.5707963267948966, n > 4 ? 12 / std::sqrt(double(n)) : 1.6);
  const int samples = 4000;
  double sum = 0;
  for (int i = 0; i <= samples; ++i) {
    const double th = top * i / samples, c = std::cos(th);
    const double d = smoothstep(c, lo, hi) - std::pow(c, n);
    sum += d * d;
  }
  return sum / (samples + 1);
}

TEST(Brown, TheSmoothstepRangeIsTheLeastSquaresFit) {
  for (const std::uint32_t n : {1u, 3u, 10u, 20u, 100u, 1000u, 10000u}) {
    SCOPED_TRACE(n);
    const double lo = BrownMethod::lower_cosine(n) / kUnit,
                 hi = BrownMethod::upper_cosine(n) / kUnit;
    EXPECT_LT(lo, 1.0);
    EXPECT_GT(hi, 1.0);
    const double fitted = mean_square(n, lo, hi);
    double best = fitted, blo = lo, bhi = hi;
    for (double step = (hi - lo) / 64; step > (hi - lo) / 4096; step /= 2) {
      bool moved = true;
      while (moved) {
        moved = false;
        for (const auto& [dl, dh] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
          const double e = mean_square(n, blo + dl * step, bhi + dh * step);
          if (e < best) {
            best = e;
            blo += dl * step;
            bhi += dh * step;
            moved = true;
          }
        }
      }
    }
    std::printf("n %u: c_lo %.6f c_hi %.6f rms %.5f, optimum %.6f %.6f rms %.5f\n", n, lo, hi,
                std::sqrt(fitted), blo, bhi, std::sqrt(best));
    EXPECT_LE(fitted, best * 1.01);
  }
}

// Brown's precision rule, p = log2(2^b / (c_hi − c_lo)) bits for b bits across the smoothstep's
// range (his eq. 17 with c_hi = 1): with b = 8 (our output levels) the cosine needs at most 21
// bits up to n = 10,000; the firmware's cosines are Q1.30, the vectors they come from accurate
// to about 2 units of 2^-30 (normalize_fast), and the Bézier sum rounds once.
TEST(Brown, TheCosineFormatMeetsBrownsPrecisionRule) {
  const double range =
      (BrownMethod::upper_cosine(kMaxExponent) - BrownMethod::lower_cosine(kMaxExponent)) / kUnit;
  const double p = std::log2(256.0 / range);
  std::printf("n = %u: c_hi - c_lo = %.3g, p = %.2f bits\n", kMaxExponent, range, p);
  EXPECT_LT(p, 21.0);
  EXPECT_LE(p + 3, 30.0);  // 3 bits for the cosines' few units of error
}

}  // namespace
}  // namespace tp::fw
