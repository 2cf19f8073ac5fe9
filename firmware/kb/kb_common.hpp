// What the three Kuijk-Blake methods share: per-term weights and (a, b), the triangle's edge
// arcs and the span ends' screen positions. The per-vertex directions (L, H, the eye vector)
// are lighting.hpp's, the same copy as Blinn-Phong's.
//
// Terms: each light that is on gives two terms, diffuse (f with the (a, b) of n = 1, weight
// Il_c·kd·O_c) and specular (f with the material's (a, b), weight Il_c·ks). Diffuse with
// f(n = 1) instead of max(0, cos) is the paper's choice: f falls smoothly to zero at b ≈ 1.8 rad
// (past the terminator at π/2) and removes the Mach band there (Kuijk-Blake section 2;
// measured against a clamped cosine in docs/KUIJK-BLAKE.md).
//
// (a, b) sources: the material's (a, b) when the host set them (b > 0), else the closed form of
// the least-squares fit for the material's n (cosn::least_squares_params); diffuse always uses
// the least-squares fit of n = 1. Least squares minimises the integrated error, which is what
// colour correctness (a mean) measures: on the teapot it gives 0.9954 against 0.9945 with
// minimax (a, b) (docs/KUIJK-BLAKE.md).
#pragma once

#include <cstdint>

#include "firmware/cosn.hpp"
#include "firmware/cosn_fd.hpp"
#include "firmware/kb/kb_geometry.hpp"
#include "firmware/kb/kb_sections.hpp"
#include "firmware/lighting.hpp"
#include "firmware/method.hpp"
#include "firmware/vecmath.hpp"

namespace tp::fw::kb {

// Il_c · k · O_c · 255/4096 in Q1.30 (the span value unit, kb_sections.hpp): Il_c <= 16 in
// Q15.16 (raw < 2^21), k·O_c <= 1 in Q1.30: the product·255 stays below 2^59.
inline q1_30 term_weight(q15_16 intensity, q1_30 k_times_colour) {
  const std::int64_t p = std::int64_t{intensity.raw()} * k_times_colour.raw() * 255;
  return q1_30::from_raw_sat(fx::round_shift_right(p, 16 + 12));
}

// ka·O_c in span units (cosn's state format Q.S, S = cosn::kStateFrac, of 255·I/4096):
// raw_Q30 · 255 · 2^(S − 30 − 12).
inline std::int64_t ambient_value(q1_30 ka, q1_30 colour) {
  const q1_30 k = fx::mul_sat<q1_30>(ka, colour);
  constexpr int shift = cosn::kStateFrac - 42;
  static_assert(shift >= 0 && shift < 20, "state format between Q.42 and Q.61");
  return std::int64_t{k.raw()} * 255 * (std::int64_t{1} << shift);
}

inline cosn::CosnParams specular_params(const MaterialCmd& m) {
  if (m.b.raw() > 0 && m.a.raw() > 0 && m.a < m.b) return {m.a, m.b};
  return cosn::least_squares_params(static_cast<int>(m.n));
}
// A constant: the closed form is evaluated at compile time, not per material change.
inline constexpr cosn::CosnParams kDiffuseParams = cosn::least_squares_params(1);

// The diffuse and specular cos^n coefficients of the current material. They depend on
// (n, a, b) alone and cost four CORDIC calls to make, so consecutive triangles of one material
// reuse them: refresh() remakes them only when (n, a, b) changed, and says so.
struct MaterialCoeffs {
  cosn::CosnCoeffs diffuse{}, specular{};
  bool refresh(const MaterialCmd& m) {
    if (made_ && n_ == m.n && a_ == m.a.raw() && b_ == m.b.raw()) return false;
    diffuse = cosn::make_coeffs(kDiffuseParams);
    specular = cosn::make_coeffs(specular_params(m));
    made_ = true;
    n_ = m.n;
    a_ = m.a.raw();
    b_ = m.b.raw();
    return true;
  }

