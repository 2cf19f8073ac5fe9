// q.hpp conventions: rounding to nearest with ties away from zero (symmetric for negatives),
// saturation of convert / add_sat / mul_sat, exactness of mul_wide.
#include <gtest/gtest.h>

#include <cstdint>

#include "fixedpoint/cordic.hpp"
#include "fixedpoint/q.hpp"
#include "fixedpoint/sqrt.hpp"
#include "fixedpoint/wide.hpp"
#include "tests/fixedpoint/input_sets.hpp"

namespace fx = tp::fx;
using q7_8 = fx::Q<7, 8, std::int16_t>;
using q3_4 = fx::Q<3, 4, std::int16_t>;

TEST(Q, ConvertRoundsTiesAwayFromZero) {
  // Q7.8 -> Q3.4 drops 4 bits: raw 8 is exactly half an output LSB.
  EXPECT_EQ(fx::convert<q3_4>(q7_8::from_raw(8)).raw(), 1);
  EXPECT_EQ(fx::convert<q3_4>(q7_8::from_raw(-8)).raw(), -1);
  EXPECT_EQ(fx::convert<q3_4>(q7_8::from_raw(7)).raw(), 0);
  EXPECT_EQ(fx::convert<q3_4>(q7_8::from_raw(-7)).raw(), 0);
  EXPECT_EQ(fx::convert<q3_4>(q7_8::from_raw(24)).raw(), 2);  // 1.5 LSB -> 2
  EXPECT_EQ(fx::convert<q3_4>(q7_8::from_raw(-24)).raw(), -2);
}

TEST(Q, ConvertIsOddSymmetricAndNearestExhaustive16) {
  // Every Q7.8 raw into Q3.4: |err| <= 1/2 LSB, and round(-x) == -round(x) except where the
  // negative side saturates at min() (the range is asymmetric).
  for (std::int64_t r : fx::testing::exhaustive16()) {
    const auto x = q7_8::from_raw(static_cast<std::int16_t>(r));
    const auto y = fx::convert<q3_4>(x);
    const long double err = fx::testing::err_lsb(y, fx::testing::to_ld(x));
    ASSERT_LE(std::fabs(err), 0.5L) << r;
    if (r != -32768) {
      const auto yn = fx::convert<q3_4>(q7_8::from_raw(static_cast<std::int16_t>(-r)));
      if (y != q3_4::min() && yn != q3_4::min()) {
        ASSERT_EQ(yn.raw(), -y.raw()) << r;
      }
    }
  }
}

TEST(Q, ConvertSaturates) {
  EXPECT_EQ(fx::convert<q3_4>(q7_8::from_int(100)), q3_4::max());
  EXPECT_EQ(fx::convert<q3_4>(q7_8::from_int(-100)), q3_4::min());
  EXPECT_EQ(fx::convert<q3_4>(q7_8::from_int(-8)), q3_4::min());  // exactly min: no saturation
  EXPECT_EQ(fx::convert<q3_4>(q7_8::from_int(-8)).raw(), -128);
  bool sat = false;
  (void)fx::convert_checked<q3_4>(q7_8::from_int(8), sat);
  EXPECT_TRUE(sat);
  (void)fx::convert_checked<q3_4>(q7_8::from_int(7), sat);
  EXPECT_FALSE(sat);
  // Widening into more fractional bits saturates instead of shifting bits away.
  EXPECT_EQ(fx::convert<fx::q1_30>(fx::q15_16::from_int(30000)), fx::q1_30::max());
  EXPECT_EQ(fx::convert<fx::q1_30>(fx::q15_16::from_int(-30000)), fx::q1_30::min());
}

TEST(Q, SaturatingAddSubNegMul) {
  const auto mx = fx::q15_16::max(), mn = fx::q15_16::min(), one = fx::q15_16::one();
  EXPECT_EQ(fx::add_sat(mx, one), mx);
  EXPECT_EQ(fx::sub_sat(mn, one), mn);
  EXPECT_EQ(fx::neg_sat(mn), mx);
  EXPECT_EQ(fx::abs_sat(mn), mx);
  EXPECT_EQ(fx::mul_sat<fx::q15_16>(mx, mx), mx);
  EXPECT_EQ(fx::mul_sat<fx::q15_16>(mx, mn), mn);
  EXPECT_EQ(fx::mul_sat<fx::q15_16>(mn, mn), mx);
  EXPECT_EQ(fx::add_sat(one, one).raw(), 2 << 16);
}

TEST(Q, MulWideIsExactOnEdgePairs) {
  const auto e = fx::testing::edge32();
  for (std::int64_t a : e)
    for (std::int64_t b : e) {
      const auto p = fx::mul_wide(fx::q1_30::from_raw(static_cast<std::int32_t>(a)),
                                  fx::q15_16::from_raw(static_cast<std::int32_t>(b)));
      static_assert(decltype(p)::frac_bits == 46 && decltype(p)::int_bits == 16);
      ASSERT_EQ(p.raw(), a * b);
    }
}

