// The quadratic of kb-adaptive's cheap path (docs/KUIJK-BLAKE.md "kb-adaptive"): a colour
// channel given by six exact samples on a (sub-)triangle, vertices A, B, C and edge midpoints
// AB, BC, CA, is interpolated by the unique quadratic through them (Lagrange on the six-point
// lattice; Vlasic's eq. 4.2 in the barycentric form) and stepped along a span by forward
// differencing: two additions per channel per pixel, whatever the number of lights.
//
// Local coordinates: (u, v) with A at (0, 0), B at (1, 0), C at (0, 1); λ_A = 1 − u − v.
//   q(u, v) = g_A + c_u u + c_v v + c_uu u² + c_vv v² + c_uv u v, with
//   c_u = 4 g_AB − 3 g_A − g_B,   c_uu = 2 g_A + 2 g_B − 4 g_AB   (and the same for v with C, CA)
//   c_uv = 4 (g_A − g_AB − g_CA + g_BC)
// (substitution: q(1, 0) = g_B, q(½, 0) = g_AB, q(½, ½) = g_BC, …; tests/kb/test_kb_quadratic.cpp).
//
// Formats: samples are 8-bit output levels in Q.14 (|g| < 2^25, unclamped:
// firmware/point_shader.hpp); the span state is levels in Q.40 (kStateFrac), so that 4,096 steps of
// a rounded second difference stay far below 1/256 of a level; (u, v) and their per-pixel steps are
// Q.30 in 64-bit words.
#pragma once

#include <array>
#include <cstdint>

#include "firmware/cosn_fd.hpp"
#include "firmware/types.hpp"
#include "fixedpoint/q.hpp"

