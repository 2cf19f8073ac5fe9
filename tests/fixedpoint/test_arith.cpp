// div / sqrt / rsqrt: exact cases, rounding ties, saturation and the documented singular results.
// The accuracy bounds over the full input sets are in test_accuracy.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>

#include "fixedpoint/arith.hpp"
#include "fixedpoint/sqrt.hpp"
#include "tests/fixedpoint/input_sets.hpp"

namespace fx = tp::fx;
using q7_8 = fx::Q<7, 8, std::int16_t>;

TEST(Div, ByZeroGivesDocumentedLimits) {
  const auto z = fx::q15_16::zero();
  EXPECT_EQ(fx::div<fx::q15_16>(fx::q15_16::one(), z), fx::q15_16::max());
  EXPECT_EQ(fx::div<fx::q15_16>(fx::q15_16::epsilon(), z), fx::q15_16::max());
  EXPECT_EQ(fx::div<fx::q15_16>(-fx::q15_16::epsilon(), z), fx::q15_16::min());
  EXPECT_EQ(fx::div<fx::q1_30>(fx::q15_16::min(), z), fx::q1_30::min());
  EXPECT_EQ(fx::div<fx::q15_16>(z, z), fx::q15_16::zero());
}

TEST(Div, ExactRoundingAndTies) {
  // 1 LSB / 2 is exactly half an LSB: ties away from zero, symmetric.
  const auto two = q7_8::from_int(2);
  EXPECT_EQ(fx::div<q7_8>(q7_8::from_raw(1), two).raw(), 1);
  EXPECT_EQ(fx::div<q7_8>(q7_8::from_raw(-1), two).raw(), -1);
  EXPECT_EQ(fx::div<q7_8>(q7_8::from_raw(1), -two).raw(), -1);
  EXPECT_EQ(fx::div<q7_8>(q7_8::from_raw(3), two).raw(), 2);
  EXPECT_EQ(fx::div<q7_8>(q7_8::from_raw(5), -two).raw(), -3);
  EXPECT_EQ(fx::div<fx::q15_16>(fx::q15_16::from_int(1), fx::q15_16::from_int(3)).raw(), 21845);
  EXPECT_EQ(fx::div<fx::q15_16>(fx::q15_16::from_int(2), fx::q15_16::from_int(3)).raw(), 43691);
  EXPECT_EQ(fx::div<fx::q15_16>(fx::q15_16::from_int(-2), fx::q15_16::from_int(3)).raw(), -43691);
}

TEST(Div, SaturatesAndHandlesExtremes) {
  EXPECT_EQ(fx::div<fx::q15_16>(fx::q15_16::max(), fx::q15_16::epsilon()), fx::q15_16::max());
  EXPECT_EQ(fx::div<fx::q15_16>(fx::q15_16::min(), fx::q15_16::epsilon()), fx::q15_16::min());
  EXPECT_EQ(fx::div<fx::q15_16>(fx::q15_16::min(), -fx::q15_16::epsilon()), fx::q15_16::max());
  // -2^15 / 1 = -2^15 is exactly representable: no saturation artefact on the negative side.
  EXPECT_EQ(fx::div<fx::q15_16>(fx::q15_16::min(), fx::q15_16::one()), fx::q15_16::min());
  EXPECT_EQ(fx::div<fx::q15_16>(fx::q15_16::max(), fx::q15_16::max()), fx::q15_16::one());
  // Tiny / huge rounds to zero (the shifted divisor leaves 64 bits).
  EXPECT_EQ(fx::div<q7_8>(fx::q1_30::epsilon(), fx::q15_16::max()), q7_8::zero());
  // Output with far more fractional bits than both inputs: 1/3 into Q1.60.
  using q1_60 = fx::Q<1, 60, std::int64_t>;
  EXPECT_EQ(fx::div<q1_60>(q7_8::from_int(1), q7_8::from_int(3)).raw(),
            (std::int64_t{1} << 60) / 3);  // 0.333.. rounds down
}

TEST(Div, OddSymmetricOnEdgePairs) {
  const auto e = fx::testing::edge32();
  for (std::int64_t a : e)
    for (std::int64_t b : e) {
      if (a == INT32_MIN || b == INT32_MIN || b == 0) continue;
      const auto A = fx::q15_16::from_raw(static_cast<std::int32_t>(a));
      const auto B = fx::q15_16::from_raw(static_cast<std::int32_t>(b));
      const auto q = fx::div<fx::q15_16>(A, B), qn = fx::div<fx::q15_16>(-A, B);
      if (q != fx::q15_16::max() && q != fx::q15_16::min()) {  // saturated ends are asymmetric
        ASSERT_EQ(qn.raw(), -q.raw()) << a << "/" << b;
      }
    }
}

TEST(Sqrt, NegativeAndZeroGiveZero) {
  EXPECT_EQ(fx::sqrt<fx::q15_16>(fx::q15_16::from_int(-4)), fx::q15_16::zero());
  EXPECT_EQ(fx::sqrt<fx::q15_16>(fx::q15_16::min()), fx::q15_16::zero());
  EXPECT_EQ(fx::sqrt<fx::q15_16>(-fx::q15_16::epsilon()), fx::q15_16::zero());
  EXPECT_EQ(fx::sqrt<fx::q15_16>(fx::q15_16::zero()), fx::q15_16::zero());
}

