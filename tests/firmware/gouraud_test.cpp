// Gouraud's spans against the exact screen-linear interpolation of its vertex colours.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <utility>
#include <vector>

#include "firmware/methods.hpp"
#include "firmware/raster.hpp"
#include "helpers.hpp"

namespace tp::fw::test {
namespace {

__extension__ using Wide = __int128;  // exact products of 47-bit lambdas and 31-bit colours

constexpr std::int32_t kW = 1024, kH = 1024;

// Rasterizes tri and gives every span to two set-up Gouraud methods: one asked for linear
// spans (the pipeline's loop), one for its span buffer; both must give the same levels.
class Spans final : public SpanTarget {
 public:
  Spans(GouraudMethod& linear, GouraudMethod& buffered) : linear_(linear), buffered_(buffered) {}
  void span(const Span& s) override {
    LinearColours c = linear_.linear_span(s);
    std::vector<Rgb8> buffer(static_cast<std::size_t>(s.x1 - s.x0));
    buffered_.shade_span(s, buffer.data());
    for (std::int32_t x = s.x0; x < s.x1; ++x) {
      Rgb8 px;
      std::uint8_t* ch[3] = {&px.r, &px.g, &px.b};
      for (int i = 0; i < 3; ++i) {
        const std::int64_t level = c.c[i] >> LinearColours::kShift;
        in_range = in_range && level >= 0 && level <= 255;
        *ch[i] = static_cast<std::uint8_t>(level);
        c.c[i] += c.dc[i];
      }
      const Rgb8 b = buffer[static_cast<std::size_t>(x - s.x0)];
      same = same && b.r == px.r && b.g == px.g && b.b == px.b;
      pixels.push_back({x, s.y, px});
    }
  }
  struct Pixel {
    std::int32_t x, y;
    Rgb8 c;
  };
  std::vector<Pixel> pixels;
  bool in_range = true, same = true;

