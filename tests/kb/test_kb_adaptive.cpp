// kb-adaptive (firmware/kb/kb_adaptive.hpp): the quadratic's algebra, and the error budget —
// every pixel that a cheap path (constant, linear, quadratic, subdivided quadratic) writes is
// within 1 level (the default budget) of the exact evaluation at that pixel — over thousands of
// random triangles, lights, exponents and eye modes (10,000 here; KB_TRIANGLES=N for another count:
// 300,000 measured on 2026-12-02, worst 1 level on every path). The measured worst case is
// printed; the scenes are checked the same way, end to end, in test_kb_adaptive_scenes.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <random>

#include "firmware/kb/kb_adaptive.hpp"
#include "firmware/methods.hpp"
#include "firmware/raster.hpp"

namespace tp::fw::kb {
namespace {

// --- The quadratic -------------------------------------------------------------------------

TEST(KbQuadratic, PassesThroughItsSixSamples) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::int32_t> g(-(2040 << kSampleFrac), 2040 << kSampleFrac);
  for (int trial = 0; trial < 1000; ++trial) {
    Samples6 s{};
    for (std::int32_t& v : s.g) v = g(rng);
    // (qu, qv) of A, B, C, AB, BC, CA on the quarter lattice.
    const int at[6][2] = {{0, 0}, {4, 0}, {0, 4}, {2, 0}, {2, 2}, {0, 2}};
    for (int k = 0; k < 6; ++k)
      ASSERT_EQ(quadratic_x8_at(s, at[k][0], at[k][1]), 8 * std::int64_t{s.g[k]}) << k;
    // The coefficient form agrees with the Lagrange form at every quarter point.
    const LocalQuadratic q = fit_quadratic(s);
    for (int qu = 0; qu <= 4; ++qu)
      for (int qv = 0; qu + qv <= 4; ++qv) {
        const std::int64_t x16 = 16 * q.c0 + 4 * q.cu * qu + 4 * q.cv * qv + q.cuu * qu * qu +
                                 q.cvv * qv * qv + q.cuv * qu * qv;  // 16 × q
        ASSERT_EQ(x16, 2 * quadratic_x8_at(s, qu, qv)) << qu << "," << qv;
      }
  }
}

// The largest |stepped − direct| (levels) over random quadratics stepped along runs of 1 .. max_n
// pixels inside the triangle.
double worst_stepping_error(int max_n, int trials, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::int32_t> g(-(2040 << kSampleFrac), 2040 << kSampleFrac);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst = 0;
  for (int trial = 0; trial < trials; ++trial) {
    Samples6 s{};
    for (std::int32_t& v : s.g) v = g(rng);
    const LocalQuadratic q = fit_quadratic(s);
    const int n = 1 + static_cast<int>(unit(rng) * (max_n - 1));
    // A run of n pixels from (u0, v0) to (u1, v1) inside the triangle.
    double u0 = unit(rng), v0 = unit(rng) * (1 - u0), u1 = unit(rng), v1 = unit(rng) * (1 - u1);
    const double du = n > 1 ? (u1 - u0) / (n - 1) : 0, dv = n > 1 ? (v1 - v0) / (n - 1) : 0;
    const auto q30 = [](double x) {
      return static_cast<std::int64_t>(std::llround(x * 1073741824.0));
    };
    QuadStep st = seed_quadratic(prepare_steps(q, q30(du), q30(dv)), q30(u0), q30(v0), n);
    for (int x = 0; x < n; ++x) {
      const double u = u0 + x * du, v = v0 + x * dv;
      const double exact = (static_cast<double>(q.c0) + q.cu * u + q.cv * v + q.cuu * u * u +
                            q.cvv * v * v + q.cuv * u * v) /
                           (1 << kSampleFrac);
      const double got =
          static_cast<double>(st.v) / static_cast<double>(std::int64_t{1} << kQuadStateFrac);
      worst = std::max(worst, std::fabs(got - exact));
      st.v += st.d1;
      st.d1 += st.d2;
    }
  }
  return worst;
}

TEST(KbQuadratic, ForwardDifferencesFollowTheQuadratic) {
  const double worst = worst_stepping_error(4096, 300, 11);
  std::printf("forward differencing over up to 4,096 pixels: worst %.3g levels\n", worst);
  // Measured 0.024 over the whole sample range (±2,040 levels, coefficients up to ~16,000 levels):
  // the Q.30 rounding of du, dv over 4,095 steps. Pinned at 1/32 level.
  EXPECT_LT(worst, 1.0 / 32);
}

TEST(KbQuadratic, ShortPiecesFollowTheQuadratic) {
  // Pieces of up to kShortPiece pixels seed d1 from two rounded values (seed_short).
  const double worst = worst_stepping_error(kShortPiece, 20000, 12);
  std::printf("forward differencing over up to %d pixels: worst %.3g levels\n", kShortPiece, worst);
  // Measured 0.0015 over 20,000 runs of the whole sample range (2026-12-01); pinned at 1/256.
  EXPECT_LT(worst, 1.0 / 256);
}

// --- The budget over random triangles ------------------------------------------------------

struct Scenario {
  Triangle tri;
  ShadeContext ctx;
};

class Random {
 public:
  explicit Random(std::uint32_t seed) : rng_(seed) {}
  double uniform(double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng_);
  }
  int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  Vec3u unit_near(double cx, double cy, double cz, double spread) {
    double x = cx + uniform(-spread, spread), y = cy + uniform(-spread, spread),
           z = cz + uniform(-spread, spread);
    const double l = std::sqrt(x * x + y * y + z * z);
    if (l < 1e-6) return unit_near(0, 0, 1, 0);
    return Vec3u{q1_30::from_raw(static_cast<std::int32_t>(std::lround(x / l * (1 << 30)))),
                 q1_30::from_raw(static_cast<std::int32_t>(std::lround(y / l * (1 << 30)))),
                 q1_30::from_raw(static_cast<std::int32_t>(std::lround(z / l * (1 << 30))))};
  }
  q15_16 q16(double v) {
    return q15_16::from_raw(static_cast<std::int32_t>(std::lround(v * 65536)));
  }
  q1_30 q30(double v) {
    return q1_30::from_raw(static_cast<std::int32_t>(std::lround(v * (1 << 30))));
  }

