// Forward differencing of the Kuijk-Blake piecewise-quadratic f along a span line
// θ(x) = θ0 + x·dθ (x = 0 .. length−1): the quadratic-segment state the span evaluator sums
// over lights and terms (docs/KUIJK-BLAKE.md, "How it works").
//
// State format: one fixed format for every term, Q.44 in int64 (kStateFrac), so states of
// different terms add. Within a segment, the value is an exact integer polynomial
//   V(t) = A t² + B t + C,  t = x − x_start,
// held as (v, d1, d2) = (V(0), V(1) − V(0), 2A); a step is v += d1, d1 += d2 (two additions),
// which is exact in integers: stepping reproduces direct evaluation bit for bit.
// Why 44 fractional bits: the rounding of A (<= 2^-45) grows like t², up to 2^24 over a
// 4,096-pixel span: 2^-21 = 1/32 of the output LSB (2^-16). With 40 bits it was measured at
// 0.44 LSB on top of the output rounding (tests/cosn, n = 1, a 3,791-pixel span).
//
// Segments: each term is cut where θ(x) crosses ±a and ±b, at most five segments; each
// segment is re-seeded from its own polynomial (value, first difference) at its start, so the
// rounding of the coefficients never accumulates across break points. To sum terms, the span
// evaluator adds jump(prev, next) = next.state − prev.state advanced to next.x at each break
// point: then the running sum equals the sum of the terms' direct evaluations exactly.
//
// Preconditions and overflow bounds (exercised in tests/cosn under UBSan):
//   1 <= length <= 4096; |θ0| <= π and |θ0 + (length−1)·dθ| <= π; |dθ| <= 1 radian per
//   pixel (make_segments saturates dθ to ±1: a span turning faster than that has no smooth
//   shading to preserve); 0 <= scale <= 1 (Q1.30); CosnCoeffs valid (0 < a < b < 4,
//   k = 1/(ab), 1/(b(b−a)) <= 2^14, true for every n <= 10,000 of all three (a, b) sources).
//   Bounds: k·|e| <= 1/b at a segment start (|e| <= a for the inner piece, b − a for the
//   outer ones), and 1/b < 2^7 since b² > ab >= 2^-14 (2^5.1 for the n <= 10,000 sources), so
//   |B| = 2·s·k·|e|·|dθ| < 2^8; |A| = s·k·dθ² <= 2^14; in Q.44: |v| <= 2^44,
//   |d1| <= 2^58.1, |d2| <= 2^59. Inside advance(), t·|dθ| is at most the piece
//   width plus one step, so t·|A| < 2^15.6 and A·t² <= 4 units: every partial product < 2^60.
//   Sums: 8 worst-case terms fit int64; at a typical |dθ| <= 2^-6, |d2| <= 2^47, so thousands.
#pragma once

#include <cstdint>

#include "firmware/cosn.hpp"
#include "fixedpoint/divide.hpp"
#include "fixedpoint/q.hpp"
#include "fixedpoint/wide.hpp"

