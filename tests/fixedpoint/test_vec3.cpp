// Vec3: dot/cross exactness, normalize on exact cases, the zero-vector convention, saturation.
#include <gtest/gtest.h>

#include <cstdint>

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
  const auto m = fx::normalize<fx::q1_30>(v30{fx::q1_30::min(), fx::q1_30::min(), fx::q1_30::min()});
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
