// Kuijk-Blake angular interpolation: the spherical geometry of one span (integer-only).
//
// Unit directions (N, L, H, and the one-vector V) are interpolated by equal-angle rotation
// along great-circle arcs, first along the triangle edges in y, then along each span in x
// (Kuijk-Blake section 1.2). A point on an arc is cos ψ·from + sin ψ·tangent with the tangent
// a unit vector orthogonal to `from` in the arc's plane: its length stays one up to rounding,
// so nothing is renormalised per pixel.
//
// For the one-vector method (Kuijk-Blake eq. 4) a span runs from V_L to V_R on one great
// circle with unit pole P = V_L × T (T the arc tangent). S is the foot of the perpendicular
// from O = (0, 0, 1) onto that circle, s = angle(O, S) and φ the signed angle from S along
// the arc; then cos α = cos φ · cos s. With Q = P × S, O = cos s·S + sin s·P gives
//   cos s · (V·S) = V_z        and        cos s · (V·Q) = V_x P_y − V_y P_x,
// so φ(V) = atan2(V_x P_y − V_y P_x, V_z) needs neither S nor a division, and
// cos s = |(P_x, P_y)|, sin s = |P_z|. φ grows from V_L to V_R by the arc angle θ.
//
// Degenerate cases (all deterministic, all tested in tests/kb):
//  - V_L ≈ V_R (arc shorter than the rounding of its tangent): φ is constant; the span is
//    described by the great circle through O and V_L: s = 0, φ = angle(O, V_L), dφ = 0.
//  - O on the span's great circle: P_z = 0, s = 0 exactly, cos α = cos φ.
//  - O perpendicular to the circle (P = ±O): cos s = 0, s = π/2, and atan2(0, 0) = 0 gives
//    φ = 0 (any φ is right: cos α = 0 on the whole span).
//  - Antipodal arc ends (a rotation of π, possible when normals differ by more than 90° across
//    a triangle): every great circle through both ends is valid; a fixed perpendicular picks one.
#pragma once

#include <cstdint>

#include "fixedpoint/arith.hpp"
#include "fixedpoint/cordic.hpp"
#include "fixedpoint/q.hpp"
#include "fixedpoint/sqrt.hpp"
#include "fixedpoint/vec3.hpp"