namespace tp::fw::cosn {

inline constexpr int kStateFrac = 44;  // Q.44 state
inline constexpr int kOutFrac = 16;    // output intensity: 1.0 = 2^16
inline constexpr int kMaxSpan = 4096;
inline constexpr int kMaxSegments = 5;  // zero | outer | inner | outer | zero
inline constexpr std::int64_t kMaxK = std::int64_t{1} << 14;
inline constexpr std::int64_t kMaxDThetaRaw = std::int64_t{1} << 29;  // 1 radian per pixel

using scale_t = fx::q1_30;

// 1/(ab) and 1/(b(b−a)) in Q.40 (relative precision 2^-41 at k >= 1/4), once per material.
struct CosnCoeffs {
  std::int64_t a = 0, b = 0;  // Q2.29 raw
  std::int64_t k_in = 0;      // 1/(ab), Q.40
  std::int64_t k_out = 0;     // 1/(b(b−a)), Q.40
  bool valid = false;
};

struct QuadState {
  std::int64_t v = 0, d1 = 0, d2 = 0;  // Q.44
  friend constexpr bool operator==(const QuadState&, const QuadState&) = default;
};

// Pieces in θ order: 0: θ <= −b, 1: −b < θ < −a, 2: |θ| <= a, 3: a < θ < b, 4: θ >= b.
struct CosnSegment {
  std::int32_t x = 0;  // first pixel of the segment
  std::int32_t piece = 0;
  QuadState st;  // state of this piece's polynomial at x
};

namespace fd_detail {

using i64 = std::int64_t;

// round(a·b / 2^sh), ties away from zero, exact (128-bit product). Callers keep the result
// below 2^63 (bounds in the header comment).
constexpr i64 mul_shr(i64 a, i64 b, int sh) { return fx::mul_shift_right(a, b, sh); }

// round(2^98 / p) for 0 < p < 2^62, by restoring long division (the remainder stays < p).
constexpr i64 recip_q98(std::uint64_t p) {
  std::uint64_t r = 1, q = 0;
  for (int i = 0; i < 98; ++i) {
    r <<= 1;
    q <<= 1;
    if (r >= p) {
      r -= p;
      q |= 1;
    }
  }
  if (2 * r >= p) ++q;
  return static_cast<i64>(q);
}

constexpr int piece_of(i64 theta, i64 a, i64 b) {
  if (theta <= -b) return 0;
  if (theta < -a) return 1;
  if (theta <= a) return 2;
  if (theta < b) return 3;
  return 4;
}

// In a domain where θ increases (dθ > 0), the first x with θ0 + x·dθ beyond `bound`:
// strictly (> bound) or not (>= bound). bound − θ0 >= 0 here.
constexpr i64 first_x_past(i64 theta_begin, i64 dtheta, i64 bound, bool strict) {
  const i64 gap = bound - theta_begin;
  if (gap < 0) return 0;
  return strict ? fx::idiv(gap, dtheta) + 1 : fx::idiv(gap + dtheta - 1, dtheta);
}

// The pixel where the piece next changes, for a span in piece `p` at x (dθ != 0).
constexpr i64 next_change(const CosnCoeffs& c, i64 theta_begin, i64 dtheta, int p) {
  // Mirror a decreasing span: −θ maps piece j to 4 − j with the same open/closed ends.
  const bool down = dtheta < 0;
  const i64 t0 = down ? -theta_begin : theta_begin, dt = down ? -dtheta : dtheta;
  const int q = down ? 4 - p : p;  // piece in the mirrored, increasing domain
  switch (q) {
    case 0: return first_x_past(t0, dt, -c.b, true);
    case 1: return first_x_past(t0, dt, -c.a, false);
    case 2: return first_x_past(t0, dt, c.a, true);
    case 3: return first_x_past(t0, dt, c.b, false);
    default: return kMaxSpan;  // past +b nothing changes any more
  }
}

// Kuijk-Blake f on one piece as V(t) = scale·(K0 + σ·k·(e + t·dθ)²), e = θ(x) − centre.
constexpr QuadState seed(const CosnCoeffs& c, i64 theta, i64 dtheta, i64 s, int piece) {
  if (piece == 0 || piece == 4) return {};
  const bool inner = piece == 2;
  const i64 centre = inner ? 0 : (piece == 1 ? -c.b : c.b);
  const i64 e = theta - centre;
  const i64 sk = mul_shr(s, inner ? c.k_in : c.k_out, 26);  // Q30·Q40 -> Q.44 (< 2^58)
  const i64 ske = mul_shr(sk, e, 29);                       // s·k·e, Q.44
  i64 A = mul_shr(mul_shr(sk, dtheta, 29), dtheta, 29);     // s·k·dθ²
  i64 B = 2 * mul_shr(ske, dtheta, 29);                     // 2·s·k·e·dθ
  i64 C = mul_shr(ske, e, 29);                              // s·k·e²
  if (inner) {                                              // 1 − k θ²
    A = -A, B = -B, C = (s << (kStateFrac - 30)) - C;
  }
  return {C, A + B, 2 * A};
}

// seed(c, θ, dθ, s, piece).v alone (the value at θ; no dθ products): the same bits.
constexpr i64 seed_value(const CosnCoeffs& c, i64 theta, i64 s, int piece) {
  if (piece == 0 || piece == 4) return 0;
  const bool inner = piece == 2;
  const i64 centre = inner ? 0 : (piece == 1 ? -c.b : c.b);
  const i64 e = theta - centre;
  const i64 sk = mul_shr(s, inner ? c.k_in : c.k_out, 26);
  const i64 C = mul_shr(mul_shr(sk, e, 29), e, 29);
  return inner ? (s << (kStateFrac - 30)) - C : C;
}

}  // namespace fd_detail

// For callers that seed f themselves at a single angle (the Kuijk-Blake methods' per-pixel and
// per-sample values): piece_of(θ, a, b) is the piece of f holding θ (0 and 4 zero, 1 and 3
// outer parabolas, 2 the inner one), and seed_value(c, θ, s, piece) is s·f(θ) in the state
// format (kStateFrac): the same bits as the forward-differenced sections at θ.
using fd_detail::piece_of;
using fd_detail::seed_value;

constexpr CosnCoeffs make_coeffs(CosnParams p) {
  CosnCoeffs c;
  c.a = p.a.raw();
  c.b = p.b.raw();
  if (c.a <= 0 || c.b <= c.a || c.b > 4 * (std::int64_t{1} << 29)) return c;
  const auto ab = static_cast<std::uint64_t>(c.a * c.b);           // Q.58, < 2^62
  const auto bba = static_cast<std::uint64_t>(c.b * (c.b - c.a));  // Q.58
  // k <= 2^14 <=> ab >= 2^44 (in Q.58); also keeps the quotient inside int64.
  if (ab < (std::uint64_t{1} << 44) || bba < (std::uint64_t{1} << 44)) return c;
  c.k_in = fd_detail::recip_q98(ab);  // 2^98 / Q.58 = Q.40
  c.k_out = fd_detail::recip_q98(bba);
  c.valid = true;
  return c;
}

// The segments of one term (a light's diffuse or specular f, times `scale`) on a span:
// returns their count (1..5); out[0].x == 0, x strictly increasing, all < length.
// dθ is ignored when length == 1.
constexpr int make_segments(const CosnCoeffs& c, angle_t theta_begin, angle_t dtheta, scale_t scale,
                            int length, CosnSegment* out) {
  const std::int64_t t0 = theta_begin.raw(), s = scale.raw();
  const std::int64_t dt_in = length > 1 ? dtheta.raw() : 0;
  const std::int64_t dt =
      dt_in > kMaxDThetaRaw ? kMaxDThetaRaw : (dt_in < -kMaxDThetaRaw ? -kMaxDThetaRaw : dt_in);
  int count = 0;
  std::int64_t x = 0;
  int piece = fd_detail::piece_of(t0, c.a, c.b);
  while (true) {
    const std::int64_t theta = t0 + x * dt;
    out[count++] = {static_cast<std::int32_t>(x), piece, fd_detail::seed(c, theta, dt, s, piece)};
    if (dt == 0 || count == kMaxSegments) break;
    const std::int64_t nx = fd_detail::next_change(c, t0, dt, piece);
    if (nx >= length) break;
    x = nx;
    piece = fd_detail::piece_of(t0 + x * dt, c.a, c.b);
  }
  return count;
}

// The state t steps after `st`, in closed form (what t forward-difference steps give).
constexpr QuadState advance(const QuadState& st, std::int64_t t) {
  return {st.v + t * st.d1 + (t * (t - 1) / 2) * st.d2, st.d1 + t * st.d2, st.d2};
}

constexpr void step(QuadState& st) {
  st.v += st.d1;
  st.d1 += st.d2;
}

// Direct evaluation of the same integer polynomial at pixel x (Q.44).
constexpr std::int64_t eval_at(const CosnSegment* segs, int count, std::int64_t x) {
  int i = 0;
  while (i + 1 < count && segs[i + 1].x <= x) ++i;
  return advance(segs[i].st, x - segs[i].x).v;
}

// What the summing span evaluator adds at next.x so that its running state switches from
// prev's polynomial to next's: exactly next.st − (prev advanced to next.x).
constexpr QuadState jump(const CosnSegment& prev, const CosnSegment& next) {
  const QuadState p = advance(prev.st, next.x - prev.x);
  return {next.st.v - p.v, next.st.d1 - p.d1, next.st.d2 - p.d2};
}

// Q.44 state value -> output intensity (1.0 = 2^16), rounded to nearest.
constexpr std::int32_t to_out(std::int64_t v) {
  return static_cast<std::int32_t>(fx::round_shift_right(v, kStateFrac - kOutFrac));
}

}  // namespace tp::fw::cosn