TEST(Q, MulSatRoundsTiesAwayFromZero) {
  // 2^-8 * 2^-1 = 2^-9: exactly half a Q7.8 LSB.
  const auto lsb = q7_8::from_raw(1), half = q7_8::from_raw(128);
  EXPECT_EQ(fx::mul_sat<q7_8>(lsb, half).raw(), 1);
  EXPECT_EQ(fx::mul_sat<q7_8>(-lsb, half).raw(), -1);
  EXPECT_EQ(fx::mul_sat<q7_8>(q7_8::from_raw(3), half).raw(), 2);  // 1.5 -> 2
  EXPECT_EQ(fx::mul_sat<q7_8>(q7_8::from_raw(-3), half).raw(), -2);
}

TEST(Q, FromRatioAndConstants) {
  EXPECT_EQ(fx::q1_30::from_ratio(1, 3).raw(), 357913941);
  EXPECT_EQ(fx::q1_30::from_ratio(-1, 3).raw(), -357913941);
  EXPECT_EQ(q7_8::from_ratio(1, 512).raw(), 1);  // tie -> away
  EXPECT_EQ(q7_8::from_ratio(-1, 512).raw(), -1);
  EXPECT_EQ(fx::q1_30::from_int(2), fx::q1_30::max());  // 2 is outside [-2, 2)
  EXPECT_EQ(fx::q1_30::from_int(-2).raw(), INT32_MIN);
}

// The public raw-integer vocabulary (fixedpoint/q.hpp, wide.hpp, sqrt.hpp, cordic.hpp).
TEST(Q, RawVocabulary) {
  EXPECT_EQ(fx::round_shift_right(5, 1), 3);    // 2.5 -> 3
  EXPECT_EQ(fx::round_shift_right(-5, 1), -3);  // -2.5 -> -3: ties away from zero
  EXPECT_EQ(fx::round_shift_right(-4, 1), -2);
  EXPECT_EQ(fx::round_shift_right(7, 0), 7);
  EXPECT_EQ(fx::clamp(-3, 0, 10), 0);
  EXPECT_EQ(fx::clamp(11, 0, 10), 10);
  EXPECT_EQ(fx::clamp(4, 0, 10), 4);
  // Every width from 0 to 64 at both ends of its range.
  EXPECT_EQ(fx::bit_width(0), 0);
  for (int w = 1; w <= 64; ++w) {
    const std::uint64_t low = std::uint64_t{1} << (w - 1);
    EXPECT_EQ(fx::bit_width(low), w);
    EXPECT_EQ(fx::bit_width(low | (low - 1)), w);
  }
  // 3·2^61 · 3 / 2^62 = 4.5 -> 5, and its negative -> -5; beyond 64 bits in between.
  EXPECT_EQ(fx::mul_shift_right(std::int64_t{3} << 61, 3, 62), 5);
  EXPECT_EQ(fx::mul_shift_right(-(std::int64_t{3} << 61), 3, 62), -5);
  EXPECT_EQ(fx::isqrt_floor(0), 0u);
  EXPECT_EQ(fx::isqrt_floor(99), 9u);
  EXPECT_EQ(fx::isqrt_floor(100), 10u);
  EXPECT_EQ(fx::isqrt_floor(~std::uint64_t{0}), 0xffffffffu);
  fx::Sum128 s;
  s.add_product(INT64_MAX, INT64_MAX);  // 2^126 − 2^64 + 1
  s.add_product(-INT64_MAX, INT64_MAX);
  EXPECT_EQ(s.sign(), 0);
  s.add_product(-1, 1);
  EXPECT_EQ(s.sign(), -1);
  // The sum rounded once: 2^62 · 3 + 2^62 · 3 = 6 · 2^62, beyond 64 bits, / 2^62 -> 6; a
  // negative total rounds its tie away from zero; a quotient beyond 63 bits is flagged.
  bool over = false;
  fx::Sum128 t;
  t.add_product(std::int64_t{1} << 62, 3);
  t.add_product(std::int64_t{1} << 62, 3);
  EXPECT_EQ(t.shifted(62, over), 6);
  EXPECT_FALSE(over);
  fx::Sum128 u;
  u.add_product(-5, std::int64_t{1} << 40);  // −5 · 2^40 / 2^41 = −2.5 -> −3
  EXPECT_EQ(u.shifted(41, over), -3);
  EXPECT_FALSE(over);
  EXPECT_EQ(t.shifted(0, over), INT64_MAX);
  EXPECT_TRUE(over);
  // π, π/2 and 2π in the angle format: round(π·2^29) and its half and double, rounded.
  EXPECT_EQ(fx::pi().raw(), 1686629713);
  EXPECT_EQ(fx::half_pi().raw(), 843314857);
  EXPECT_EQ(fx::two_pi_raw(), 3373259426);
  EXPECT_EQ(fx::atan2_fast(std::int64_t{1} << 40, std::int64_t{1} << 40).raw(),
            fx::atan2_fast(fx::q1_30::one(), fx::q1_30::one()).raw());  // any common scale
}
