// CORDIC: singular and exact cases, symmetry, range reduction. Accuracy bounds over the full
// input sets are in test_trig_accuracy.cpp.
#include <gtest/gtest.h>

#include <cmath>

#include "fixedpoint/cordic.hpp"
#include "tests/fixedpoint/input_sets.hpp"

namespace fx = tp::fx;
using fx::testing::err_lsb;
using fx::testing::to_ld;

TEST(Cordic, Atan2OfZeroIsZero) {
  EXPECT_EQ(fx::atan2(fx::q15_16::zero(), fx::q15_16::zero()), fx::angle_t::zero());
  EXPECT_EQ(fx::to_polar(fx::q15_16::zero(), fx::q15_16::zero()).magnitude, fx::q15_16::zero());
  EXPECT_EQ(fx::to_polar(fx::q15_16::zero(), fx::q15_16::zero()).angle, fx::angle_t::zero());
}

TEST(Cordic, Atan2AxesAndQuadrants) {
  const auto one = fx::q15_16::one(), z = fx::q15_16::zero();
  const fx::angle_t pi = fx::angle_t::from_raw(tp::tables::pi_q2_29);
  EXPECT_EQ(fx::atan2(z, one), fx::angle_t::zero());
  EXPECT_EQ(fx::atan2(z, -one), pi) << "atan2(0, x<0) = +pi";
  EXPECT_EQ(fx::atan2(one, z).raw(), (tp::tables::pi_q2_29 + 1) / 2);
  EXPECT_EQ(fx::atan2(-one, z).raw(), -(tp::tables::pi_q2_29 + 1) / 2);
  // Odd in y, exactly (vectoring is symmetric under y -> -y).
  for (std::int64_t y : fx::testing::edge32())
    for (std::int64_t x : {std::int64_t{1}, std::int64_t{-77}, std::int64_t{65536}}) {
      if (y == INT32_MIN) continue;
      const auto Y = fx::q15_16::from_raw(static_cast<std::int32_t>(y));
      const auto X = fx::q15_16::from_raw(static_cast<std::int32_t>(x));
      if (y == 0 && x < 0) continue;  // +pi by convention
      ASSERT_EQ(fx::atan2(-Y, X).raw(), -fx::atan2(Y, X).raw()) << y << "," << x;
    }
}

TEST(Cordic, SinCosSpecialAngles) {
  const auto sc0 = fx::sin_cos(fx::angle_t::zero());
  EXPECT_LE(std::abs(sc0.sin.raw()), 1);
  EXPECT_GE(sc0.cos.raw(), (1 << 30) - 1);
  // Range ends: angle_t min() = -4 and max() ~ 4 (beyond ±π) reduce correctly.
  for (auto a :
       {fx::angle_t::min(), fx::angle_t::max(), fx::angle_t::from_raw(tp::tables::pi_q2_29),
        fx::angle_t::from_raw(-tp::tables::pi_q2_29)}) {
    const auto sc = fx::sin_cos(a);
    EXPECT_LE(std::fabs(err_lsb(sc.sin, std::sin(to_ld(a)))), 0.503L) << a.raw();
    EXPECT_LE(std::fabs(err_lsb(sc.cos, std::cos(to_ld(a)))), 0.503L) << a.raw();
  }
  // sin^2 + cos^2 stays 1 within a few LSB over a sweep (no gain error).
  for (std::int64_t r = -(std::int64_t{1} << 31); r < (std::int64_t{1} << 31); r += 12345677) {
    const auto sc = fx::sin_cos(fx::angle_t::from_raw(static_cast<std::int32_t>(r)));
    const long double s = to_ld(sc.sin), c = to_ld(sc.cos);
    ASSERT_NEAR(static_cast<double>(s * s + c * c), 1.0, 4e-9) << r;
  }
}

