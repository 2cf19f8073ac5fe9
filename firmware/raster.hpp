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

namespace tp::fw {

class SpanTarget {
 public:
  virtual void span(const Span& s) = 0;

 protected:
  ~SpanTarget() = default;
};

// Whether the spans carry the edge parameter t of their ends (EdgePos::t).
enum class EdgeParameters : std::uint8_t { kWithout, kWith };

// Calls target.span() for every non-empty span of tri inside [0, width) x [0, height), top row
// first. tri.area2 must be > 0. Returns the number of spans.
std::uint32_t rasterize(const Triangle& tri, std::int32_t width, std::int32_t height,
                        SpanTarget& target, EdgeParameters edges = EdgeParameters::kWith);

// Integer division rounding toward +infinity / -infinity, for d > 0.
constexpr std::int64_t ceil_div(std::int64_t n, std::int64_t d) {
  return n >= 0 ? (n + d - 1) / d : -((-n) / d);
}
constexpr std::int64_t floor_div(std::int64_t n, std::int64_t d) {
  return n >= 0 ? n / d : -((-n + d - 1) / d);
}

// First pixel row (or column) whose centre 16 k + 8 is >= the subpixel coordinate v.
constexpr std::int32_t first_centre_at_or_after(std::int32_t v) {
  return static_cast<std::int32_t>(ceil_div(std::int64_t{v} - 8, 16));
}

}  // namespace tp::fw