  // A triangle of 3–200 pixels across in a 256² viewport, perspective w in [1, 6], eye-space
  // positions on the view rays, vertex normals within a random spread of a random facing
  // direction; 1–16 directional or point lights, some of them very near the surface.
  Scenario scenario() {
    Scenario sc{};
    const double size = std::exp(uniform(std::log(3.0), std::log(200.0)));
    const double cx = uniform(20, 236), cy = uniform(20, 236);
    const double fx = uniform(-0.6, 0.6), fy = uniform(-0.6, 0.6);
    const double spread = std::exp(uniform(std::log(0.01), std::log(0.8)));
    for (ShadeVertex& v : sc.tri.v) {
      const double px = cx + uniform(-size, size) / 2, py = cy + uniform(-size, size) / 2;
      const double w = uniform(1, 6);
      v.sx = static_cast<std::int32_t>(std::lround(px * 16));
      v.sy = static_cast<std::int32_t>(std::lround(py * 16));
      v.w = q16(w);
      v.z = static_cast<std::int64_t>(std::llround((1 - 2 / w) * 1073741824.0));
      v.eye = Vec3q16{q16((px - 128) / 128 * w), q16((128 - py) / 128 * w), q16(-w)};
      v.normal = unit_near(fx, fy, 1, spread);
    }
    std::int64_t area2 = edge_function(sc.tri.v[0], sc.tri.v[1], sc.tri.v[2].sx, sc.tri.v[2].sy);
    if (area2 < 0) {
      std::swap(sc.tri.v[1], sc.tri.v[2]);
      area2 = -area2;
    }
    sc.tri.area2 = area2;
    // A new shading state, as the device's set_material / set_light would raise it: the
    // method's boundary memo must not serve a previous scenario's samples.
    sc.ctx.revision = ++revision_;
    MaterialCmd& m = sc.ctx.material;
    for (q1_30& c : m.color) c = q30(uniform(0, 1));
    m.ka = q30(uniform(0, 0.3));
    m.kd = q30(uniform(0, 1));
    m.ks = q30(uniform(0, 1));
    m.n = static_cast<std::uint32_t>(std::lround(std::exp(uniform(0, std::log(4096.0)))));
    sc.ctx.eye = integer(0, 1) == 0 ? EyeMode::kFinite : EyeMode::kInfinite;
    const int lights = integer(0, 3) == 0 ? integer(1, 16) : integer(1, 2);
    for (int i = 0; i < lights; ++i) {
      LightState& l = sc.ctx.lights[i];
      l.type = integer(0, 1) == 0 ? LightType::kDirectional : LightType::kPoint;
      for (q15_16& c : l.color) c = q16(uniform(0, 1.5));
      l.direction = unit_near(0, 0, 1, 1.5);
      // Point lights from far away to a hundredth of the triangle's size off its first vertex.
      const double d = std::exp(uniform(std::log(0.01), std::log(10.0)));
      const Vec3q16& p = sc.tri.v[0].eye;
      l.position = Vec3q16{q16(p.x.raw() / 65536.0 + uniform(-d, d)),
                           q16(p.y.raw() / 65536.0 + uniform(-d, d)), q16(p.z.raw() / 65536.0 + d)};
    }
    return sc;
  }