TEST(Sqrt, ExactSquaresAndSaturation) {
  for (int i = 0; i <= 181; ++i)
    ASSERT_EQ(fx::sqrt<fx::q15_16>(fx::q15_16::from_int(i * i)), fx::q15_16::from_int(i));
  EXPECT_EQ(fx::sqrt<fx::q1_30>(fx::q15_16::from_int(16)), fx::q1_30::max());  // 4 > 2
  EXPECT_EQ(fx::sqrt<fx::q1_30>(fx::q15_16::from_int(4)), fx::q1_30::max());   // 2 is not in Q1.30
  EXPECT_EQ(fx::sqrt<fx::q1_30>(fx::q1_30::epsilon()).raw(), 32768);           // sqrt(2^-30)
  EXPECT_EQ(fx::sqrt<q7_8>(fx::q1_30::epsilon()), q7_8::zero());               // 2^-15 < half LSB
}

TEST(Rsqrt, NonPositiveGivesMax) {
  EXPECT_EQ(fx::rsqrt<fx::q15_16>(fx::q15_16::zero()), fx::q15_16::max());
  EXPECT_EQ(fx::rsqrt<fx::q15_16>(fx::q15_16::from_int(-1)), fx::q15_16::max());
  EXPECT_EQ(fx::rsqrt<fx::q1_30>(fx::q1_30::min()), fx::q1_30::max());
}

TEST(Rsqrt, PowersOfFourAreExactAndLargeSaturates) {
  for (int k = -7; k <= 7; ++k) {
    // x = 4^k: rsqrt = 2^-k, exact in Q15.16 for k in [-7, 7].
    const auto x = fx::q15_16::from_raw(static_cast<std::int32_t>(std::int64_t{1} << (16 + 2 * k)));
    ASSERT_EQ(fx::rsqrt<fx::q15_16>(x).raw(), std::int64_t{1} << (16 - k)) << k;
  }
  EXPECT_EQ(fx::rsqrt<fx::q1_30>(fx::q15_16::from_ratio(1, 16)), fx::q1_30::max());  // 4 > 2
  // rsqrt(2^-30) = 2^15 is just outside Q15.16; rsqrt(2^-28) = 2^14 is exact.
  EXPECT_EQ(fx::rsqrt<fx::q15_16>(fx::q1_30::epsilon()), fx::q15_16::max());
  EXPECT_EQ(fx::rsqrt<fx::q15_16>(fx::q1_30::from_raw(4)).raw(), std::int64_t{1} << 30);
}

// The roots' shared seed (fixedpoint/sqrt.hpp, rsqrt_seed): 1/√T interpolated between 49 knots.
// Swept over every 2^10-th t of [2^30, 2^32), both ends included: worst relative error
// 3.585·10^-4 (2^-11.45, near T = 1/4), pinned at the bound the Newton-step counts of
// rsqrt_core, rsqrt_fast and isqrt_plain rely on, 2^-11.4 = 3.70·10^-4.
TEST(RsqrtSeed, InterpolationWithinItsBound) {
  long double worst = 0;
  for (std::uint64_t t = std::uint64_t{1} << 30; t < (std::uint64_t{1} << 32); t += 1u << 10) {
    for (const std::uint64_t x : {t, t + (1u << 10) - 1}) {
      const long double seed = fx::detail::rsqrt_seed(static_cast<std::uint32_t>(x)) / 32768.0L;
      const long double rel = std::fabs(seed * std::sqrt(x / 4294967296.0L) - 1.0L);
      worst = rel > worst ? rel : worst;
    }
  }
  std::printf("rsqrt_seed: worst relative error %.4Lg\n", worst);
  EXPECT_LE(worst, 3.70e-4L);
  EXPECT_EQ(fx::detail::rsqrt_seed(std::uint32_t{1} << 30), 65536u);  // 1/√(1/4) = 2, exact
}

// A speed build reads the seed from 64-bit segments (knot with its 2^15, and its fall), a size
// build from the 16-bit knots: the same value for every t, so that both builds' frames are the
// same bits. This test runs in both (fixedpoint_test and fixedpoint_size_build_test) and checks
// each build's seed against the knots' formula at every t whose low 10 bits are 0 or all ones
// (the seed reads t's bits 10..31).
TEST(RsqrtSeed, EveryBuildGivesTheKnotsInterpolation) {
  const auto& knot = fx::detail::rsqrt_knots;
  std::uint64_t mismatches = 0;
  for (std::uint64_t t = std::uint64_t{1} << 30; t < (std::uint64_t{1} << 32); t += 1u << 10) {
    for (const std::uint64_t x : {t, t + (1u << 10) - 1}) {
      const std::size_t k = static_cast<std::size_t>((x >> 26) - 16);
      const std::uint32_t frac = (x >> 10) & 0xffffu;
      const std::uint32_t want =
          (1u << 15) + knot[k] - ((static_cast<std::uint32_t>(knot[k] - knot[k + 1]) * frac) >> 16);
      mismatches += fx::detail::rsqrt_seed(static_cast<std::uint32_t>(x)) != want;
    }
  }
  EXPECT_EQ(mismatches, 0u);
}
