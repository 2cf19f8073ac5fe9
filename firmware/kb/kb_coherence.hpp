// Span-setup coherence between consecutive spans (docs/KUIJK-BLAKE.md, "How it works").
//
// The exact span setup of the one-vector method (two slerps, the great circle, s, φ, dφ, f(s):
// three CORDIC atan2, two sin_cos, a sqrt, an rsqrt and two divisions per term) costs far more
// than the pixels of a short span. Within a triangle section (the rows between two vertex
// rows, where the left and right edges stay the same), the span parameters are smooth in y:
//   φ_L(y)      φ at the left edge crossing (unwrapped: no 2π jumps between samples),
//   r(y)        dφ per pixel, θ / (x_R − x_L) (smooth where both go to zero at an apex),
//   q_c(y)      the per-channel scale w_c·f(s(y)) (f is even in s, so the kink of s = |…| where
//               the span's circle passes through O does not show).
// They are computed exactly at the first, middle and last row of a chunk of at most kChunkRows
// rows and interpolated quadratically by forward differencing in y: three additions per
// parameter per row instead of the CORDIC work. Chunks shorter than kMinChunkRows are set up
// exactly on every row. The interpolation error is measured against the exact setup in
// docs/KUIJK-BLAKE.md (tests pin the image accuracy).
#pragma once

#include <cstdint>

#include "firmware/kb/kb_common.hpp"
#include "fixedpoint/divide.hpp"

namespace tp::fw::kb {

inline constexpr int kChunkRows = 16;
inline constexpr int kMinChunkRows = 4;
inline constexpr std::int32_t kMinChunkWidthRaw = 8 << 16;  // 8 pixels, Q15.16

// Exact span parameters of one term at one row.
struct SpanParams {
  std::int64_t phi_left = 0;          // angle_t raw
  std::int64_t rate = 0;              // dangle_t raw (Q.40 rad per pixel), |rate| <= 1 rad
  std::int64_t scale[3] = {0, 0, 0};  // q1_30 raw, w_c·f(s)
  angle_t theta{};                    // the span's arc angle (exact setup only)
};

inline constexpr int kParams = 5;  // φ_L, r, q_r, q_g, q_b

// A quadratic through three samples at row offsets 0, h1, h2 (0 < h1 < h2), stepped one row at a
// time: value, first and second difference with kExtra fractional bits.
struct QuadY {
  static constexpr int kExtra = 10;
  std::int64_t v = 0, d1 = 0, d2 = 0;

  // p0, p1, p2 below 2^52 in magnitude; h2 <= kChunkRows.
  void fit(std::int64_t p0, std::int64_t p1, std::int64_t p2, std::int64_t h1, std::int64_t h2) {
    // p(k) = p0 + B k + A k²: A = ((p2−p0)/h2 − (p1−p0)/h1)/(h2 − h1), B = (p1−p0)/h1 − A h1.
    // With D = h1 h2 (h2 − h1): A = ((p2−p0) h1 − (p1−p0) h2)/D, B = ((p1−p0) h2² − (p2−p0) h1²)/D.
    const std::int64_t a_num = (p2 - p0) * h1 - (p1 - p0) * h2;
    const std::int64_t b_num = (p1 - p0) * h2 * h2 - (p2 - p0) * h1 * h1;
    const std::int64_t den = h1 * h2 * (h2 - h1);
    // d1 = A + B, d2 = 2A, in units of 2^-kExtra (|A|, |B| < 2^52: no overflow at 10 bits).
    const std::int64_t a = div_round(a_num * (std::int64_t{1} << kExtra), den);
    const std::int64_t b = div_round(b_num * (std::int64_t{1} << kExtra), den);
    v = p0 * (std::int64_t{1} << kExtra);
    d1 = a + b;
    d2 = 2 * a;
  }
  void step() {
    v += d1;
    d1 += d2;
  }
  std::int64_t value() const { return fx::round_shift_right(v, kExtra); }

  static std::int64_t div_round(std::int64_t n, std::int64_t d) {
    return n >= 0 ? fx::idiv(n + d / 2, d) : -fx::idiv(-n + d / 2, d);
  }
};

}  // namespace tp::fw::kb
