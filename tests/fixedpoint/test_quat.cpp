// Quaternions (fixedpoint/quat.hpp): exact and degenerate cases, then accuracy against long
// double over fixed-seed random unit vectors (tests/fixedpoint/measure_quat.hpp, the same sets
// as the docs/ACCURACY.md rows).
//
// Where the bounds come from: the quaternion rows of `build/release/bench/accuracy_fixedpoint`
// (configure/build command in docs/ACCURACY.md, "Fixed-point functions"; same input sets, from
// measure_quat.hpp) and, for the subsets only this file uses (other epsilons, smaller n), the
// same measure_* functions run on those subsets. The code is integer-exact, so Debug, Release
// and sanitize builds measure identical numbers. Each bound = measured max + the margin stated
// next to it. Units: LSB of Q1.30 (2^-30), angles in 2^-30 rad.
#include <gtest/gtest.h>

#include <cmath>

#include "fixedpoint/quat.hpp"
#include "tests/fixedpoint/measure_quat.hpp"

namespace fx = tp::fx;
using fx::q1_30;
using fx::testing::ErrStats;
using fx::testing::LdVec;
using fx::testing::quat30;
using fx::testing::v30;

namespace {
q1_30 r30(std::int64_t r) { return q1_30::from_raw(static_cast<std::int32_t>(r)); }
const q1_30 kOne = q1_30::one(), kZero = q1_30::zero();
const v30 kAxes[3] = {{kOne, kZero, kZero}, {kZero, kOne, kZero}, {kZero, kZero, kOne}};

// Measured maxima (see the header comment) and the pinned bounds.
// rotation_between, one rounding of an exact expression: measured 0.4999916 (random), 0.4999962
// (π - 1e-2), 0.4999765 (π - 1e-4), 0.5000436 (π - 1e-6). Pinned 0.5 + 0.001. Closer to π the
// (|from| - |to|)^2/2 input-rounding term in w (<= 1.5 * 2^-60 / |p|) shows: measured 0.5263901
// (π - 1e-8), 0.5406557 (π - 2^-28). Pinned 0.56 (margin 0.02).
constexpr long double kRotationBetween = 0.501L;
constexpr long double kRotationBetweenNearPi = 0.56L;
// rotate, one rounding of an exact expression: measured 0.4999995; pinned 0.5 + 1e-6.
constexpr long double kRotateRounding = 0.5L + 1e-6L;
// rotate(rotation_between(a, b), a) vs b: q's 4 x 0.5 LSB rounding acts on a unit vector
// through 2 |dq| (~2 LSB) plus the rotate rounding and |a| != 1: measured 3.3526 (random),
// 3.2888 (π - 1e-6), 3.049 / 3.133 / 3.283 (π - 1e-3 / 1e-6 / 1e-8, 5000 pairs), 3.5146
// (antipodal sweep, 3000 per k, incl. exactly opposite). Pinned 4.0 (margin ~0.35).
constexpr long double kMapsOnto = 4.0L;
// Length: measured 3.3589; angle(R L, R N) - angle(L, N): measured 1.9361; Kuijk-Blake eq. 4
// invariant: measured 2.3745. Pinned at measured + ~0.5: 3.9, 2.5, 3.0.
constexpr long double kLength = 3.9L;
constexpr long double kAnglePreserved = 2.5L;
constexpr long double kKbInvariant = 3.0L;

void expect_max(const ErrStats& s, long double bound, const char* what) {
  EXPECT_GT(s.n, 1000u) << what;
  EXPECT_LE(s.max_abs, bound) << what;
}
}  // namespace

// ---- exact and degenerate cases ---------------------------------------------------------

TEST(Quat, IdentityWhenFromEqualsTo) {
  for (const auto& a : kAxes) EXPECT_EQ(fx::rotation_between<q1_30>(a, a), fx::identity<q1_30>());
  for (const auto& a : fx::testing::random_units(1000, 31u)) {
    const v30 f = fx::testing::round30(a);
    ASSERT_EQ(fx::rotation_between<q1_30>(f, f), fx::identity<q1_30>());
  }
}

TEST(Quat, ZeroInputGivesIdentity) {
  const v30 z{kZero, kZero, kZero};
  EXPECT_EQ(fx::rotation_between<q1_30>(z, kAxes[0]), fx::identity<q1_30>());
  EXPECT_EQ(fx::rotation_between<q1_30>(kAxes[1], z), fx::identity<q1_30>());
  EXPECT_EQ(fx::rotation_between<q1_30>(z, z), fx::identity<q1_30>());
}