namespace tp::fw::kb {

inline constexpr int kSampleFrac = 14;        // sample values: levels, Q.14
inline constexpr int kQuadStateFrac = 40;     // forward-differencing state: levels, Q.40
using local_t = fx::Q<32, 30, std::int64_t>;  // u, v, du, dv

// The six samples of one channel, in the order A, B, C, AB, BC, CA.
struct Samples6 {
  std::int32_t g[6];
};

struct LocalQuadratic {
  std::int64_t c0 = 0, cu = 0, cv = 0, cuu = 0, cvv = 0, cuv = 0;  // levels, Q.14
};

constexpr LocalQuadratic fit_quadratic(const Samples6& s) {
  const std::int64_t a = s.g[0], b = s.g[1], c = s.g[2], ab = s.g[3], bc = s.g[4], ca = s.g[5];
  return LocalQuadratic{a,
                        4 * ab - 3 * a - b,
                        4 * ca - 3 * a - c,
                        2 * a + 2 * b - 4 * ab,
                        2 * a + 2 * c - 4 * ca,
                        4 * (a - ab - ca + bc)};
}

// 8 × q at the quarter-lattice point (qu/4, qv/4), qu + qv <= 4, exactly in integers: the
// Lagrange basis there is λ(2λ − 1) at the vertices (×8: 0, −1, 0, 3, 8 for λ = 0, ¼, ½, ¾, 1)
// and 4 λ_i λ_j at the midpoints (×8: 2 k_i k_j for λ = k/4).
constexpr std::int64_t quadratic_x8_at(const Samples6& s, int qu, int qv) {
  constexpr std::int64_t vertex_weight[5] = {0, -1, 0, 3, 8};
  const int ka = 4 - qu - qv, kb = qu, kc = qv;
  return vertex_weight[ka] * s.g[0] + vertex_weight[kb] * s.g[1] + vertex_weight[kc] * s.g[2] +
         2 * ka * kb * std::int64_t{s.g[3]} + 2 * kb * kc * std::int64_t{s.g[4]} +
         2 * kc * ka * std::int64_t{s.g[5]};
}

// The nine points of the quarter lattice that are not samples: where kb-adaptive checks the
// quadratic against exact values (they are the samples of the next subdivision level).
struct QuarterPoint {
  int qu, qv;
};
inline constexpr QuarterPoint kCheckPoints[9] = {{1, 0}, {3, 0}, {0, 1}, {0, 3}, {3, 1},
                                                 {1, 3}, {1, 1}, {2, 1}, {1, 2}};

// quadratic_x8_at's weights of the six samples (A, B, C, AB, BC, CA) at each check point, formed
// once: the check takes them at every cell of every triangle.
struct SampleWeights {
  std::int64_t w[6];
};
inline constexpr auto kCheckWeights = [] {
  std::array<SampleWeights, 9> t{};
  for (int k = 0; k < 9; ++k)
    for (int j = 0; j < 6; ++j) {
      Samples6 unit{};
      unit.g[j] = 1;
      t[static_cast<std::size_t>(k)].w[j] =
          quadratic_x8_at(unit, kCheckPoints[k].qu, kCheckPoints[k].qv);
    }
  return t;
}();

// Forward-differencing state of one channel along a span piece.
struct QuadStep {
  std::int64_t v = 0, d1 = 0, d2 = 0;  // levels, Q.40
};

// A cell's quadratic prepared for stepping with fixed per-pixel steps (du, dv): the value is the
// quadratic itself, the first difference q(u + du, v + dv) − q(u, v) is linear in (u, v),
//   d1 = e0 + e_u u + e_v v,  e0 = c_u du + c_v dv + c_uu du² + c_vv dv² + c_uv du dv,
//   e_u = 2 c_uu du + c_uv dv,  e_v = 2 c_vv dv + c_uv du,
// and the second difference d2 = 2 (c_uu du² + c_vv dv² + c_uv du dv) is constant. e0 and d2
// are formed once per cell with the steps' full precision (Q.14 × Q.60 in 128 bits).
// Bounds: |c| < 2^29 (|g| < 2^25); |u|, |v| <= 1 + 2^-20 at every pixel of a piece, and |du|,
// |dv| < 1 + 2^-20 when the piece has two pixels or more (both lie in the cell); steps are
// clamped to ±2 (a one-pixel piece never uses them), so every product below stays under 2^62.
// The clamp is proven harmless rather than counted: a step beyond ±2 means the cell is narrower
// than half a pixel along x, so no piece of two pixels lies in it and no pixel reads the step.
struct SteppedQuadratic {
  LocalQuadratic q;
  std::int64_t du = 0, dv = 0;                  // Q.30
  std::int64_t e0 = 0, eu = 0, ev = 0, d2 = 0;  // e0, d2: Q.40; eu, ev: Q.44 (× Q.30 -> Q.74)
};

inline SteppedQuadratic prepare_steps(const LocalQuadratic& q, std::int64_t du, std::int64_t dv) {
  constexpr std::int64_t kTwo = std::int64_t{2} << 30;
  du = du > kTwo ? kTwo : (du < -kTwo ? -kTwo : du);
  dv = dv > kTwo ? kTwo : (dv < -kTwo ? -kTwo : dv);
  SteppedQuadratic s;
  s.q = q;
  s.du = du;
  s.dv = dv;
  const std::int64_t du2 = du * du, dv2 = dv * dv, dudv = du * dv;  // Q.60, <= 2^62
  constexpr int kFromSq = 60 + kSampleFrac - kQuadStateFrac;        // Q.14 × Q.60 -> Q.40
  constexpr int kFromLin = 30 + kSampleFrac - kQuadStateFrac;       // Q.14 × Q.30 -> Q.40
  const std::int64_t curve = fx::mul_shift_right(q.cuu, du2, kFromSq) +
                             fx::mul_shift_right(q.cvv, dv2, kFromSq) +
                             fx::mul_shift_right(q.cuv, dudv, kFromSq);
  s.d2 = 2 * curve;
  s.e0 = fx::mul_shift_right(q.cu, du, kFromLin) + fx::mul_shift_right(q.cv, dv, kFromLin) + curve;
  s.eu = 2 * q.cuu * du + q.cuv * dv;  // Q.44
  s.ev = 2 * q.cvv * dv + q.cuv * du;
  return s;
}

// The monomials of a point (u, v) (Q.30), shared by every channel's quadratic there.
struct Monomials {
  std::int64_t u = 0, v = 0, uu = 0, vv = 0, uv = 0;  // Q.30
};
inline Monomials monomials(std::int64_t u, std::int64_t v) {
  const auto sq30 = [](std::int64_t a, std::int64_t b) { return fx::round_shift_right(a * b, 30); };
  return Monomials{u, v, sq30(u, u), sq30(v, v), sq30(u, v)};
}

// The quadratic's value at a point, levels in Q.40.
inline std::int64_t value_at(const LocalQuadratic& q, const Monomials& m) {
  constexpr int kToState = kQuadStateFrac - kSampleFrac;    // 26
  constexpr int kProd = 30 + kSampleFrac - kQuadStateFrac;  // Q.30 × Q.14 -> Q.40: >> 4
  return q.c0 * (std::int64_t{1} << kToState) +
         fx::round_shift_right(q.cu * m.u + q.cv * m.v + q.cuu * m.uu + q.cvv * m.vv + q.cuv * m.uv,
                               kProd);
}

// Pieces of up to this many pixels take their first difference as the difference of the values
// at their first two pixels (seed_short): the Q.30 rounding of the monomials makes that d1 up to
// 3·2^-15 of a level off for the largest coefficients (2^15 levels), a drift of 0.006 level
// over 64 pixels; longer pieces take it from e0, e_u, e_v (seed_quadratic), as exact as the steps.
inline constexpr std::int32_t kShortPiece = 64;

// The state of a short piece at the point with monomials `at`; `second`, the monomials at its
// second pixel (u + du, v + dv), or nullptr for a one-pixel piece (the value alone).
inline QuadStep seed_short(const SteppedQuadratic& s, const Monomials& at,
                           const Monomials* second) {
  QuadStep st;
  st.v = value_at(s.q, at);
  if (second == nullptr) return st;
  st.d1 = value_at(s.q, *second) - st.v;
  st.d2 = s.d2;
  return st;
}

// The state at local (u, v) (Q.30) of a piece of n pixels.
inline QuadStep seed_quadratic(const SteppedQuadratic& s, std::int64_t u, std::int64_t v,
                               std::int32_t n) {
  constexpr int kProd = 30 + kSampleFrac - kQuadStateFrac;  // Q.30 × Q.14 -> Q.40: >> 4
  const Monomials at = monomials(u, v);
  if (n <= 1) return seed_short(s, at, nullptr);  // (its steps may point far outside the cell)
  if (n <= kShortPiece) {
    const Monomials second = monomials(u + s.du, v + s.dv);
    return seed_short(s, at, &second);
  }
  QuadStep st;
  st.v = value_at(s.q, at);
  st.d1 = s.e0 + fx::mul_shift_right(s.eu, u, kProd + 30) +
          fx::mul_shift_right(s.ev, v, kProd + 30);  // Q.44 × Q.30 -> Q.40
  st.d2 = s.d2;
  return st;
}

// Output level of a state value: round, clamp to [0, 255].
constexpr std::uint8_t quad_level(std::int64_t v) {
  const std::int64_t l = (v + (std::int64_t{1} << (kQuadStateFrac - 1))) >> kQuadStateFrac;
  // One unsigned comparison for the usual case, in [0, 255]; the clamp only outside it.
  if (static_cast<std::uint64_t>(l) <= 255u) return static_cast<std::uint8_t>(l);
  return l < 0 ? std::uint8_t{0} : std::uint8_t{255};
}

}  // namespace tp::fw::kb