 private:
  std::mt19937 rng_;
  std::uint64_t revision_ = 0;
};

// Shades every span with the method and compares each pixel with the exact evaluation.
class BudgetProbe final : public SpanTarget {
 public:
  explicit BudgetProbe(KbAdaptiveMethod& m) : m_(m) {}
  void span(const Span& s) override {
    m_.shade_span(s, buf_);
    for (std::int32_t x = s.x0; x < s.x1; ++x) {
      const Rgb8 got = buf_[x - s.x0], want = m_.exact_at(x, s.y);
      const int d =
          std::max({std::abs(got.r - want.r), std::abs(got.g - want.g), std::abs(got.b - want.b)});
      worst = std::max(worst, d);
      ++pixels;
    }
  }
  int worst = 0;
  std::uint64_t pixels = 0;

 private:
  KbAdaptiveMethod& m_;
  Rgb8 buf_[kMaxDimension];
};

TEST(KbAdaptiveBudget, RandomTrianglesStayWithinOneLevelOfTheExactEvaluation) {
  Random rnd(2026);
  Counters counters;
  auto method = std::make_unique<KbAdaptiveMethod>();
  int worst_by_path[5] = {0, 0, 0, 0, 0};
  std::uint64_t triangles_by_path[5] = {0, 0, 0, 0, 0}, pixels = 0;
  const int kTriangles =
      std::getenv("KB_TRIANGLES") ? std::atoi(std::getenv("KB_TRIANGLES")) : 10000;
  for (int t = 0; t < kTriangles; ++t) {
    Scenario sc = rnd.scenario();
    if (sc.tri.area2 == 0) continue;
    sc.ctx.counters = &counters;
    ASSERT_TRUE(method->setup(sc.tri, sc.ctx));
    BudgetProbe probe(*method);
    rasterize(sc.tri, 256, 256, probe);
    const int path = static_cast<int>(method->path());
    ++triangles_by_path[path];
    worst_by_path[path] = std::max(worst_by_path[path], probe.worst);
    pixels += probe.pixels;
    EXPECT_LE(probe.worst, 1) << "triangle " << t << " path " << path << " n " << sc.ctx.material.n
                              << " area2 " << sc.tri.area2 << " eye "
                              << static_cast<int>(sc.ctx.eye);
  }
  const char* names[5] = {"constant", "linear", "quadratic", "subdivided", "exact"};
  std::printf("%d random triangles, %llu pixels; worst |kb-adaptive - exact| by path:\n",
              kTriangles, static_cast<unsigned long long>(pixels));
  for (int p = 0; p < 5; ++p)
    std::printf("  %-10s %5llu triangles, worst %d level(s)\n", names[p],
                static_cast<unsigned long long>(triangles_by_path[p]), worst_by_path[p]);
  // Every cheap path must actually be exercised for the bound to mean something.
  EXPECT_GT(triangles_by_path[0], 0u);
  EXPECT_GT(triangles_by_path[1], 0u);
  EXPECT_GT(triangles_by_path[2], 0u);
  EXPECT_GT(triangles_by_path[3], 0u);
  EXPECT_GT(triangles_by_path[4], 0u);
  // And the deepest cells that refine takes without their own check (kTrustedMiss).
  std::printf("  %llu deepest cells taken unchecked\n",
              static_cast<unsigned long long>(counters.subtriangles_unchecked));
  EXPECT_GT(counters.subtriangles_unchecked, 0u);
}