TEST(Quat, QuarterTurnBetweenAxes) {
  // x -> y: 90 degrees about z, (cos 45, 0, 0, sin 45); 2^30 / sqrt(2) = 759250124.99 -> ...125.
  const quat30 q = fx::rotation_between<q1_30>(kAxes[0], kAxes[1]);
  EXPECT_EQ(q, (quat30{r30(759250125), kZero, kZero, r30(759250125)}));
  EXPECT_EQ(fx::rotate<q1_30>(q, kAxes[0]).y.raw(),
            1 << 30);  // 2 * 759250125^2 / 2^30 rounds to 2^30
  // Components +-1 exactly, every ordered pair of signed axes (not opposite): rotate maps
  // from onto to within the end-to-end bound.
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int si : {1, -1})
        for (int sj : {1, -1}) {
          if (i == j && si != sj) continue;
          const v30 f = si > 0 ? kAxes[i] : fx::neg_sat(kAxes[i]);
          const v30 t = sj > 0 ? kAxes[j] : fx::neg_sat(kAxes[j]);
          const v30 r = fx::rotate<q1_30>(fx::rotation_between<q1_30>(f, t), f);
          EXPECT_LE(std::abs(r.x.raw() - t.x.raw()), 1) << i << j << si << sj;
          EXPECT_LE(std::abs(r.y.raw() - t.y.raw()), 1) << i << j << si << sj;
          EXPECT_LE(std::abs(r.z.raw() - t.z.raw()), 1) << i << j << si << sj;
        }
}

TEST(Quat, AntipodalAxesUseTheDocumentedPerpendicular) {
  // 180 degrees about normalize(from x e), e the least aligned basis axis (ties: lower index).
  const q1_30 m = -kOne;
  struct Case {
    v30 from;
    quat30 expected;
  };
  const Case cases[] = {
      {kAxes[0], {kZero, kZero, kZero, kOne}},  // e = y: x cross y = z
      {fx::neg_sat(kAxes[0]), {kZero, kZero, kZero, m}},
      {kAxes[1], {kZero, kZero, kZero, m}},  // e = x: y cross x = -z
      {fx::neg_sat(kAxes[1]), {kZero, kZero, kZero, kOne}},
      {kAxes[2], {kZero, kZero, kOne, kZero}},  // e = x: z cross x = y
      {fx::neg_sat(kAxes[2]), {kZero, kZero, m, kZero}},
  };
  for (const auto& c : cases) {
    const v30 to = fx::neg_sat(c.from);
    const quat30 q = fx::rotation_between<q1_30>(c.from, to);
    EXPECT_EQ(q, c.expected);
    EXPECT_EQ(fx::rotate<q1_30>(q, c.from), to) << "a half turn of an axis is exact";
  }
}

TEST(Quat, AntipodalRandomDirections) {
  // from = -to exactly: w = 0, the axis is a unit vector perpendicular to from, and the half
  // turn maps from onto to. Bounds: the axis is one normalize (<= 0.5 LSB per component);
  // measured |from . axis| <= 1 and ||axis|^2 - 1| <= 1 LSB, pinned 2; rotate as kMapsOnto.
  for (const auto& a : fx::testing::random_units(2000, 32u)) {
    const v30 f = fx::testing::round30(a), t = fx::neg_sat(f);
    const quat30 q = fx::rotation_between<q1_30>(f, t);
    ASSERT_EQ(q.w, kZero);
    const v30 axis{q.x, q.y, q.z};
    EXPECT_LE(std::abs(fx::dot<q1_30>(f, axis).raw()), 2);
    EXPECT_LE(std::abs(fx::dot<q1_30>(axis, axis).raw() - (1 << 30)), 2);
    const LdVec r = fx::testing::to_ldv(fx::rotate<q1_30>(q, f));
    const LdVec e = fx::testing::ld_unit(fx::testing::to_ldv(t));
    for (int i = 0; i < 3; ++i) ASSERT_LE(std::fabs(fx::testing::lsb30(r[i] - e[i])), kMapsOnto);
  }
}