namespace tp::fw::kb {

using fx::angle_t;
using fx::q1_30;
using Unit = fx::Vec3<q1_30>;

// Screen x positions and widths of spans: 16 fractional bits cover the 1/16-pixel snapping.
using xpos_t = fx::Q<15, 16, std::int32_t>;
// Per-pixel angle increment: 40 fractional bits so that 4,096 steps accumulate less than
// 2^-28 rad of rounding (|dφ| <= 4 rad per pixel at most: 3 integer bits suffice).
using dangle_t = fx::Q<3, 40, std::int64_t>;

inline constexpr Unit kO{q1_30::zero(), q1_30::zero(), q1_30::one()};  // Kuijk-Blake's O

// π in angle_t, rounded (raw = round(π · 2^29)).
inline constexpr angle_t kPi = angle_t::from_raw(1686629713);
inline constexpr angle_t kHalfPi = angle_t::from_raw(843314857);

// c1·u + c2·v per component: an exact wide sum of two products, rounded once.
constexpr Unit combine(q1_30 c1, const Unit& u, q1_30 c2, const Unit& v) {
  const fx::Vec3<q1_30> c{c1, c2, q1_30::zero()};
  const auto one = [&c](q1_30 a, q1_30 b) {
    return fx::dot<q1_30>(c, fx::Vec3<q1_30>{a, b, q1_30::zero()});
  };
  return {one(u.x, v.x), one(u.y, v.y), one(u.z, v.z)};
}

// A unit vector orthogonal to v, chosen deterministically (the axis v is least aligned with,
// crossed with v): used only for antipodal arcs.
constexpr Unit any_perpendicular(const Unit& v) {
  const auto mag = [](q1_30 c) { return c.raw() < 0 ? -static_cast<std::int64_t>(c.raw()) : c.raw(); };
  Unit axis{q1_30::zero(), q1_30::zero(), q1_30::zero()};
  if (mag(v.x) <= mag(v.y) && mag(v.x) <= mag(v.z)) axis.x = q1_30::one();
  else if (mag(v.y) <= mag(v.z)) axis.y = q1_30::one();
  else axis.z = q1_30::one();
  return fx::normalize<q1_30>(fx::cross<q1_30>(v, axis));
}

// A residual of a few LSB: below it an orthogonal part is rounding noise, not a direction
// (angles under 8 · 2^-30 rad, four LSB of angle_t, count as zero).
inline constexpr std::int32_t kNegligibleRaw = 8;
constexpr bool is_negligible(const Unit& w) {
  const auto small = [](q1_30 c) { return c.raw() <= kNegligibleRaw && c.raw() >= -kNegligibleRaw; };
  return small(w.x) && small(w.y) && small(w.z);
}

// The great-circle arc from `from` toward `to`: V(ψ) = cos ψ·from + sin ψ·tangent, ψ in
// [0, angle]. A zero tangent marks an arc too short to have a direction (angle 0).
struct Arc {
  Unit from{};
  Unit tangent{};
  angle_t angle{};
  constexpr bool has_direction() const {
    return tangent.x.raw() != 0 || tangent.y.raw() != 0 || tangent.z.raw() != 0;
  }
};

constexpr Arc make_arc(const Unit& from, const Unit& to) {
  Arc arc{from, Unit{}, angle_t::zero()};
  const q1_30 c = fx::dot<q1_30>(from, to);
  // w = to − (from·to)·from: the part of `to` orthogonal to `from`; |w| = sin θ.
  Unit w = combine(q1_30::one(), to, fx::neg_sat(c), from);
  // Orthogonalise once more: near 0 and π, w is small and its rounding has a part along
  // `from` that would tilt the tangent ("twice is enough", Gram-Schmidt).
  w = combine(q1_30::one(), w, fx::neg_sat(fx::dot<q1_30>(w, from)), from);
  Unit t{};
  if (is_negligible(w) || !fx::try_normalize<q1_30>(w, t)) {
    if (c.raw() >= 0) return arc;  // identical ends
    arc.tangent = any_perpendicular(from);
    arc.angle = kPi;
    return arc;
  }
  arc.tangent = t;
  // θ = atan2(sin θ, cos θ) with sin θ = w·t = |w|: accurate at every angle, unlike acos.
  arc.angle = fx::atan2(fx::dot<q1_30>(w, t), c);
  return arc;
}

// The point at angle ψ along the arc (equal-angle interpolation, no renormalisation).
constexpr Unit arc_at(const Arc& arc, angle_t psi) {
  if (!arc.has_direction()) return arc.from;
  const fx::SinCos sc = fx::sin_cos(psi);
  return combine(sc.cos, arc.from, sc.sin, arc.tangent);
}

// The point at fraction t in [0, 1] of the arc (t in q1_30): ψ = t·θ.
constexpr Unit arc_at_fraction(const Arc& arc, q1_30 t) {
  return arc_at(arc, fx::mul_sat<angle_t>(t, arc.angle));
}

// The span's great circle seen from O (Kuijk-Blake eq. 4, Figure 10).
struct SpanCircle {
  angle_t s{};          // angle(O, S) in [0, π/2]: cos^n α = cos^n φ · cos^n s
  angle_t phi_left{};   // φ at V_L
  angle_t theta{};      // arc angle from V_L to V_R (φ at V_R = phi_left + theta)
  bool constant = false;  // V_L ≈ V_R: φ does not change along the span
};

// φ of a unit vector on the circle with pole p (see the header comment).
constexpr angle_t phi_on_circle(const Unit& v, const Unit& p) {
  const q1_30 num = fx::dot<q1_30>(fx::Vec3<q1_30>{v.x, fx::neg_sat(v.y), q1_30::zero()},
                                   fx::Vec3<q1_30>{p.y, p.x, q1_30::zero()});
  return fx::atan2(num, v.z);
}

// |(x, y)| of two unit-vector components, correctly rounded.
constexpr q1_30 hypot2(q1_30 x, q1_30 y) {
  using Sq = fx::Q<2, 60, std::int64_t>;
  const Sq sq = fx::dot<Sq>(fx::Vec3<q1_30>{x, y, q1_30::zero()},
                            fx::Vec3<q1_30>{x, y, q1_30::zero()});
  return fx::sqrt<q1_30>(sq);
}

constexpr SpanCircle span_circle(const Unit& vl, const Unit& vr) {
  SpanCircle c;
  const Arc arc = make_arc(vl, vr);
  if (!arc.has_direction()) {
    // V_L ≈ V_R: take the circle through O and V_L (s = 0, φ = angle(O, V_L)).
    c.constant = true;
    c.phi_left = fx::atan2(hypot2(vl.x, vl.y), vl.z);
    return c;
  }
  // Pole of the arc's plane; unit because from ⟂ tangent, both unit.
  const Unit p = fx::cross<q1_30>(arc.from, arc.tangent);
  c.s = fx::atan2(fx::abs_sat(p.z), hypot2(p.x, p.y));
  c.phi_left = phi_on_circle(vl, p);
  c.theta = arc.angle;
  return c;
}

// φ along the pixels of a span: φ(x) = φ_L + (x − x_L)·θ / (x_R − x_L), sampled at the
// first pixel centre and stepped by dφ per pixel.
struct SpanLine {
  angle_t phi_first{};
  dangle_t dphi{};
};

constexpr SpanLine span_line(const SpanCircle& c, xpos_t x_left, xpos_t x_right,
                             xpos_t first_centre) {
  SpanLine line{c.phi_left, dangle_t::zero()};
  if (c.constant) return line;
  const xpos_t width = fx::sub_sat(x_right, x_left);
  if (width.raw() <= 0) return line;
  // Fraction of the span width at the first centre, clamped to [0, 1] (a centre is inside).
  q1_30 frac = fx::div<q1_30>(fx::sub_sat(first_centre, x_left), width);
  if (frac.raw() < 0) frac = q1_30::zero();
  if (frac > q1_30::one()) frac = q1_30::one();
  line.phi_first = fx::add_sat(c.phi_left, fx::mul_sat<angle_t>(frac, c.theta));
  line.dphi = fx::div<dangle_t>(c.theta, width);
  return line;
}

}  // namespace tp::fw::kb
