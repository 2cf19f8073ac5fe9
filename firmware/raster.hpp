// The span rasterizer: edge walking in y, spans in x, top-left fill rule.
//
// Coverage (docs/CONVENTIONS.md): pixel (i, j) is covered when its centre (16 i + 8, 16 j + 8)
// in 1/16-pixel units is strictly inside the triangle, or on a top or left edge. In scanline
// form that is exactly: rows with ytop <= yc < ybottom, and in each row the pixels with
// x_left(yc) <= xc < x_right(yc), where x_left / x_right are the exact (rational) crossings of
// the row's centre line with the bounding edges. Every crossing is computed exactly in integers
// from the edge's two snapped endpoints, so two triangles sharing an edge agree to the bit and a
// closed mesh covers each pixel exactly once.
//
// Bounds (why 64-bit never overflows): geometry.cpp clips to a guard band |x|, |y| <= 64 w, so
// snapped coordinates satisfy |sx|, |sy| <= 65 / 2 * 16 * kMaxDimension + 1 < 2^22 and every
// coordinate difference is below 2^23. The walker's numerator (ax - 8) * dy + (yc - ay) * dx
// is then below 2 * 2^22 * 2^23 = 2^46, its divisor 16 dy below 2^27; edge functions and
// twice the area are below 2 * 2^46 = 2^47. Hence kMaxDimension = 4096 is the largest size
// for which every intermediate fits with the 2^62 headroom the interpolators assume
// (interp.hpp: |value difference| * |dy| <= 2^34 * 2^23 = 2^57); large_test.cpp renders at it.
#pragma once

#include <cstdint>

#include "firmware/method.hpp"
#include "fixedpoint/arith.hpp"
#include "fixedpoint/divide.hpp"

namespace tp::fw {

// What rasterize() hands its spans to: any class with a member span(const Span&). A template
// parameter, so that the device's pixel writer is called (and inlined) without a virtual call
// per span; tests and benchmarks that want run-time dispatch derive from this interface.
class SpanTarget {
 public:
  virtual void span(const Span& s) = 0;

 protected:
  ~SpanTarget() = default;
};

// Whether the spans carry the edge parameter t of their ends (EdgePos::t).
enum class EdgeParameters : std::uint8_t { kWithout, kWith };

// Integer division rounding toward +infinity / -infinity, for d > 0.
constexpr std::int64_t ceil_div(std::int64_t n, std::int64_t d) {
  return n >= 0 ? fx::idiv(n + d - 1, d) : -fx::idiv(-n, d);
}
constexpr std::int64_t floor_div(std::int64_t n, std::int64_t d) {
  return n >= 0 ? fx::idiv(n, d) : -fx::idiv(-n + d - 1, d);
}

// First pixel row (or column) whose centre 16 k + 8 is >= the subpixel coordinate v.
constexpr std::int32_t first_centre_at_or_after(std::int32_t v) {
  return static_cast<std::int32_t>(ceil_div(std::int64_t{v} - 8, 16));
}

namespace detail {

// Walks one edge a -> b (a.sy < b.sy) row by row. At row centre yc the crossing is
// x(yc) = ax + (yc - ay) dx / dy, and the first pixel whose centre is at or right of it is
// ix = ceil((x - 8) / 16) = ceil(N / D) with N = (ax - 8) dy + (yc - ay) dx, D = 16 dy.
// Stepping one row adds S = 16 dx to N; ix advances by floor(S / D) plus a carry from the
// error term e = ix D - N in [0, D): exact Bresenham-style integer stepping, no drift.
class EdgeWalker {
 public:
  void init(const Triangle& tri, std::uint8_t from, std::uint8_t to, std::int32_t yc) {
    const ShadeVertex& a = tri.v[from];
    const ShadeVertex& b = tri.v[to];
    from_ = from;
    to_ = to;
    ay_ = a.sy;
    dy_ = std::int64_t{b.sy} - a.sy;
    const std::int64_t dx = std::int64_t{b.sx} - a.sx;
    den_ = 16 * dy_;
    const std::int64_t n = (std::int64_t{a.sx} - 8) * dy_ + (std::int64_t{yc} - a.sy) * dx;
    ix_ = ceil_div(n, den_);
    err_ = ix_ * den_ - n;
    const std::int64_t s = 16 * dx;
    q_ = floor_div(s, den_);
    r_ = s - q_ * den_;
  }
  void step() {
    ix_ += q_;
    err_ -= r_;
    if (err_ < 0) {
      err_ += den_;
      ++ix_;
    }
  }
  std::int64_t ix() const { return ix_; }
  EdgePos pos(std::int32_t yc, EdgeParameters edges) const {
    if (edges == EdgeParameters::kWithout) return EdgePos{from_, to_, q1_30::zero()};
    // t = (yc - ay) / dy in [0, 1): the row centre lies on the edge's half-open y range.
    const auto t =
        fx::div<q1_30>(fx::int_q::from_raw(std::int64_t{yc} - ay_), fx::int_q::from_raw(dy_));
    return EdgePos{from_, to_, t};
  }