// Larger budgets (ShadeContext::budget_levels, set_budget): the estimate's thresholds scale
// with B, and every pixel stays within B levels of the exact evaluation. 3,000 random triangles
// per budget here (KB_TRIANGLES_B=N for another count).
TEST(KbAdaptiveBudget, LargerBudgetsHoldOverRandomTriangles) {
  const int kTriangles =
      std::getenv("KB_TRIANGLES_B") ? std::atoi(std::getenv("KB_TRIANGLES_B")) : 3000;
  for (const std::uint32_t budget : {2u, 4u, 16u}) {
    Random rnd(2027);
    Counters counters;
    auto method = std::make_unique<KbAdaptiveMethod>();
    int worst = 0;
    std::uint64_t cheap = 0;
    for (int t = 0; t < kTriangles; ++t) {
      Scenario sc = rnd.scenario();
      if (sc.tri.area2 == 0) continue;
      sc.ctx.counters = &counters;
      sc.ctx.budget_levels = budget;
      ASSERT_TRUE(method->setup(sc.tri, sc.ctx));
      BudgetProbe probe(*method);
      rasterize(sc.tri, 256, 256, probe);
      if (method->path() != KbAdaptiveMethod::Path::kExact) ++cheap;
      worst = std::max(worst, probe.worst);
      EXPECT_LE(probe.worst, static_cast<int>(budget)) << "budget " << budget << " triangle " << t;
    }
    std::printf("budget %2u: %d random triangles, %llu on a cheap path, worst %d level(s)\n",
                budget, kTriangles, static_cast<unsigned long long>(cheap), worst);
    EXPECT_GT(cheap, 0u);
  }
}

// Shades every span with two methods set up on the same triangle and counts differing pixels.
class SameImage final : public SpanTarget {
 public:
  SameImage(KbAdaptiveMethod& a, KbAdaptiveMethod& b) : a_(a), b_(b) {}
  void span(const Span& s) override {
    a_.shade_span(s, buf_a_);
    b_.shade_span(s, buf_b_);
    for (std::int32_t i = 0; i < s.x1 - s.x0; ++i) {
      const Rgb8 p = buf_a_[i], q = buf_b_[i];
      differing += (p.r != q.r || p.g != q.g || p.b != q.b) ? 1 : 0;
      ++pixels;
    }
  }
  std::uint64_t differing = 0, pixels = 0;

 private:
  KbAdaptiveMethod& a_;
  KbAdaptiveMethod& b_;
  Rgb8 buf_a_[kMaxDimension], buf_b_[kMaxDimension];
};

// Skipping (lights that add exactly 0, constant triangles filled) must not change a pixel, also
// when some lights are dark: a dark point light must keep both variants on the same evaluation
// route (the stepped per-pixel path takes directional lights only).
TEST(KbAdaptiveSkipping, RandomTrianglesWithDarkLightsMatchTheNoSkipVariant) {
  Random rnd(77);
  Counters counters;
  auto skip = std::make_unique<KbAdaptiveMethod>(AdaptiveMode::kAdaptive);
  auto noskip = std::make_unique<KbAdaptiveMethod>(AdaptiveMode::kNoSkip);
  std::uint64_t pixels = 0, differing = 0;
  int with_dark_point = 0;
  for (int t = 0; t < 2000; ++t) {
    Scenario sc = rnd.scenario();
    if (sc.tri.area2 == 0) continue;
    bool dark_point = false;
    for (LightState& l : sc.ctx.lights) {
      if (l.type == LightType::kOff || rnd.integer(0, 2) != 0) continue;
      for (q15_16& c : l.color) c = q15_16::zero();
      dark_point = dark_point || l.type == LightType::kPoint;
    }
    with_dark_point += dark_point ? 1 : 0;
    sc.ctx.counters = &counters;
    ASSERT_TRUE(skip->setup(sc.tri, sc.ctx));
    ASSERT_TRUE(noskip->setup(sc.tri, sc.ctx));
    SameImage probe(*skip, *noskip);
    rasterize(sc.tri, 256, 256, probe);
    pixels += probe.pixels;
    differing += probe.differing;
  }
  std::printf("%d triangles with a dark point light; %llu of %llu pixels differ\n", with_dark_point,
              static_cast<unsigned long long>(differing), static_cast<unsigned long long>(pixels));
  EXPECT_GT(with_dark_point, 100);
  EXPECT_EQ(differing, 0u);
}

