// Vlasic's quadratic shading: his eq. 4.2 checked by substitution, and the pixel loop — forward
// differences along spans up to the device's widest, eq. 4.1 per pixel under perspective —
// against eq. 4.1 evaluated exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <vector>

#include "firmware/methods.hpp"
#include "firmware/raster.hpp"
#include "firmware/six_points.hpp"

namespace tp::fw {
namespace {

// The six samples at (s, t) = (0, 0), (½, 0), (1, 0), (½, ½), (0, 1), (0, ½) (Vlasic's order,
// round the triangle), in halves.
constexpr int kAt[6][2] = {{0, 0}, {1, 0}, {2, 0}, {1, 1}, {0, 2}, {0, 1}};

// Eq. 4.1 at (s, t) = (a / 2, b / 2), times 4, exactly in integers.
std::int64_t four_r(const QuadraticMethod::Coefficients& q, int a, int b) {
  const std::int64_t* c = q.c;
  return 4 * c[0] + 2 * a * c[1] + 2 * b * c[2] + a * a * c[3] + a * b * c[4] + b * b * c[5];
}

// Substituting the six points into eq. 4.1 with eq. 4.2's coefficients gives back the six
// samples exactly: the sample order is the one eq. 4.2 was solved for. A test that fails with
// the midpoints taken in another order (r1 and r5 swapped: the r[1] <-> r[5] variant below).
TEST(Quadratic, Equation42InterpolatesTheSixSamplesInItsOrder) {
  std::mt19937_64 rng(42);
  std::uniform_int_distribution<std::int64_t> colour(0, std::int64_t{1} << 30);
  for (int trial = 0; trial < 10000; ++trial) {
    std::int64_t r[6];
    for (std::int64_t& v : r) v = colour(rng);
    const QuadraticMethod::Coefficients q = QuadraticMethod::coefficients(r);
    for (const std::int64_t c : q.c) ASSERT_LE(std::abs(c), std::int64_t{8} << 30);  // |C| <= 8
    for (int k = 0; k < 6; ++k) {
      ASSERT_EQ(four_r(q, kAt[k][0], kAt[k][1]), 4 * r[k]) << "sample " << k;
      // evaluate() (s and t at 28 bits) is exact at halves.
      ASSERT_EQ(QuadraticMethod::evaluate(q, std::int64_t{kAt[k][0]} << 29,
                                          std::int64_t{kAt[k][1]} << 29),
                r[k]);
    }
    std::int64_t swapped[6] = {r[0], r[5], r[2], r[3], r[4], r[1]};
    const QuadraticMethod::Coefficients w = QuadraticMethod::coefficients(swapped);
    if (r[1] != r[5]) {
      EXPECT_NE(four_r(w, 1, 0), 4 * r[1]);
    }
  }
}

constexpr std::int32_t kW = 4096, kH = 4096;

class Collect final : public SpanTarget {
 public:
  explicit Collect(QuadraticMethod& m) : m_(m) {}
  void span(const Span& s) override {
    std::vector<Rgb8> out(static_cast<std::size_t>(s.x1 - s.x0));
    m_.shade_span(s, out.data());
    for (std::int32_t x = s.x0; x < s.x1; ++x)
      pixels.push_back({x, s.y, out[static_cast<std::size_t>(x - s.x0)]});
  }
  struct Pixel {
    std::int32_t x, y;
    Rgb8 c;
  };
  std::vector<Pixel> pixels;