TEST(Quat, ConjugateMultiplyNormalize) {
  const quat30 q = fx::rotation_between<q1_30>(fx::testing::round30({0.6L, -0.8L, 0.0L}),
                                               fx::testing::round30({0.0L, 0.28L, 0.96L}));
  // q q* = |q|^2 (1, 0, 0, 0): |q|^2 is 1 within q's rounding (measured: 0 LSB; bound 2).
  const quat30 p = fx::multiply<q1_30>(q, fx::conjugate(q));
  EXPECT_LE(std::abs(p.w.raw() - (1 << 30)), 2);
  EXPECT_EQ(p.x, kZero);  // exact cancellation: one rounding of an exact sum
  EXPECT_EQ(p.y, kZero);
  EXPECT_EQ(p.z, kZero);
  // i j = k, j i = -k (exact).
  const quat30 i{kZero, kOne, kZero, kZero}, j{kZero, kZero, kOne, kZero};
  EXPECT_EQ(fx::multiply<q1_30>(i, j), (quat30{kZero, kZero, kZero, kOne}));
  EXPECT_EQ(fx::multiply<q1_30>(j, i), (quat30{kZero, kZero, kZero, -kOne}));
  // normalize: zero -> identity (documented); (2, 2, 2, 2) * 2^-k -> (1/2, 1/2, 1/2, 1/2).
  EXPECT_EQ(fx::normalize<q1_30>(quat30{kZero, kZero, kZero, kZero}), fx::identity<q1_30>());
  for (int k = 0; k <= 29; ++k) {
    const q1_30 c = r30(std::int64_t{1} << (30 - k));
    ASSERT_EQ(fx::normalize<q1_30>(quat30{c, c, -c, c}),
              (quat30{r30(1 << 29), r30(1 << 29), r30(-(1 << 29)), r30(1 << 29)}))
        << k;
  }
  EXPECT_EQ(fx::conjugate(quat30{kOne, q1_30::min(), kOne, kZero}).x, q1_30::max());
}

TEST(Quat, MultiplyComposesRotations) {
  // rotate(a b, v) == rotate(a, rotate(b, v)) within the rounding of the three quaternion
  // products and two extra rotate roundings (measured max 4 LSB over these 1000 triples).
  const auto us = fx::testing::random_units(6000, 33u);
  ErrStats s;
  for (std::size_t n = 0; n + 5 < us.size(); n += 6) {
    using fx::testing::round30;
    const quat30 a = fx::rotation_between<q1_30>(round30(us[n]), round30(us[n + 1]));
    const quat30 b = fx::rotation_between<q1_30>(round30(us[n + 2]), round30(us[n + 3]));
    const v30 v = round30(us[n + 4]);
    const v30 x = fx::rotate<q1_30>(fx::multiply<q1_30>(a, b), v);
    const v30 y = fx::rotate<q1_30>(a, fx::rotate<q1_30>(b, v));
    s.add(static_cast<long double>(x.x.raw() - y.x.raw()));
    s.add(static_cast<long double>(x.y.raw() - y.y.raw()));
    s.add(static_cast<long double>(x.z.raw() - y.z.raw()));
  }
  EXPECT_LE(s.max_abs, 6.0L);  // measured 4; margin 2 LSB
}

TEST(Quat, ExtremeInputsSaturateWithoutOverflow) {
  // Non-unit inputs are outside the contract; these only have to be defined (the sanitize
  // build checks there is no overflow) and sensible.
  const q1_30 mn = q1_30::min(), mx = q1_30::max();
  const v30 big{mn, mn, mn}, big2{mx, mn, kZero};
  const quat30 q = fx::rotation_between<q1_30>(big, big);
  EXPECT_EQ(q, fx::identity<q1_30>());
  const quat30 q2 = fx::rotation_between<q1_30>(big, big2);
  EXPECT_LE(std::abs(fx::dot<q1_30>(v30{q2.x, q2.y, q2.z}, v30{q2.x, q2.y, q2.z}).raw() +
                     fx::mul_sat<q1_30>(q2.w, q2.w).raw() - (1 << 30)),
            4);
  const quat30 qm{mn, mn, mn, mn};
  (void)fx::rotate<q1_30>(qm, big);  // components clamped to -1 first
  const quat30 m = fx::multiply<q1_30>(qm, qm);
  EXPECT_EQ(m.w, mn);  // 4 - 4 - 4 - 4 = -8 saturates
  EXPECT_EQ(fx::normalize<q1_30>(qm).w.raw(), -(1 << 29));
  // A q15.16 vector rotated into q15.16: a quarter turn about z maps (100, 0, 0) to (0, 100, 0).
  using fx::q15_16;
  const fx::Vec3<q15_16> p{q15_16::from_int(100), q15_16::zero(), q15_16::zero()};
  const auto rp = fx::rotate<q15_16>(fx::rotation_between<q1_30>(kAxes[0], kAxes[1]), p);
  EXPECT_EQ(rp.y, q15_16::from_int(100));
  EXPECT_EQ(rp.x, q15_16::zero());
}