 private:
  GouraudMethod& linear_;
  GouraudMethod& buffered_;
};

// Every pixel of random triangles (1 to 1024 pixels across, vertex colours anywhere in [0, 1]
// and, for every third triangle, within a few units of a tie) gets round(255 v) of the exact
// interpolation v = v0 + (l1 (v1 - v0) + l2 (v2 - v0)) / area2 at its centre, except where 255 v
// lies within ε of a tie, ε the arithmetic's proven error (two Q.30 units: at()'s rounding, the
// steps along rows and spans; 16 where at() cuts the lambdas of a triangle with area2 >= 2^27),
// and there it is one level off. Fails with the row steps' sign flipped, a step in the wrong
// unit, or a level rounded down.
TEST(Gouraud, SpansAreTheExactInterpolationRoundedOnceOutsideTies) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<std::int32_t> coord(0, kW * 16 - 1);
  std::uniform_int_distribution<std::int32_t> colour(0, 1 << 30);
  std::uniform_int_distribution<std::int32_t> jitter(-3, 3);
  long pixels = 0, ties = 0;
  int triangles = 0;
  for (int t = 0; triangles < 3000; ++t) {
    Triangle tri;
    const int shift = t % 10;  // triangles from the whole viewport down to a few pixels
    const std::int32_t ox = coord(rng), oy = coord(rng);
    for (ShadeVertex& v : tri.v) {
      v.sx = std::clamp(ox + ((coord(rng) - kW * 8) >> shift), 0, kW * 16 - 1);
      v.sy = std::clamp(oy + ((coord(rng) - kH * 8) >> shift), 0, kH * 16 - 1);
    }
    tri.area2 = edge_function(tri.v[0], tri.v[1], tri.v[2].sx, tri.v[2].sy);
    if (tri.area2 <= 0) continue;
    ++triangles;
    VertexLevels levels[3];
    for (int i = 0; i < 3; ++i) {
      tri.v[i].id = i;
      for (int ch = 0; ch < 3; ++ch) {
        // 0.1 (ambient's 25.5 levels) rounds to a value 0.4 units from a tie.
        levels[i].c[ch] =
            t % 3 == 0 ? std::clamp(107374182 + jitter(rng), 0, 1 << 30) : colour(rng);
      }
    }
    tri.levels = levels;
    GouraudMethod linear, buffered;
    const ShadeContext ctx;  // the colours come from the cache: no lighting
    ASSERT_TRUE(linear.setup(tri, ctx));
    ASSERT_TRUE(buffered.setup(tri, ctx));
    Spans spans(linear, buffered);
    rasterize(tri, kW, kH, spans, EdgeParameters::kWithout);
    ASSERT_TRUE(spans.in_range) << "triangle " << t;
    ASSERT_TRUE(spans.same) << "triangle " << t;
    const long double eps = (tri.area2 >= (std::int64_t{1} << 27) ? 16.0L : 2.0L) * 255.0L /
                            static_cast<long double>(1 << 30);
    for (const auto& p : spans.pixels) {
      const std::int64_t px = 16 * std::int64_t{p.x} + 8, py = 16 * std::int64_t{p.y} + 8;
      const Wide l1 = edge_function(tri.v[2], tri.v[0], px, py);
      const Wide l2 = edge_function(tri.v[0], tri.v[1], px, py);
      const std::uint8_t got[3] = {p.c.r, p.c.g, p.c.b};
      for (int ch = 0; ch < 3; ++ch) {
        const Wide v0 = levels[0].c[ch], d1 = levels[1].c[ch] - v0, d2 = levels[2].c[ch] - v0;
        const Wide num = v0 * tri.area2 + l1 * d1 + l2 * d2;
        const long double x = 255.0L * static_cast<long double>(num) /
                              (static_cast<long double>(tri.area2) * (1 << 30));
        const long double want = std::floor(x + 0.5L);
        if (static_cast<long double>(got[ch]) == want) continue;
        ASSERT_LT(std::fabs(x - std::floor(x) - 0.5L), eps)
            << "triangle " << t << " pixel " << p.x << "," << p.y << " channel " << ch << ": got "
            << int{got[ch]} << ", exact " << static_cast<double>(x);
        ASSERT_EQ(std::fabs(static_cast<long double>(got[ch]) - want), 1.0L);
        ++ties;
      }
      ++pixels;
    }
  }
  std::printf("%d triangles, %ld pixels, %ld channels one level off at a tie\n", triangles, pixels,
              ties);
  EXPECT_GT(pixels, 1000000);
}

// The pipeline computes flat's and Gouraud's colours in its own pixel loop (linear spans), except
// with the write counts on, where it takes them through the span buffer: both give the same
// bytes, in either pixel format, with the depth test on and off. Two overlapping spheres, one
// seen through the other, lit by a point light near them.
TEST(Gouraud, LinearLoopsWriteWhatTheSpanBufferWrites) {
  Mesh m = octasphere(4, 0.8, {-0.3, 0, 0});
  const Mesh second = octasphere(3, 0.6, {0.5, 0.1, 0.3});
  const auto base = static_cast<std::uint32_t>(m.positions.size());
  m.positions.insert(m.positions.end(), second.positions.begin(), second.positions.end());
  m.normals.insert(m.normals.end(), second.normals.begin(), second.normals.end());
  for (std::uint32_t i : second.indices) m.indices.push_back(base + i);
  const auto render = [&](Method method, bool counts, PixelFormat format, bool depth) {
    Rig rig(97, 83, 4096, 3 * 8192, counts, format);
    auto& d = rig.dev;
    EXPECT_EQ(d.set_method(method), Error::kOk);
    EXPECT_EQ(d.set_depth_test(depth), Error::kOk);
    LightCmd l;
    l.index = 0;
    l.type = LightType::kPoint;
    l.color[0] = q16(1);
    l.color[1] = q16(0.8);
    l.color[2] = q16(0.6);
    l.position = Vec3q16{q16(0.4), q16(0.5), q16(1.2)};
    EXPECT_EQ(d.set_light(l), Error::kOk);
    EXPECT_EQ(d.clear(Rgb8{10, 20, 30}), Error::kOk);
    EXPECT_EQ(rig.load(m), Error::kOk);
    EXPECT_EQ(rig.draw_all(m), Error::kOk);
    const FramebufferView fb = d.framebuffer();
    return std::make_pair(std::vector<std::uint8_t>(fb.data, fb.data + fb.stride * fb.height),
                          d.counters().pixels_written);
  };
  for (Method method : {Method::kFlat, Method::kGouraud})
    for (PixelFormat format : {PixelFormat::kRgb888, PixelFormat::kRgb565})
      for (bool depth : {true, false}) {
        const auto linear = render(method, false, format, depth);
        const auto buffered = render(method, true, format, depth);
        EXPECT_GT(linear.second, 3000u);
        EXPECT_EQ(linear.second, buffered.second);
        EXPECT_TRUE(linear.first == buffered.first)
            << "method " << static_cast<int>(method) << " format " << static_cast<int>(format)
            << " depth " << depth;
      }
}

}  // namespace
}  // namespace tp::fw::test