// Early depth (kSkipsHiddenPixels, firmware/method.hpp): asked for [first, last) of a span, a
// method gives those pixels exactly the colours it gives them in the whole span. Every span of
// 2,000 random triangles is shaded whole, then narrowed at both ends by random amounts, for each
// kb-adaptive variant and for Phong (the same exact evaluation).
class NarrowedSpans final : public SpanTarget {
 public:
  NarrowedSpans(ShadingMethod& m, std::mt19937& rng) : m_(m), rng_(rng) {}
  void span(const Span& s) override {
    m_.shade_span(s, whole_);
    Span part = s;
    std::uniform_int_distribution<std::int32_t> at(s.x0, s.x1 - 1);
    part.first = at(rng_);
    part.last = std::uniform_int_distribution<std::int32_t>(part.first + 1, s.x1)(rng_);
    m_.shade_span(part, narrowed_);
    for (std::int32_t x = part.first; x < part.last; ++x) {
      const Rgb8 p = whole_[x - s.x0], q = narrowed_[x - s.x0];
      differing += (p.r != q.r || p.g != q.g || p.b != q.b) ? 1 : 0;
      ++pixels;
    }
    narrowed_spans += part.last - part.first < s.x1 - s.x0 ? 1 : 0;
  }
  std::uint64_t differing = 0, pixels = 0, narrowed_spans = 0;

 private:
  ShadingMethod& m_;
  std::mt19937& rng_;
  Rgb8 whole_[kMaxDimension], narrowed_[kMaxDimension];
};

TEST(KbAdaptiveEarlyDepth, NarrowedSpansShadeEveryPixelAsTheWholeSpan) {
  auto adaptive = std::make_unique<KbAdaptiveMethod>(AdaptiveMode::kAdaptive);
  auto noskip = std::make_unique<KbAdaptiveMethod>(AdaptiveMode::kNoSkip);
  auto exact = std::make_unique<KbAdaptiveMethod>(AdaptiveMode::kExactOnly);
  auto phong = std::make_unique<PhongMethod>();
  static_assert(KbAdaptiveMethod::kSkipsHiddenPixels && PhongMethod::kSkipsHiddenPixels);
  ShadingMethod* methods[] = {adaptive.get(), noskip.get(), exact.get(), phong.get()};
  for (ShadingMethod* m : methods) {
    Random rnd(31);
    std::mt19937 rng(5);
    Counters counters;
    NarrowedSpans probe(*m, rng);
    for (int t = 0; t < 2000; ++t) {
      Scenario sc = rnd.scenario();
      if (sc.tri.area2 == 0) continue;
      sc.ctx.counters = &counters;
      if (!m->setup(sc.tri, sc.ctx)) continue;
      rasterize(sc.tri, 256, 256, probe);
    }
    std::printf("%llu narrowed spans, %llu pixels compared, %llu differ\n",
                static_cast<unsigned long long>(probe.narrowed_spans),
                static_cast<unsigned long long>(probe.pixels),
                static_cast<unsigned long long>(probe.differing));
    EXPECT_GT(probe.narrowed_spans, 10000u);
    EXPECT_EQ(probe.differing, 0u);
  }
}

}  // namespace
}  // namespace tp::fw::kb
