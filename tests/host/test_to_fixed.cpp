// Float -> fixed: rounding like tp::fx::convert, range errors reported by name, never wrapped.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "host/to_fixed.hpp"

using namespace tp::host;
using tp::fx::q15_16;
using tp::fx::q1_14;

TEST(ToFixed, RoundsToNearestTiesAwayFromZero) {
  ConversionReport r;
  EXPECT_EQ(to_fixed<q1_14>(0.5, "x", r)->raw(), 8192);
  EXPECT_EQ(to_fixed<q1_14>(1.5 / 16384, "x", r)->raw(), 2);    // tie 1.5 ulp -> 2
  EXPECT_EQ(to_fixed<q1_14>(-1.5 / 16384, "x", r)->raw(), -2);  // symmetric
  EXPECT_EQ(to_fixed<q1_14>(-2.0, "x", r)->raw(), -32768);      // the minimum fits
  EXPECT_TRUE(r.ok());
  EXPECT_DOUBLE_EQ(to_double(*to_fixed<q15_16>(-3.25, "y", r)), -3.25);
}

TEST(ToFixed, OutOfRangeIsReportedNotWrapped) {
  ConversionReport r;
  EXPECT_FALSE(to_fixed<q1_14>(2.0, "light 2 position.x", r).has_value());  // max is 2 − 2^-14
  EXPECT_FALSE(to_fixed<q1_14>(std::numeric_limits<double>::quiet_NaN(), "ka", r).has_value());
  EXPECT_FALSE(to_fixed<q15_16>(40000.0, "vertex 7.z", r).has_value());
  ASSERT_EQ(r.issues().size(), 3u);
  EXPECT_EQ(r.issues()[0].quantity, "light 2 position.x");
  EXPECT_EQ(r.issues()[0].format, "Q1.14");
  EXPECT_DOUBLE_EQ(r.issues()[0].min, -2.0);
  EXPECT_DOUBLE_EQ(r.issues()[0].max, 2.0 - 1.0 / 16384);
  EXPECT_NE(r.to_string().find("vertex 7.z = 40000 does not fit Q15.16"), std::string::npos)
      << r.to_string();
  // Just below the top rounds to the maximum; half an ulp above it rounds out of range.
  ConversionReport r2;
  EXPECT_EQ(to_fixed<q1_14>(2.0 - 1.4 / 16384, "x", r2)->raw(), 32767);
  EXPECT_FALSE(to_fixed<q1_14>(2.0 - 0.5 / 16384, "x", r2).has_value());
}

TEST(ToFixed, VectorsAndThrowingForm) {
  ConversionReport r;
  const auto v = to_fixed3<q15_16>({1, -2, 0.5}, "n", r);
  ASSERT_TRUE(v.has_value());
  EXPECT_EQ((*v)[1].raw(), -2 * 65536);
  EXPECT_FALSE(to_fixed3<q1_14>({0, 3, 0}, "N", r).has_value());
  EXPECT_EQ(r.issues().at(0).quantity, "N.y");
  EXPECT_THROW(to_fixed_or_throw<q1_14>(5.0, "ks"), FixedRangeError);
  EXPECT_EQ(to_fixed_or_throw<q1_14>(0.25, "ks").raw(), 4096);
}