TEST(Cordic, AcosUnitEndsAndClamp) {
  const fx::angle_t pi = fx::angle_t::from_raw(tp::tables::pi_q2_29);
  EXPECT_EQ(fx::acos_unit(fx::q1_30::one()), fx::angle_t::zero());
  EXPECT_EQ(fx::acos_unit(-fx::q1_30::one()), pi);
  EXPECT_EQ(fx::acos_unit(fx::q1_30::max()), fx::angle_t::zero()) << "c > 1 clamps to 1";
  EXPECT_EQ(fx::acos_unit(fx::q1_30::min()), pi) << "c < -1 clamps to -1";
  EXPECT_EQ(fx::acos_unit(fx::q1_30::zero()).raw(), (tp::tables::pi_q2_29 + 1) / 2);
}

TEST(Cordic, ToPolarMagnitudeExactCasesAndSaturation) {
  const auto m = fx::to_polar(fx::q15_16::from_int(3), fx::q15_16::from_int(-4));
  EXPECT_EQ(m.magnitude, fx::q15_16::from_int(5));
  EXPECT_LE(std::fabs(err_lsb(m.angle, std::atan2(-4.0L, 3.0L))), 0.503L);
  // |(max, max)| = sqrt(2) * 2^15 does not fit Q15.16: saturates.
  EXPECT_EQ(fx::to_polar(fx::q15_16::max(), fx::q15_16::max()).magnitude, fx::q15_16::max());
  EXPECT_EQ(fx::to_polar(fx::q15_16::min(), fx::q15_16::zero()).magnitude, fx::q15_16::max());
}

// The setup-grade variants (8 CORDIC steps + closed-form residual): max error over sweeps of
// every quadrant and of tiny / huge arguments, in LSB of the output.
TEST(CordicFast, Atan2AndSinCosMatchTheFullCordic) {
  long double worst_atan = 0, worst_sin = 0, worst_cos = 0;
  int differ = 0, total = 0;
  std::uint64_t state = 12345;
  const auto next = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<std::int32_t>(state >> 32);
  };
  for (int i = 0; i < 200000; ++i) {
    std::int32_t y = next(), x = next();
    const int sh = i % 31;  // also small magnitudes and very unequal components
    if (i % 3 == 1) y >>= sh;
    if (i % 3 == 2) x >>= sh;
    const auto Y = fx::q1_30::from_raw(y), X = fx::q1_30::from_raw(x);
    const fx::angle_t a = fx::atan2_fast(Y, X);
    if (x == 0 && y == 0) {
      EXPECT_EQ(a.raw(), 0);
      continue;
    }
    worst_atan = std::max(
        worst_atan, std::fabs(err_lsb(
                        a, std::atan2(static_cast<long double>(y), static_cast<long double>(x)))));
    differ += a.raw() != fx::atan2(Y, X).raw();
    ++total;
    const fx::angle_t t = fx::angle_t::from_raw(next());
    const auto sc = fx::sin_cos_fast(t);
    worst_sin = std::max(worst_sin, std::fabs(err_lsb(sc.sin, std::sin(to_ld(t)))));
    worst_cos = std::max(worst_cos, std::fabs(err_lsb(sc.cos, std::cos(to_ld(t)))));
  }
  std::printf(
      "atan2_fast max %.6Lf LSB (%d of %d differ from atan2); sin_cos_fast max sin %.6Lf, cos "
      "%.6Lf LSB\n",
      worst_atan, differ, total, worst_sin, worst_cos);
  EXPECT_LE(worst_atan, 0.506L);
  EXPECT_LE(worst_sin, 0.506L);
  EXPECT_LE(worst_cos, 0.506L);
  EXPECT_EQ(fx::atan2_fast(fx::q1_30::zero(), fx::q1_30::one()).raw(), 0);
  EXPECT_EQ(fx::atan2_fast(fx::q1_30::zero(), -fx::q1_30::one()),
            fx::angle_t::from_raw(tp::tables::pi_q2_29));
}

