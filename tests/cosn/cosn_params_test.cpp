// (a, b) sources for the Kuijk-Blake cos^n: the firmware's integer (a, b) are converted to
// double and the max error of f against max(0, cos)^n is measured on [0, π].
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "firmware/cosn.hpp"
#include "firmware/cosn_fd.hpp"
#include "tables/cosn_fits.hpp"
#include "tables/cosn_fits_lookup.hpp"
#include "tables/cosn_reference.hpp"

namespace {

using namespace tp::fw::cosn;
namespace ref = tp::tables::cosn;

double to_d(angle_t x) { return std::ldexp(static_cast<double>(x.raw()), -29); }
double err_of(const CosnParams& p, int n, int samples = 3000) {
  return ref::max_error(n, to_d(p.a), to_d(p.b), samples);
}
// The generated minimax fit, read from the table (the firmware links none).
CosnParams table_params(int n) {
  const auto p = tp::tables::cosn_fits::minimax_params(n);
  return {p.a, p.b};
}

// Limits pinned from `build/release/bench/accuracy_cosn` (2026-11-22), margin to the brief's
// targets: closed form max 2.449 % at n = 1, 1.812 % at n = 2, 1.469 % over 3..10,000 (n = 12).
// n = 2 cannot meet 1.5 %: the minimax optimum of f itself is 1.765 % there.
double closed_limit(int n) { return n == 1 ? 0.025 : (n == 2 ? 0.0185 : 0.015); }

TEST(CosnParams, ClosedFormWithinTargetForEveryN) {
  double worst = 0;
  int worst_n = 0;
  for (int n = kMinN; n <= kMaxN; ++n) {
    const double e = err_of(closed_params(n), n, 2000);
    ASSERT_LE(e, closed_limit(n)) << "n = " << n;
    if (n >= 3 && e > worst) worst = e, worst_n = n;
  }
  // Not slack: the closed form stays within 0.1 points of the minimax optimum (1.43 %).
  EXPECT_GT(worst, 0.0140) << worst_n;
}

TEST(CosnParams, EverySourceHasValidCoefficients) {
  for (int n = kMinN; n <= kMaxN; ++n) {
    for (const CosnParams& p :
         {paper_params(n), closed_params(n), least_squares_params(n), table_params(n)}) {
      ASSERT_LT(p.a.raw(), p.b.raw()) << n;
      ASSERT_TRUE(make_coeffs(p).valid) << n;
    }
  }
}

// The paper's formulas are a least-squares fit for n <= 125; beyond, b tends to 0.2 while the
// optimum shrinks like 1/√n. Measured (build/release/bench/accuracy_cosn, 2026-11-22): 5.23 % at
// n = 1, 1.46 % at n = 20, 5.56 % at n = 125, 38.6 % at n = 1000, 72.8 % at n = 10,000.
TEST(CosnParams, PaperFormulasDegradePast125) {
  EXPECT_LT(err_of(paper_params(1), 1), 0.055);
  EXPECT_GT(err_of(paper_params(1), 1), 0.050);
  EXPECT_LT(err_of(paper_params(20), 20), 0.016);
  EXPECT_LT(err_of(paper_params(125), 125), 0.058);
  EXPECT_GT(err_of(paper_params(1000), 1000), 0.30);
  EXPECT_GT(err_of(paper_params(10000), 10000), 0.60);
}

// Paper labels: as printed (a and b exchanged) a > b for n >= 2, which f forbids; the
// corrected ones agree with our least-squares fit within 10 % for 1 <= n <= 125.
TEST(CosnParams, PaperMatchesOwnLeastSquaresFitUpTo125) {
  namespace t = tp::tables::cosn_fits;
  for (int i = 0; i < t::kCount && t::kN[i] <= 125; ++i) {
    const int n = t::kN[i];
    const CosnParams p = paper_params(n);
    const double a_ls = std::ldexp(t::kA_ls[i], -29), b_ls = std::ldexp(t::kB_ls[i], -29);
    EXPECT_NEAR(to_d(p.a) / a_ls, 1.0, 0.10) << n;
    EXPECT_NEAR(to_d(p.b) / b_ls, 1.0, 0.10) << n;
    EXPECT_LT(a_ls, b_ls);
  }
}

// The generated minimax table: recorded error is what the fit achieves, and the least-squares
// fit is never better in max error (up to sampling noise of the fit, 0.01 points).
TEST(CosnParams, TableFitsMatchRecordedErrors) {
  namespace t = tp::tables::cosn_fits;
  for (int i = 0; i < t::kCount; ++i) {
    const int n = t::kN[i];
    const double e = err_of(table_params(n), n);
    EXPECT_NEAR(e, t::kErrPpm_mm[i] * 1e-6, 2e-5) << n;
    EXPECT_LE(t::kErrPpm_mm[i], t::kErrPpm_ls[i] + 100) << n;
    // Minimax optimum: 2.38 % at n = 1, 1.77 % at n = 2, <= 1.44 % beyond (gen_cosn_fits).
    EXPECT_LE(e, n == 1 ? 0.0240 : (n == 2 ? 0.0178 : 0.0145)) << n;
  }
}

// The firmware's default (a, b): the closed form of the least-squares fit tracks the generated
// fit at every grid point (every n <= 200, 64 per decade to 10,000). Measured 2026-12-04 with
// the Q16 coefficients: a within 7.2e-5 and b within 4.0e-5 relative (bench/fit_cosn_closed_form
// least-squares); so close to the fit's flat optimum that max |f − cos^n| moves by at most
// 0.002 points.
TEST(CosnParams, LeastSquaresClosedFormTracksTheFit) {
  namespace t = tp::tables::cosn_fits;
  double worst_a = 0, worst_b = 0, worst_err = 0;
  for (int i = 0; i < t::kCount; ++i) {
    const int n = t::kN[i];
    const CosnParams p = least_squares_params(n);
    const double da = std::fabs(to_d(p.a) / std::ldexp(t::kA_ls[i], -29) - 1);
    const double db = std::fabs(to_d(p.b) / std::ldexp(t::kB_ls[i], -29) - 1);
    const double de = std::fabs(err_of(p, n) - t::kErrPpm_ls[i] * 1e-6);
    worst_a = std::max(worst_a, da);
    worst_b = std::max(worst_b, db);
    worst_err = std::max(worst_err, de);
    ASSERT_LE(da, 8e-5) << n;
    ASSERT_LE(db, 5e-5) << n;
    ASSERT_LE(de, 5e-5) << n;
  }
  // Not slack: the worst distances are within 20 % of the limits.
  EXPECT_GT(worst_a, 6.4e-5);
  EXPECT_GT(worst_b, 4e-5);
}

// Between grid points (n > 200) the interpolated table stays near the optimum.
TEST(CosnParams, InterpolatedTableBetweenGridPoints) {
  for (int n : {201, 333, 777, 1234, 4321, 9999})
    EXPECT_LE(err_of(table_params(n), n), 0.0145) << n;
}

// Every source is usable at compile time (materials can be baked into constant tables).
static_assert(paper_params(20).a < paper_params(20).b);
static_assert(closed_params(20).a < closed_params(20).b);
static_assert(least_squares_params(20).a < least_squares_params(20).b);
static_assert(make_coeffs(least_squares_params(10000)).valid);
static_assert(make_coeffs(closed_params(10000)).valid);

TEST(CosnParams, OutOfRangeNIsClamped) {
  EXPECT_EQ(closed_params(0).a, closed_params(1).a);
  EXPECT_EQ(closed_params(20000).b, closed_params(10000).b);
  EXPECT_EQ(least_squares_params(-5).a, least_squares_params(1).a);
  EXPECT_EQ(table_params(-5).a, table_params(1).a);
}

}  // namespace
