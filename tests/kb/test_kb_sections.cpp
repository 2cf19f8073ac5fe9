// Summed sections (firmware/kb/kb_sections.hpp): the forward-differenced sum of all terms
// equals the direct evaluation of the same integer polynomials, bit for bit, over spans of up
// to 4,096 pixels and up to 32 terms (16 lights × diffuse + specular); filling all-zero
// segments with the ambient colour changes nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include "firmware/cosn.hpp"
#include "firmware/kb/kb_sections.hpp"

namespace kb = tp::fw::kb;
namespace cosn = tp::fw::cosn;
using tp::fx::angle_t;

namespace {

angle_t ang(double v) {
  return angle_t::from_raw(static_cast<std::int32_t>(std::llround(std::ldexp(v, 29))));
}

struct Case {
  int length = 1;
  int terms = 1;
};

// Random terms on one span; returns false if the span was rejected by the overflow guard.
void fill_random(kb::SpanSections& sec, std::mt19937_64& rng, const Case& c) {
  std::uniform_real_distribution<double> u(0, 1);
  const int ns[] = {1, 5, 20, 50, 125, 500, 2000};
  const double pi = std::numbers::pi;
  std::int64_t ambient[3];
  for (auto& a : ambient)
    a = std::llround(u(rng) * 0.1 * 255 / 4096 * std::ldexp(1.0, cosn::kStateFrac));
  sec.begin(c.length, ambient);
  for (int j = 0; j < c.terms; ++j) {
    const int n = ns[rng() % 7];
    const auto coeffs = cosn::make_coeffs(cosn::closed_params(n));
    // θ over the span stays within [−π, π] (cosn's precondition); some spans sit still,
    // some start exactly on a break point.
    const double t0 = (2 * u(rng) - 1) * (j % 3 == 0 ? 0.6 : pi);
    angle_t theta0 = ang(t0);
    if (j % 5 == 1) theta0 = angle_t::from_raw(static_cast<std::int32_t>(coeffs.a));
    if (j % 5 == 2) theta0 = angle_t::from_raw(static_cast<std::int32_t>(-coeffs.b));
    const double t1 = (2 * u(rng) - 1) * (j % 3 == 0 ? 0.6 : pi);
    angle_t dtheta = c.length > 1 && j % 7 != 3 ? ang((t1 - t0) / (c.length - 1)) : ang(0);
    // Keep the rounded end inside ±π.
    const std::int64_t end = theta0.raw() + std::int64_t{dtheta.raw()} * (c.length - 1);
    if (end > std::llround(std::ldexp(pi, 29)) || end < -std::llround(std::ldexp(pi, 29)))
      dtheta = ang(0);
    // Some spans run past ±π (V passing the point opposite S): the term is cut there.
    if (j % 11 == 4 && c.length > 2) {
      theta0 = ang(2.2);
      dtheta = ang(2.9 / (c.length - 1));
    }
    cosn::scale_t scale[3];
    const bool white = j % 2 == 1;
    for (int ch = 0; ch < 3; ++ch)
      scale[ch] = white && ch > 0 ? scale[0]
                                  : tp::fx::q1_30::from_raw(static_cast<std::int32_t>(
                                        std::llround(u(rng) * (255.0 * 16 / 4096) * (1 << 30))));
    kb::make_term(sec.next_term(), coeffs, theta0, dtheta, scale, c.length);
    sec.commit();
  }
}

}  // namespace

TEST(KbSections, ForwardDifferencingIsBitExact) {
  std::mt19937_64 rng(44);
  auto sec = std::make_unique<kb::SpanSections>();
  std::vector<std::int64_t> r(4096), g(4096), b(4096);
  const int term_counts[] = {1, 2, 4, 8, 16, 32};
  const int lengths[] = {1, 2, 3, 17, 300, 1024, 4095, 4096};
  long checked = 0, segments = 0, direct = 0;
  for (int trial = 0; trial < 240; ++trial) {
    const Case c{lengths[trial % 8], term_counts[(trial / 8) % 6]};
    fill_random(*sec, rng, c);
    const auto stats = sec->evaluate_raw(r.data(), g.data(), b.data());
    segments += stats.segments;
    direct += stats.direct ? 1 : 0;
    for (int x = 0; x < c.length; ++x) {
      ASSERT_EQ(r[x], sec->direct_raw(x, 0)) << "trial " << trial << " x " << x;
      ASSERT_EQ(g[x], sec->direct_raw(x, 1)) << "trial " << trial << " x " << x;
      ASSERT_EQ(b[x], sec->direct_raw(x, 2)) << "trial " << trial << " x " << x;
      ++checked;
    }
  }
  std::printf("bit-exact: %ld pixels, %ld merged segments, %ld spans by the overflow guard\n",
              checked, segments, direct);
  // The guard only takes spans whose slope is extreme; the rest is forward differencing.
  EXPECT_LT(direct, 24);
}

TEST(KbSections, AmbientFillOfZeroSegmentsChangesNothing) {
  std::mt19937_64 rng(45);
  auto sec = std::make_unique<kb::SpanSections>();
  std::vector<tp::fw::Rgb8> on(4096), off(4096);
  long filled = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Case c{1 + static_cast<int>(rng() % 4096), 1 + static_cast<int>(rng() % 32)};
    std::mt19937_64 copy = rng;
    fill_random(*sec, rng, c);
    const auto s_on = sec->evaluate(on.data(), true);
    fill_random(*sec, copy, c);
    (void)sec->evaluate(off.data(), false);
    filled += s_on.ambient_pixels;
    for (int x = 0; x < c.length; ++x) {
      ASSERT_EQ(on[x].r, off[x].r) << trial << " " << x;
      ASSERT_EQ(on[x].g, off[x].g);
      ASSERT_EQ(on[x].b, off[x].b);
      const auto d = sec->direct_pixel(x);
      ASSERT_EQ(on[x].r, d.r);
      ASSERT_EQ(on[x].g, d.g);
      ASSERT_EQ(on[x].b, d.b);
    }
  }
  // The random spans must exercise the fill (|θ| >= b on whole segments of every term).
  std::printf("ambient-filled pixels: %ld\n", filled);
  EXPECT_GT(filled, 0);
}

// Levels: clamp(round(v / 2^28), 0, 255).
TEST(KbSections, LevelRounding) {
  constexpr std::int64_t one = std::int64_t{1} << kb::kLevelShift;
  EXPECT_EQ(kb::level_of(-5), 0);
  EXPECT_EQ(kb::level_of(one / 2 - 1), 0);
  EXPECT_EQ(kb::level_of(one / 2), 1);
  EXPECT_EQ(kb::level_of(254 * one + one / 2), 255);
  EXPECT_EQ(kb::level_of(4000 * one), 255);
}
