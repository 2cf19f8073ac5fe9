// Vec3: dot/cross exactness, normalize on exact cases, the zero-vector convention, saturation;
// the sample-grade normalize_fast against the exact direction.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>

#include "fixedpoint/normalize_fast.hpp"
#include "fixedpoint/vec3.hpp"

namespace fx = tp::fx;
using v30 = fx::Vec3<fx::q1_30>;

namespace {
fx::q1_30 r30(std::int64_t r) { return fx::q1_30::from_raw(static_cast<std::int32_t>(r)); }
}  // namespace

TEST(Vec3, NormalizeZeroVectorIsZero) {
  const v30 z{fx::q1_30::zero(), fx::q1_30::zero(), fx::q1_30::zero()};
  EXPECT_EQ(fx::normalize<fx::q1_30>(z), z);
  v30 out{fx::q1_30::one(), fx::q1_30::one(), fx::q1_30::one()};
  EXPECT_FALSE(fx::try_normalize(z, out));
  EXPECT_EQ(out.x, fx::q1_30::one()) << "out is left untouched";
}

TEST(Vec3, NormalizeExactCases) {
  // (3, 4, 0) * 2^-k and (2, -1, 2)/3-type Pythagorean vectors normalise exactly (to 1/2 LSB).
  for (int k = 0; k <= 26; ++k) {
    const v30 v{r30(3 << k), r30(-(4 << k)), r30(0)};
    const auto n = fx::normalize<fx::q1_30>(v);
    ASSERT_EQ(n.x, fx::q1_30::from_ratio(3, 5)) << k;
    ASSERT_EQ(n.y, fx::q1_30::from_ratio(-4, 5)) << k;
    ASSERT_EQ(n.z, fx::q1_30::zero()) << k;
  }
  const v30 v{r30(2), r30(-1), r30(2)};
  const auto n = fx::normalize<fx::q1_30>(v);
  EXPECT_EQ(n.x, fx::q1_30::from_ratio(2, 3));
  EXPECT_EQ(n.y, fx::q1_30::from_ratio(-1, 3));
  // Axis vectors of any length, including the most negative component.
  EXPECT_EQ(fx::normalize<fx::q1_30>(v30{fx::q1_30::min(), r30(0), r30(0)}).x, -fx::q1_30::one());
  EXPECT_EQ(fx::normalize<fx::q1_30>(v30{r30(0), r30(1), r30(0)}).y, fx::q1_30::one());
  // Largest input: all components min() (|v|^2 = 3 * 2^62 uses the full u64 range).
  const auto m =
      fx::normalize<fx::q1_30>(v30{fx::q1_30::min(), fx::q1_30::min(), fx::q1_30::min()});
  EXPECT_EQ(m.x, fx::q1_30::from_raw(-619925131));  // -2^30 / sqrt(3) = -619925130.57
}

TEST(Vec3, NormalizeIntoNarrowFormat) {
  using q1_14 = fx::q1_14;
  const auto n = fx::normalize<q1_14>(v30{r30(1 << 20), r30(1 << 20), r30(0)});
  EXPECT_EQ(n.x.raw(), 11585);  // 2^14 / sqrt(2) = 11585.24
  EXPECT_EQ(n.y.raw(), 11585);
}

TEST(Vec3, DotIsExactWithOneRounding) {
  const v30 ones{fx::q1_30::one(), fx::q1_30::one(), fx::q1_30::one()};
  using q3_28 = fx::Q<3, 28>;
  using q4_27 = fx::Q<4, 27>;
  EXPECT_EQ(fx::dot<q3_28>(ones, ones).raw(), 3 << 28);
  // Saturation instead of wrap: 3 * 4 = 12 does not fit Q1.30; products would overflow int64.
  const v30 mins{fx::q1_30::min(), fx::q1_30::min(), fx::q1_30::min()};
  EXPECT_EQ(fx::dot<fx::q1_30>(mins, mins), fx::q1_30::max());
  EXPECT_EQ(fx::dot<q4_27>(mins, mins).raw(), 12 << 27);
  // -3 * 2^31 * (2^31 - 1) / 2^33 = -1610612735.25 -> -1610612735.
  EXPECT_EQ(fx::dot<q4_27>(mins, fx::neg_sat(mins)).raw(), -1610612735);
  // Two half-LSB terms sum exactly to one LSB (a per-term rounding would give 0 or 2).
  using q7_8 = fx::Q<7, 8, std::int16_t>;
  const fx::Vec3<q7_8> a{q7_8::from_raw(1), q7_8::from_raw(1), q7_8::zero()};
  const fx::Vec3<q7_8> h{q7_8::from_raw(128), q7_8::from_raw(128), q7_8::zero()};
  EXPECT_EQ(fx::dot<q7_8>(a, h).raw(), 1);
  EXPECT_EQ(fx::dot<q7_8>(fx::neg_sat(a), h).raw(), -1);
}