 private:
  QuadraticMethod& m_;
};

// Random triangles from the whole 4096² viewport (spans of up to 4096 pixels: the longest forward
// differencing) down to a few pixels, with random colours at the six points (the vertices' from
// the lit-vertex cache, the midpoints' as ka = 1 times a random material colour, no light), with
// equal w (forward differences) and with w from 1 to 8 (eq. 4.1 per pixel at perspective-correct
// (s, t)). Every pixel is round(255 r) of eq. 4.1 with the same coefficients at the pixel centre's
// exact (s, t), clamped, except within 1e-5 levels of a tie, and there one level off. Measured
// 2026-12-03 (the printed line): 51 of 100 million channels off, all within 1.95e-6 of a tie;
// with the second difference formed through Q.40 (ds² rounded first) 9,848, up to 2.9e-3 away.
TEST(Quadratic, PixelsAreEquation41AtTheExactCoordinates) {
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<std::int32_t> coord(0, kW * 16 - 1);
  std::uniform_int_distribution<std::int32_t> colour(0, 1 << 30);
  std::uniform_int_distribution<std::int32_t> wdist(1 << 16, 8 << 16);
  long pixels = 0, ties = 0;
  long double widest = 0;  // the largest distance from a tie at which a level was off
  int triangles = 0;
  for (int t = 0; triangles < 160; ++t) {
    Triangle tri;
    const int shift = t % 8;
    const bool perspective = t % 2 == 1;
    const std::int32_t ox = coord(rng), oy = coord(rng);
    for (ShadeVertex& v : tri.v) {
      v.sx = std::clamp(ox + ((coord(rng) - kW * 8) >> shift), 0, kW * 16 - 1);
      v.sy = std::clamp(oy + ((coord(rng) - kH * 8) >> shift), 0, kH * 16 - 1);
      v.w = q15_16::from_raw(perspective ? wdist(rng) : 1 << 16);
      v.normal = Vec3u{q1_30::zero(), q1_30::zero(), q1_30::one()};
    }
    tri.area2 = edge_function(tri.v[1], tri.v[2], tri.v[0].sx, tri.v[0].sy);
    if (tri.area2 <= 0) continue;
    ++triangles;
    VertexLevels levels[3];
    for (int i = 0; i < 3; ++i) {
      tri.v[i].id = i;
      for (int ch = 0; ch < 3; ++ch) levels[i].c[ch] = colour(rng);
    }
    tri.levels = levels;
    Counters counters;
    ShadeContext ctx;
    ctx.counters = &counters;
    ctx.material.ka = q1_30::one();
    ctx.material.kd = ctx.material.ks = q1_30::zero();
    for (q1_30& c : ctx.material.color) c = q1_30::from_raw(colour(rng));
    QuadraticMethod method(false);
    ASSERT_TRUE(method.setup(tri, ctx));
    VertexLevels six[6];
    six_levels(tri, ctx, six);
    Collect collect(method);
    rasterize(tri, kW, kH, collect, EdgeParameters::kWithout);
    for (const auto& p : collect.pixels) {
      const std::int64_t px = 16 * std::int64_t{p.x} + 8, py = 16 * std::int64_t{p.y} + 8;
      long double b[3] = {static_cast<long double>(edge_function(tri.v[1], tri.v[2], px, py)),
                          static_cast<long double>(edge_function(tri.v[2], tri.v[0], px, py)),
                          static_cast<long double>(edge_function(tri.v[0], tri.v[1], px, py))};
      long double sum = 0;
      for (int i = 0; i < 3; ++i) sum += b[i] /= tri.v[i].w.raw();
      const long double s = b[1] / sum, u = b[2] / sum;
      const std::uint8_t got[3] = {p.c.r, p.c.g, p.c.b};
      for (int ch = 0; ch < 3; ++ch) {
        const std::int64_t r[6] = {six[0].c[ch], six[3].c[ch], six[1].c[ch],
                                   six[4].c[ch], six[2].c[ch], six[5].c[ch]};
        const QuadraticMethod::Coefficients q = QuadraticMethod::coefficients(r);
        const long double v =
            (q.c[0] + q.c[1] * s + q.c[2] * u + q.c[3] * s * s + q.c[4] * s * u + q.c[5] * u * u) /
            static_cast<long double>(1 << 30);
        const long double x = 255.0L * std::clamp(v, 0.0L, 1.0L);
        const long double want = std::floor(x + 0.5L);
        if (static_cast<long double>(got[ch]) == want) continue;
        const long double from_tie = std::fabs(x - std::floor(x) - 0.5L);
        widest = std::max(widest, from_tie);
        ASSERT_LT(from_tie, 1e-5L)
            << "triangle " << t << " pixel " << p.x << "," << p.y << " channel " << ch << ": got "
            << int{got[ch]} << ", exact " << static_cast<double>(x);
        ASSERT_EQ(std::fabs(static_cast<long double>(got[ch]) - want), 1.0L);
        ++ties;
      }
      ++pixels;
    }
  }
  std::printf(
      "%d triangles, %ld pixels, %ld channels one level off at a tie, at most %.2Le from it\n",
      triangles, pixels, ties, widest);
  EXPECT_GT(pixels, 1000000);
}

}  // namespace
}  // namespace tp::fw