 private:
  bool made_ = false;
  std::uint32_t n_ = 0;
  std::int32_t a_ = 0, b_ = 0;
};

// f(θ) of one term at a single angle, in cosn's state format: the value of the one-pixel
// segment of the same polynomial (make_segments(c, θ, 0, 1, 1)[0].st.v, without building it).
inline std::int64_t f_at(const cosn::CosnCoeffs& c, angle_t theta) {
  return cosn::seed_value(c, theta.raw(), q1_30::one().raw(),
                          cosn::piece_of(theta.raw(), c.a, c.b));
}

// scale_c = weight_c · f (f in cosn's state format, <= 1), rounded into Q1.30: f is first
// rounded to Q.30 so that the product stays below 2^60.
inline q1_30 scaled(q1_30 weight, std::int64_t f_state) {
  const std::int64_t f30 = fx::round_shift_right(f_state, cosn::kStateFrac - 30);
  return q1_30::from_raw_sat(fx::round_shift_right(std::int64_t{weight.raw()} * f30, 30));
}

// The triangle's three edges, as the rasterizer names them (EdgePos from -> to):
// index 0: 0 -> 1, 1: 1 -> 2, 2: 2 -> 0. An EdgePos in the other direction reads the same
// edge at 1 − t.
struct EdgeRef {
  int index = 0;
  bool reversed = false;
};
constexpr EdgeRef edge_ref(const EdgePos& e) {
  const int a = e.from, b = e.to;
  if ((a + 1) % 3 == b) return {a, false};
  return {b, true};
}
constexpr q1_30 edge_fraction(const EdgePos& e, bool reversed) {
  return reversed ? fx::sub_sat(q1_30::one(), e.t) : e.t;
}

// Screen x (pixels, Q15.16) of a span end: sx_from + t·(sx_to − sx_from), sx in 1/16 pixel.
// |sx| <= 2^18 (raster.hpp), t <= 2^30 raw: the product is below 2^49.
inline xpos_t edge_x(const Triangle& tri, const EdgePos& e) {
  const std::int64_t from = tri.v[e.from].sx, to = tri.v[e.to].sx;
  const std::int64_t num = (from << 30) + std::int64_t{e.t.raw()} * (to - from);
  return xpos_t::from_raw_sat(fx::round_shift_right(num, 30 + 4 - 16));
}
// Whether a span end's x saturated in edge_x (or sits exactly at xpos_t's limit, the same
// value): xpos_t holds ±2^15 pixels while the guard band reaches 65/2 · 4096 pixels
// (docs/CONVENTIONS.md), so the ends of triangles reaching far into the guard band on viewports
// wider than 1008 pixels can. The methods count it once per span end (Counters::saturations).
constexpr bool at_limit(xpos_t x) {
  return x.raw() == xpos_t::max_raw || x.raw() == xpos_t::min_raw;
}
inline int saturated_ends(xpos_t left, xpos_t right) {
  return (at_limit(left) ? 1 : 0) + (at_limit(right) ? 1 : 0);
}
// Whether any span end of the triangle can reach that limit: span ends lie between the
// vertices' x, so not when every |sx| is below 2^19 subpixels (2^15 pixels) less one pixel.
constexpr bool may_saturate_x(const Triangle& tri) {
  constexpr std::int32_t kLimit = (std::int32_t{1} << 19) - 16;
  for (const ShadeVertex& v : tri.v)
    if (v.sx >= kLimit || v.sx <= -kLimit) return true;
  return false;
}

inline xpos_t pixel_centre(std::int32_t x) {
  return xpos_t::from_raw_sat((std::int64_t{x} << 16) + (std::int64_t{1} << 15));
}

// Arcs of a per-vertex direction along the three edges.
struct EdgeArcs {
  Arc arc[3];
  void set(const Unit v[3]) {
    for (int i = 0; i < 3; ++i) arc[i] = make_arc(v[i], v[(i + 1) % 3]);
  }
  Unit at(const EdgePos& e) const {
    const EdgeRef r = edge_ref(e);
    return arc_at_fraction(arc[r.index], edge_fraction(e, r.reversed));
  }
};

// φ along the span for cosn: the per-pixel step in angle_t (cosn's dθ format).
inline angle_t dphi_angle(const SpanLine& line) { return fx::convert<angle_t>(line.dphi); }

}  // namespace tp::fw::kb