TEST(Vec3, CrossOfAxes) {
  const auto one = fx::q1_30::one(), zero = fx::q1_30::zero();
  const v30 x{one, zero, zero}, y{zero, one, zero}, z{zero, zero, one};
  EXPECT_EQ(fx::cross<fx::q1_30>(x, y), z);
  EXPECT_EQ(fx::cross<fx::q1_30>(y, z), x);
  EXPECT_EQ(fx::cross<fx::q1_30>(z, x), y);
  EXPECT_EQ(fx::cross<fx::q1_30>(y, x), fx::neg_sat(z));
}

TEST(Vec3, AddSubScaleSaturate) {
  const auto mx = fx::q1_30::max(), one = fx::q1_30::one();
  const v30 a{mx, -one, one}, b{one, -one, -one};
  EXPECT_EQ(fx::add_sat(a, b), (v30{mx, fx::q1_30::from_int(-2), fx::q1_30::zero()}));
  EXPECT_EQ(fx::sub_sat(b, a).x, fx::sub_sat(one, mx));
  const auto s = fx::scale<fx::q1_30>(a, fx::q15_16::from_int(2));
  EXPECT_EQ(s.x, mx);
  EXPECT_EQ(s.y, fx::q1_30::min());
}

// normalize_fast (fixedpoint/normalize_fast.hpp): against the double-precision direction over
// 1,000,000 random vectors of every magnitude from 2^0 to 2^61. Measured: at most 1.725 LSB
// of Q1.30 per component (2026-12-04, the interpolated seed; this test's own printout);
// pinned at 2.5.
TEST(NormalizeFast, WithinTwoAndAHalfLsbOfTheExactDirection) {
  std::mt19937_64 rng(1);
  double worst = 0;
  for (int i = 0; i < 1000000; ++i) {
    const int shift = static_cast<int>(rng() % 62);
    const auto component = [&](int s) {
      const auto m = static_cast<std::int64_t>(rng() >> (2 + s));
      return (rng() & 1) != 0 ? m : -m;
    };
    const std::int64_t x = component(shift % 40), y = component(shift % 40),
                       z = component(static_cast<int>(rng() % 62));
    const double l = std::sqrt(static_cast<double>(x) * static_cast<double>(x) +
                               static_cast<double>(y) * static_cast<double>(y) +
                               static_cast<double>(z) * static_cast<double>(z));
    if (l == 0) continue;
    const v30 n = fx::normalize_fast(x, y, z);
    const double one = 1073741824.0;
    worst = std::max({worst, std::fabs(n.x.raw() - static_cast<double>(x) / l * one),
                      std::fabs(n.y.raw() - static_cast<double>(y) / l * one),
                      std::fabs(n.z.raw() - static_cast<double>(z) / l * one)});
  }
  std::printf("normalize_fast: worst %.3f LSB\n", worst);
  EXPECT_LE(worst, 2.5);
}

TEST(NormalizeFast, ZeroAndAxes) {
  EXPECT_EQ(fx::normalize_fast(0, 0, 0), (v30{r30(0), r30(0), r30(0)}));
  // Axis vectors of any length come out within 1 LSB of the unit axis (Newton from the seed
  // truncates): measured 1073741823 or 1073741824.
  for (const std::int64_t len : {std::int64_t{1}, std::int64_t{3}, std::int64_t{5},
                                 std::int64_t{1} << 30, std::int64_t{1} << 61}) {
    for (int axis = 0; axis < 3; ++axis)
      for (const std::int64_t sign : {std::int64_t{1}, std::int64_t{-1}}) {
        const std::int64_t c[3] = {axis == 0 ? sign * len : 0, axis == 1 ? sign * len : 0,
                                   axis == 2 ? sign * len : 0};
        const v30 n = fx::normalize_fast(c[0], c[1], c[2]);
        const std::int64_t got[3] = {n.x.raw(), n.y.raw(), n.z.raw()};
        for (int k = 0; k < 3; ++k)
          EXPECT_LE(std::llabs(got[k] - (k == axis ? sign * (std::int64_t{1} << 30) : 0)), 1)
              << len << " axis " << axis;
      }
  }
}