// sqrt's e = 0 path (isqrt_plain) gives exactly what the general digit-by-digit root gives.
TEST(SqrtPlain, IdenticalToTheGeneralRoot) {
  std::uint64_t state = 987654321;
  for (int i = 0; i < 300000; ++i) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    const std::uint64_t u = i < 1000 ? static_cast<std::uint64_t>(i) : state >> (i % 40);
    for (std::uint64_t limit :
         {std::uint64_t{1} << 31, std::uint64_t{1} << 20, ~std::uint64_t{0} >> 5}) {
      const auto a = fx::detail::isqrt_plain(u, limit);
      const auto b = fx::detail::isqrt_shifted(u, 0, limit);
      ASSERT_EQ(a.over, b.over) << u;
      if (a.over) continue;
      ASSERT_EQ(a.root, b.root) << u;
      ASSERT_EQ(a.round_up, b.round_up) << u;
    }
  }
}

// sin_cos_fast's 8 rotation steps: the size build's own loop (word-by-word shifts) against the
// shared step loop, bit for bit. In the speed build both are rotation_steps; the size build's
// copy of this test (fixedpoint_size_build_test) is the one that compares two loops.
TEST(CordicFast, TheFastRotationStepsAreTheSharedSteps) {
  namespace d = fx::detail;
  std::uint64_t state = 24680;
  for (int i = 0; i < 100000; ++i) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    // sin_cos_fast's inputs: z reduced to [−π/2, π/2] in Q60, x the gain's inverse, y zero; and
    // wider x and y of either sign, for the shifts' carries between the words.
    d::wide_t z = static_cast<d::wide_t>(state) >> 2;
    d::reduce_to_half_pi(z);
    d::wide_t x = tp::tables::cordic_fast_gain_inv_q60, y = 0;
    if (i % 2 == 1) {
      x = static_cast<d::wide_t>(state * 0x9e3779b97f4a7c15ULL) >> 4;  // |.| < 2^60: the
      y = static_cast<d::wide_t>(state * 0xc2b2ae3d27d4eb4fULL) >> 4;  // gain 1.65 fits
    }
    d::wide_t x1 = x, y1 = y, z1 = z;
    d::fast_rotation_steps(x1, y1, z1);
    d::rotation_steps<false>(x, y, z, d::kFastIterations);
    ASSERT_EQ(x1, x) << i;
    ASSERT_EQ(y1, y) << i;
    ASSERT_EQ(z1, z) << i;
  }
}

// sin_cos_fast's z³/6 by two 32-bit divisions equals the 64-bit division over its whole domain's
// edges and a million random pairs (0 <= u < 2^16, |v| <= 2^23).
TEST(CordicFast, TheProductOverSixIsTheDivision) {
  namespace d = fx::detail;
  const auto check = [](d::wide_t u, d::wide_t v) {
    ASSERT_EQ(d::product_over_6_by_halves(u, v), u * v / 6) << u << " * " << v;
    ASSERT_EQ(d::product_over_6(u, v), u * v / 6) << u << " * " << v;
  };
  const d::wide_t vmax = (d::wide_t{1} << 23) - 1;
  for (d::wide_t u = 0; u < 64; ++u)
    for (d::wide_t v :
         {-vmax, -vmax + 1, d::wide_t{-7}, d::wide_t{-6}, d::wide_t{-5}, d::wide_t{-1},
          d::wide_t{0}, d::wide_t{1}, d::wide_t{5}, d::wide_t{6}, d::wide_t{7}, vmax - 1, vmax}) {
      check(u, v);
      check((d::wide_t{1} << 16) - 1 - u, v);
    }
  std::uint64_t state = 13579;
  for (int i = 0; i < 1000000; ++i) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    const auto u = static_cast<d::wide_t>(state >> 48);                             // [0, 2^16)
    const auto v = static_cast<d::wide_t>(static_cast<std::int64_t>(state) >> 40);  // [-2^23, 2^23)
    check(u, v);
  }
}
