// Forward differencing of the Kuijk-Blake quadratic segments (firmware/cosn_fd.hpp):
// bit-exact against direct evaluation, summable via jumps, and its error against double f.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "firmware/cosn.hpp"
#include "firmware/cosn_fd.hpp"
#include "tables/cosn_reference.hpp"

namespace {

using namespace tp::fw::cosn;
namespace ref = tp::tables::cosn;

constexpr std::int64_t kPiRaw = 1686629713;  // floor(π · 2^29): |θ| <= π stays inside
double to_d(std::int64_t raw) { return std::ldexp(static_cast<double>(raw), -29); }

struct Case {
  CosnParams p;
  int n;
  std::int64_t theta0, dtheta;
  std::int32_t scale;  // Q1.30
  int length;
};

struct SpanRun {
  std::vector<CosnSegment> segs;
  int count = 0;
};

SpanRun segments_of(const Case& c) {
  SpanRun r;
  r.segs.resize(kMaxSegments);
  r.count = make_segments(make_coeffs(c.p), angle_t::from_raw(static_cast<std::int32_t>(c.theta0)),
                          angle_t::from_raw(static_cast<std::int32_t>(c.dtheta)),
                          scale_t::from_raw(c.scale), c.length, r.segs.data());
  return r;
}

CosnParams source(int which, int n) {
  if (which == 0) return paper_params(n);
  if (which == 1) return closed_params(n);
  return least_squares_params(n);
}

// Random spans with |θ| <= π everywhere; every fourth crosses all four break points.
std::vector<Case> random_cases(int count) {
  std::mt19937_64 rng(20261122);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Case> cases;
  for (int i = 0; i < count; ++i) {
    Case c;
    c.n = static_cast<int>(std::lround(std::exp(u(rng) * std::log(10000.0))));
    c.p = source(i % 3, c.n);
    c.length = i % 2 == 0 ? kMaxSpan : 1 + static_cast<int>(u(rng) * (kMaxSpan - 1));
    c.scale = static_cast<std::int32_t>(u(rng) * (1 << 30));
    const double b = to_d(c.p.b.raw()) * 1.05;
    double t0 = (2 * u(rng) - 1) * std::numbers::pi, t1 = (2 * u(rng) - 1) * std::numbers::pi;
    if (i % 4 == 1) t0 = -b, t1 = b;  // all four break points, increasing
    if (i % 4 == 3) t0 = b, t1 = -b;  // all four, decreasing
    c.theta0 = std::llround(std::ldexp(t0, 29));
    c.dtheta = c.length > 1 ? std::llround(std::ldexp((t1 - t0) / (c.length - 1), 29)) : 0;
    c.dtheta = std::clamp<std::int64_t>(c.dtheta, -kMaxDThetaRaw, kMaxDThetaRaw);
    while (std::llabs(c.theta0 + (c.length - 1) * c.dtheta) > kPiRaw)
      c.dtheta -= c.dtheta > 0 ? 1 : -1;
    cases.push_back(c);
  }
  return cases;
}

// Special spans: dθ = 0, θ0 exactly on ±a, ±b, tiny and huge steps, length 1 and 2.
std::vector<Case> special_cases() {
  std::vector<Case> cases;
  for (int n : {1, 2, 20, 125, 1000, 10000}) {
    for (int which = 0; which < 3; ++which) {
      const CosnParams p = source(which, n);
      const std::int64_t a = p.a.raw(), b = p.b.raw();
      for (std::int64_t t0 : {-b, -a, std::int64_t{0}, a, b, b - 1, a + 1, -a - 1, -b + 1}) {
        for (std::int64_t dt : {std::int64_t{0}, std::int64_t{1}, std::int64_t{-1}, b / 1000,
                                -b / 1000, 2 * b / 4095, -2 * b / 4095, a, -b}) {
          for (int len : {1, 2, 100, kMaxSpan}) {
            Case c{p,       n,  t0, std::clamp<std::int64_t>(dt, -kMaxDThetaRaw, kMaxDThetaRaw),
                   1 << 30, len};
            while (std::llabs(c.theta0 + (c.length - 1) * c.dtheta) > kPiRaw) c.dtheta /= 2;
            cases.push_back(c);
          }
        }
      }
    }
  }
  return cases;
}

// Steps the segment list the way the span evaluator will (re-seed at each segment start)
// and compares every pixel with direct evaluation and with the piece θ(x) actually lies in.
void check_exact(const Case& c) {
  const SpanRun r = segments_of(c);
  const CosnCoeffs k = make_coeffs(c.p);
  ASSERT_GE(r.count, 1);
  ASSERT_EQ(r.segs[0].x, 0);
  int seg = 0;
  QuadState st = r.segs[0].st;
  for (int x = 0; x < c.length; ++x) {
    if (seg + 1 < r.count && r.segs[static_cast<std::size_t>(seg) + 1].x == x)
      st = r.segs[static_cast<std::size_t>(++seg)].st;
    const std::int64_t theta = c.theta0 + x * c.dtheta;
    const int piece = theta <= -k.b ? 0 : theta < -k.a ? 1 : theta <= k.a ? 2 : theta < k.b ? 3 : 4;
    ASSERT_EQ(r.segs[static_cast<std::size_t>(seg)].piece, piece) << "x=" << x;
    ASSERT_EQ(st.v, eval_at(r.segs.data(), r.count, x)) << "x=" << x;
    step(st);
  }
  ASSERT_EQ(seg + 1, r.count) << "every segment starts inside the span";
}

TEST(CosnFd, ForwardDifferencingIsBitExactRandom) {
  for (const Case& c : random_cases(600)) {
    SCOPED_TRACE(testing::Message()
                 << "n=" << c.n << " t0=" << c.theta0 << " dt=" << c.dtheta << " len=" << c.length);
    check_exact(c);
    if (HasFatalFailure()) return;
  }
}

TEST(CosnFd, ForwardDifferencingIsBitExactSpecial) {
  for (const Case& c : special_cases()) {
    SCOPED_TRACE(testing::Message()
                 << "n=" << c.n << " t0=" << c.theta0 << " dt=" << c.dtheta << " len=" << c.length);
    check_exact(c);
    if (HasFatalFailure()) return;
  }
}

TEST(CosnFd, CrossingSpanHasFiveSegments) {
  const CosnParams p = closed_params(20);
  const Case up{p, 20, -p.b.raw() - 1000, (2 * p.b.raw() + 2000) / 4000, 1 << 30, kMaxSpan};
  EXPECT_EQ(segments_of(up).count, 5);
  Case down = up;
  down.theta0 = -up.theta0, down.dtheta = -up.dtheta;
  EXPECT_EQ(segments_of(down).count, 5);
}

// A step above one radian per pixel is saturated to it (the documented overflow guard).
TEST(CosnFd, StepIsSaturatedToOneRadian) {
  const CosnCoeffs k = make_coeffs(closed_params(1));
  CosnSegment fast[kMaxSegments], clamped[kMaxSegments];
  const auto t0 = angle_t::from_raw(-(3 << 28));
  const auto s = scale_t::from_raw(1 << 30);
  const int nf = make_segments(k, t0, angle_t::from_raw(3 << 28), s, 3, fast);
  const int nc = make_segments(k, t0, angle_t::from_raw(1 << 29), s, 3, clamped);
  ASSERT_EQ(nf, nc);
  for (int i = 0; i < nf; ++i) {
    EXPECT_EQ(fast[i].x, clamped[i].x);
    EXPECT_EQ(fast[i].st, clamped[i].st);
  }
}

// Several terms summed into one running state, switching polynomials by jump() at every
// break point of every term: equals the sum of the direct evaluations, bit for bit.
TEST(CosnFd, SummedTermsViaJumpsAreExact) {
  const auto cases = random_cases(240);
  for (std::size_t base = 0; base + 3 <= cases.size(); base += 3) {
    std::vector<SpanRun> runs;
    QuadState sum;
    for (std::size_t j = 0; j < 3; ++j) {
      Case c = cases[base + j];
      c.length = kMaxSpan;
      while (std::llabs(c.theta0 + (c.length - 1) * c.dtheta) > kPiRaw) c.dtheta /= 2;
      runs.push_back(segments_of(c));
      sum.v += runs.back().segs[0].st.v, sum.d1 += runs.back().segs[0].st.d1;
      sum.d2 += runs.back().segs[0].st.d2;
    }
    std::vector<int> at(3, 0);
    for (int x = 0; x < kMaxSpan; ++x) {
      std::int64_t direct = 0;
      for (std::size_t j = 0; j < 3; ++j) {
        SpanRun& r = runs[j];
        const auto next = static_cast<std::size_t>(at[j]) + 1;
        if (static_cast<int>(next) < r.count && r.segs[next].x == x) {
          const QuadState d = jump(r.segs[next - 1], r.segs[next]);
          sum.v += d.v, sum.d1 += d.d1, sum.d2 += d.d2;
          ++at[j];
        }
        direct += eval_at(r.segs.data(), r.count, x);
      }
      ASSERT_EQ(sum.v, direct) << "case " << base << " x=" << x;
      step(sum);
    }
  }
}

// Error of the integer evaluation (output Q.16, 1 LSB = 2^-16 of full intensity) against
// the double f at the same θ(x) and scale, over all random and special spans.
TEST(CosnFd, ErrorAgainstDoubleF) {
  double worst_f = 0, worst_closed = 0, worst_ls = 0;
  auto all = random_cases(600);
  const auto sp = special_cases();
  all.insert(all.end(), sp.begin(), sp.end());
  for (const Case& c : all) {
    const SpanRun r = segments_of(c);
    const double a = to_d(c.p.a.raw()), b = to_d(c.p.b.raw());
    const double s = std::ldexp(c.scale, -30);
    // Against cos^n only for our (a, b) (the paper's are tens of % off for large n).
    const bool closed = c.p.a == closed_params(c.n).a && c.p.b == closed_params(c.n).b;
    const bool ls = c.p.a == least_squares_params(c.n).a && c.p.b == least_squares_params(c.n).b;
    for (int x = 0; x < c.length; ++x) {
      const double theta = to_d(c.theta0 + x * c.dtheta);
      const double got = to_out(eval_at(r.segs.data(), r.count, x)) / 65536.0;
      const double ef = std::fabs(got - s * ref::f_quad(theta, a, b)) * 65536;
      worst_f = std::max(worst_f, ef);
      const double ec = std::fabs(got - s * ref::cosn_target(theta, c.n)) * 65536;
      if (closed) worst_closed = std::max(worst_closed, ec);
      if (ls) worst_ls = std::max(worst_ls, ec);
    }
  }
  std::printf(
      "max |int - f| = %.4f LSB(2^-16); max |int - cos^n| = %.1f LSB (closed_params), "
      "%.1f LSB (least_squares_params)\n",
      worst_f, worst_closed, worst_ls);
  // Measured by this test's printout (build/release/tests/cosn/cosn_fd_test
  // --gtest_filter=*Error*), 2026-11-22: 0.5231 LSB against f = the output rounding (0.5) plus
  // the Q.44 coefficient rounding grown over t² (bound 1/32 LSB); 1605.3 LSB = 2.45 % against
  // cos^n (n = 1, closed form). Pinned with margin: 0.54 LSB, 2.5 % of the peak. The
  // least-squares form minimises the integrated error, not the max: the least-squares optimum
  // itself is 3.377 % off at n = 1 (docs/ACCURACY.md); 2026-12-04: 2215.0 LSB = 3.38 %, pinned
  // at 3.45 %.
  EXPECT_LE(worst_f, 0.54);
  EXPECT_LE(worst_closed, 0.025 * 65536);
  EXPECT_LE(worst_ls, 0.0345 * 65536);
  EXPECT_GT(worst_closed, 0);
  EXPECT_GT(worst_ls, 0);
}

}  // namespace