static_assert(fx::rotation_between<q1_30>(v30{q1_30::one(), q1_30::zero(), q1_30::zero()},
                                          v30{-q1_30::one(), q1_30::zero(), q1_30::zero()}) ==
              quat30{q1_30::zero(), q1_30::zero(), q1_30::zero(), q1_30::one()});
static_assert(fx::rotate<q1_30>(quat30{q1_30::zero(), q1_30::zero(), q1_30::zero(), q1_30::one()},
                                v30{q1_30::one(), q1_30::zero(), q1_30::zero()}) ==
              v30{-q1_30::one(), q1_30::zero(), q1_30::zero()});

// ---- accuracy against long double --------------------------------------------------------

TEST(QuatAccuracy, RotationBetween) {
  using namespace fx::testing;
  expect_max(measure_rotation_between(random_pairs(100000)), kRotationBetween, "random");
  for (long double eps : {1e-2L, 1e-4L, 1e-6L})
    expect_max(measure_rotation_between(near_antipodal_pairs(5000, eps, 5u)), kRotationBetween,
               "near antipodal");
  expect_max(measure_rotation_between(near_antipodal_pairs(5000, 1e-8L, 5u)),
             kRotationBetweenNearPi, "pi - 1e-8");
  expect_max(measure_rotation_between(near_antipodal_pairs(5000, std::ldexp(1.0L, -28), 6u)),
             kRotationBetweenNearPi, "pi - 2^-28");
}

TEST(QuatAccuracy, RotateIsOneRounding) {
  using namespace fx::testing;
  expect_max(measure_rotate_rounding(random_pairs(100000)), kRotateRounding, "rotate");
}

TEST(QuatAccuracy, RotationMapsFromOntoTo) {
  using namespace fx::testing;
  expect_max(measure_maps_onto(random_pairs(100000)), kMapsOnto, "random");
  for (long double eps : {1e-3L, 1e-6L, 1e-8L})
    expect_max(measure_maps_onto(near_antipodal_pairs(5000, eps, 7u)), kMapsOnto, "near antipodal");
  expect_max(measure_antipodal_sweep(fx::detail::kAntipodalLog2, 3000), kMapsOnto, "sweep");
}

TEST(QuatAccuracy, PreservesLengthsAndAngles) {
  using namespace fx::testing;
  ErrStats len, ang;
  measure_preservation(random_pairs(100000), len, ang);
  expect_max(len, kLength, "length");
  expect_max(ang, kAnglePreserved, "angle");
  // Kuijk-Blake eq. 4 relies on exactly this: angle(R(N->O) L, O) = angle(N, L).
  expect_max(measure_kb_invariant(100000), kKbInvariant, "KB eq. 4");
}

TEST(QuatAntipodal, ThresholdIsTheMeasuredBest) {
  // The crossover that fixes kAntipodalLog2 = 0 (|p| < one input LSB): one step lower lets the
  // general formula run on nearly opposite rounded pairs where input rounding dominates w; one
  // step higher takes the half turn while the exact rotation is still measurably better.
  // Measured worst error (LSB) of rotate(q, from) vs to, kLog2 = -2..3, 3000 pairs per k:
  // 3.9115, 3.7279, 3.5146, 3.5146, 4.9501, 8.9818; with 20000 per k: 4.75, 4.75, 3.66, 3.72,
  // 5.26, 8.98. 0 and +1 differ only in the 2^-29 band (0.1 LSB), so +1 is allowed to tie.
  using fx::testing::measure_antipodal_sweep;
  const long double chosen = measure_antipodal_sweep(0, 3000).max_abs;
  for (int k : {-2, -1, 2, 3})
    EXPECT_LT(chosen, measure_antipodal_sweep(k, 3000).max_abs) << "kAntipodalLog2 " << k;
  EXPECT_LE(chosen, measure_antipodal_sweep(1, 3000).max_abs);
  static_assert(fx::detail::kAntipodalLog2 == 0);
}