 private:
  std::int64_t ix_ = 0, err_ = 0, den_ = 1, q_ = 0, r_ = 0, dy_ = 1;
  std::int32_t ay_ = 0;
  std::uint8_t from_ = 0, to_ = 0;
};

}  // namespace detail

// Calls target.span() for every non-empty span of tri inside [0, width) x [0, height), top row
// first. tri.area2 must be > 0. Returns the number of spans.
template <class Target>
std::uint32_t rasterize(const Triangle& tri, std::int32_t width, std::int32_t height,
                        Target& target, EdgeParameters edges = EdgeParameters::kWith) {
  using detail::EdgeWalker;
  // Sort the vertices top to bottom (indices only: the method sees the triangle unchanged).
  std::uint8_t top = 0, mid = 1, bot = 2;
  const auto y = [&](std::uint8_t i) { return tri.v[i].sy; };
  if (y(mid) < y(top)) {
    const auto t = top;
    top = mid;
    mid = t;
  }
  if (y(bot) < y(mid)) {
    const auto t = mid;
    mid = bot;
    bot = t;
  }
  if (y(mid) < y(top)) {
    const auto t = top;
    top = mid;
    mid = t;
  }

  // Rows whose centre yc satisfies ytop <= yc < ybot, inside the viewport.
  const std::int32_t row0 =
      static_cast<std::int32_t>(fx::clamp(first_centre_at_or_after(y(top)), 0, height));
  const std::int32_t row1 =
      static_cast<std::int32_t>(fx::clamp(first_centre_at_or_after(y(bot)), 0, height));
  if (row0 >= row1) return 0;

  // Is the middle vertex left of the long edge top->bot? Then the long edge bounds spans on
  // the right. (x_long(mid.y) - mid.x) * dy_long > 0 means mid is left.
  const ShadeVertex& t = tri.v[top];
  const ShadeVertex& m = tri.v[mid];
  const ShadeVertex& b = tri.v[bot];
  const std::int64_t side = (std::int64_t{b.sx} - t.sx) * (std::int64_t{m.sy} - t.sy) -
                            (std::int64_t{m.sx} - t.sx) * (std::int64_t{b.sy} - t.sy);
  if (side == 0) return 0;  // collinear: zero area covers nothing
  const bool long_is_right = side > 0;

  EdgeWalker long_edge, short_edge;
  std::int32_t yc = 16 * row0 + 8;
  long_edge.init(tri, top, bot, yc);
  bool upper = yc < m.sy;
  if (upper) {
    short_edge.init(tri, top, mid, yc);
  } else {
    short_edge.init(tri, mid, bot, yc);
  }

  std::uint32_t spans = 0;
  for (std::int32_t row = row0; row < row1; ++row, yc += 16) {
    if (upper && yc >= m.sy) {  // the short edge changes at the middle vertex
      upper = false;
      short_edge.init(tri, mid, bot, yc);
    }
    const EdgeWalker& l = long_is_right ? short_edge : long_edge;
    const EdgeWalker& r = long_is_right ? long_edge : short_edge;
    const std::int64_t x0 = fx::clamp(l.ix(), 0, width);
    const std::int64_t x1 = fx::clamp(r.ix(), 0, width);
    if (x0 < x1) {
      const auto first = static_cast<std::int32_t>(x0), last = static_cast<std::int32_t>(x1);
      target.span(Span{row, first, last, l.pos(yc, edges), r.pos(yc, edges), first, last});
      ++spans;
    }
    long_edge.step();
    short_edge.step();
  }
  return spans;
}

}  // namespace tp::fw
