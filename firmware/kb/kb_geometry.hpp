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
// from O (the paper's (0, 0, 1), or any fixed unit vector) onto that circle, s = angle(O, S)
// and φ the signed angle from S along the arc; then cos α = cos φ · cos s. With Q = P × S,
// O = cos s·S + sin s·P gives
//   cos s · (V·S) = V·O        and        cos s · (V·Q) = V·(P × O),
// so φ(V) = atan2(V·(P × O), V·O) needs neither S nor a division, and cos s = |P × O|,
// sin s = |P·O|. φ grows from V_L to V_R by the arc angle θ.
//
// Degenerate cases (all deterministic, all tested in tests/kb):
//  - V_L ≈ V_R (arc shorter than the rounding of its tangent): φ is constant; the span is
//    described by the great circle through O and V_L: s = 0, φ = angle(O, V_L), dφ = 0.
//  - O on the span's great circle: P·O = 0, s = 0 exactly, cos α = cos φ.
//  - O perpendicular to the circle (P = ±O): cos s = 0, s = π/2, and atan2(0, 0) = 0 gives
//    φ = 0 (any φ is right: cos α = 0 on the whole span).
//  - Antipodal arc ends (a rotation of π, possible when normals differ by more than 90° across
//    a triangle): every great circle through both ends is valid; a fixed perpendicular picks one.
#pragma once

#include <cstdint>

#include "fixedpoint/arith.hpp"
#include "fixedpoint/cordic.hpp"
#include "fixedpoint/divide.hpp"
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

inline constexpr angle_t kPi = fx::pi();
inline constexpr angle_t kHalfPi = fx::half_pi();
inline constexpr std::int64_t kTwoPiRaw = fx::two_pi_raw();

// An angle in raw angle_t units (any value a sum of a few angles can take) wrapped into
// [−π, π].
constexpr std::int64_t wrap_pi(std::int64_t v) {
  while (v > kPi.raw()) v -= kTwoPiRaw;
  while (v < -kPi.raw()) v += kTwoPiRaw;
  return v;
}

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
  const auto mag = [](q1_30 c) {
    return c.raw() < 0 ? -static_cast<std::int64_t>(c.raw()) : c.raw();
  };
  Unit axis{q1_30::zero(), q1_30::zero(), q1_30::zero()};
  if (mag(v.x) <= mag(v.y) && mag(v.x) <= mag(v.z))
    axis.x = q1_30::one();
  else if (mag(v.y) <= mag(v.z))
    axis.y = q1_30::one();
  else
    axis.z = q1_30::one();
  return fx::normalize<q1_30>(fx::cross<q1_30>(v, axis));
}

// |v| of a vector of unit-vector-sized components, correctly rounded.
constexpr q1_30 length(const Unit& v) {
  using Sq = fx::Q<2, 60, std::int64_t>;
  return fx::sqrt<q1_30>(fx::dot<Sq>(v, v));
}

// A residual of a few LSB: below it an orthogonal part is rounding noise, not a direction
// (angles under 8 · 2^-30 rad, four LSB of angle_t, count as zero).
inline constexpr std::int32_t kNegligibleRaw = 8;
constexpr bool is_negligible(const Unit& w) {
  const auto small = [](q1_30 c) {
    return c.raw() <= kNegligibleRaw && c.raw() >= -kNegligibleRaw;
  };
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

// The exact pole from × to (Q.60: two exact products per component, |.| = sin θ) and its
// largest component's bit width; 0 for a pole of at most ~16 LSB of Q1.30 (ends equal or
// opposite up to rounding).
struct ExactPole {
  std::int64_t p[3] = {0, 0, 0};
  int width = 0;
};
constexpr ExactPole exact_pole(const Unit& a, const Unit& b) {
  ExactPole e;
  e.p[0] = std::int64_t{a.y.raw()} * b.z.raw() - std::int64_t{a.z.raw()} * b.y.raw();
  e.p[1] = std::int64_t{a.z.raw()} * b.x.raw() - std::int64_t{a.x.raw()} * b.z.raw();
  e.p[2] = std::int64_t{a.x.raw()} * b.y.raw() - std::int64_t{a.y.raw()} * b.x.raw();  // < 2^61
  const auto mag = [](std::int64_t v) {
    return v < 0 ? std::uint64_t{0} - static_cast<std::uint64_t>(v) : static_cast<std::uint64_t>(v);
  };
  const std::uint64_t big = mag(e.p[0]) | mag(e.p[1]) | mag(e.p[2]);
  if (big > (std::uint64_t{kNegligibleRaw} << 31)) e.width = fx::bit_width(big);
  return e;
}
// The pole scaled by 2^-(width − 30): largest component in [2^29, 2^30) raw (shift >= 5).
constexpr Unit scaled_pole(const ExactPole& e) {
  const int shift = e.width - 30;
  const auto cut = [shift](std::int64_t v) {
    return q1_30::from_raw(static_cast<std::int32_t>(fx::round_shift_right(v, shift)));
  };
  return {cut(e.p[0]), cut(e.p[1]), cut(e.p[2])};
}
// θ = atan2(sin θ, cos θ) with sin θ = |Pn|·2^(width − 60) (|Pn| raw in Q1.30), in Q.60 terms.
constexpr angle_t pole_angle(const ExactPole& e, q1_30 pn_len, q1_30 cos_t) {
  const int shift = e.width - 30;
  const std::int64_t s = pn_len.raw(), c = cos_t.raw();
  return shift >= 30 ? fx::atan2_fast(s * (std::int64_t{1} << (shift - 30)), c)
                     : fx::atan2_fast(s, c * (std::int64_t{1} << (30 - shift)));
}

constexpr Arc make_arc(const Unit& from, const Unit& to) {
  Arc arc{from, Unit{}, angle_t::zero()};
  const q1_30 c = fx::dot<q1_30>(from, to);
  // The tangent from the exact pole: T = (P × from)/|P| with P scaled to unit size by a power of
  // two (Pn): T = (Pn × from)/|Pn|, one reciprocal (Q.61 / Q.30 -> Q.31) for the three
  // components. Ends equal or opposite up to a few LSB: the construction below.
  const ExactPole pole = exact_pole(from, to);
  if (pole.width != 0) {
    const Unit pn = scaled_pole(pole);
    const q1_30 pn_len = length(pn);  // [2^29, √3·2^30) raw
    const Unit tu = fx::cross<q1_30>(pn, from);
    const std::int64_t inv = fx::idiv(std::int64_t{1} << 61, pn_len.raw());  // 1/|Pn|, Q.31, < 2^32
    const auto one = [inv](q1_30 v) {
      return q1_30::from_raw_sat(fx::round_shift_right(std::int64_t{v.raw()} * inv, 31));
    };
    arc.tangent = Unit{one(tu.x), one(tu.y), one(tu.z)};
    arc.angle = pole_angle(pole, pn_len, c);
    return arc;
  }
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
  arc.angle = fx::atan2_fast(fx::dot<q1_30>(w, t), c);
  return arc;
}

// R(N→O), the minimal rotation taking unit n onto unit o (Kuijk-Blake's one-vector rotation),
// as axis k = normalize(n × o), sin = |n × o|, cos = n·o; applied by Rodrigues' formula
//   R v = cos·v + sin·(k × v) + (1 − cos)·k (k·v),
// which stays exact-ish near a half turn (no division by 1 + cos). n = −o: a half turn about a
// fixed perpendicular of n (any_perpendicular); n = o: the identity.
struct Rotation {
  Unit axis{};
  q1_30 sin{}, cos = q1_30::one();
};
constexpr Rotation rotation_to(const Unit& n, const Unit& o) {
  Rotation r;
  const Unit a = fx::cross<q1_30>(n, o);
  r.cos = fx::dot<q1_30>(n, o);
  // Near a half turn n × o is tiny and its rounding tilts it out of the plane orthogonal to n;
  // an axis orthogonal to n keeps R·n = cos·n + sin·(k × n) close to o whatever its azimuth.
  // Normalise first (the projection then carries 1 LSB, not 1 LSB / |n × o|), then project.
  Unit k0{};
  const bool has_axis =
      !is_negligible(a) && fx::try_normalize<q1_30>(a, k0) &&
      fx::try_normalize<q1_30>(combine(q1_30::one(), k0, fx::neg_sat(fx::dot<q1_30>(k0, n)), n),
                               r.axis);
  if (!has_axis) {
    if (r.cos.raw() >= 0) return Rotation{};  // identity
    r.axis = any_perpendicular(n);
    r.sin = q1_30::zero();
    r.cos = fx::neg_sat(q1_30::one());
    return r;
  }
  // |a| = a·k0 (k0 = a/|a|), up to a few LSB of rounding: no square root.
  r.sin = fx::dot<q1_30>(a, k0);
  return r;
}
constexpr Unit rotate(const Rotation& r, const Unit& v) {
  const Unit kxv = fx::cross<q1_30>(r.axis, v);
  // (1 − cos)·(k·v) <= 2 in magnitude: q1_30's range [−2, 2) holds it up to one LSB.
  const q1_30 along =
      fx::mul_sat<q1_30>(fx::sub_sat(q1_30::one(), r.cos), fx::dot<q1_30>(r.axis, v));
  using W = fx::Q<2, 60, std::int64_t>;
  const auto one = [&](q1_30 vc, q1_30 kxvc, q1_30 kc) {
    const std::int64_t sum = fx::mul_wide(r.cos, vc).raw() + fx::mul_wide(r.sin, kxvc).raw() +
                             fx::mul_wide(along, kc).raw();  // each < 2^61, sum < 2^62.6: no
    return fx::convert<q1_30>(W::from_raw(sum));             // overflow, |result| <= ~1
  };
  return {one(v.x, kxv.x, r.axis.x), one(v.y, kxv.y, r.axis.y), one(v.z, kxv.z, r.axis.z)};
}

// The point at angle ψ along the arc (equal-angle interpolation, no renormalisation).
constexpr Unit arc_at(const Arc& arc, angle_t psi) {
  if (!arc.has_direction()) return arc.from;
  const fx::SinCos sc = fx::sin_cos_fast(psi);
  return combine(sc.cos, arc.from, sc.sin, arc.tangent);
}

// The point at fraction t in [0, 1] of the arc (t in q1_30): ψ = t·θ.
constexpr Unit arc_at_fraction(const Arc& arc, q1_30 t) {
  return arc_at(arc, fx::mul_sat<angle_t>(t, arc.angle));
}

// The span's great circle seen from O (Kuijk-Blake eq. 4, Figure 10).
struct SpanCircle {
  angle_t s{};            // angle(O, S) in [0, π/2]: cos^n α = cos^n φ · cos^n s
  angle_t phi_left{};     // φ at V_L
  angle_t theta{};        // arc angle from V_L to V_R (φ at V_R = phi_left + theta)
  bool constant = false;  // V_L ≈ V_R: φ does not change along the span
};

// For any unit O (the paper takes (0, 0, 1); the methods may pick one per triangle, see
// shade_kb_one_vector.cpp): with pole P and Q' = P × O, |Q'| = cos s and P·O = ±sin s, and
//   cos s·(V·S) = V·O,   cos s·(V·Q) = V·Q'   (Q = P × S = Q'/cos s),
// so φ(V) = atan2(V·Q', V·O), s = atan2(|P·O|, |Q'|).
//
// The pole comes from the exact cross product V_L × V_R (Q.60, two exact products per
// component; |V_L × V_R| = sin θ), scaled by a power of two to unit size: no normalisation, and
// exact in direction up to that one rounding. s and φ are ratios, so the scale drops out of s
// and is carried as |P| in φ; θ = atan2(sin θ, cos θ). Only a pole of a few LSB (V_L ≈ ±V_R)
// takes the arc construction below (constant span, or the half turn).
constexpr SpanCircle span_circle(const Unit& vl, const Unit& vr, const Unit& o = kO) {
  SpanCircle c;
  using W = fx::Q<2, 60, std::int64_t>;
  const ExactPole pole = exact_pole(vl, vr);
  if (pole.width != 0) {
    const Unit pn = scaled_pole(pole);
    const q1_30 pn_len = length(pn);  // in [2^29, √3·2^30) raw
    const Unit q = fx::cross<q1_30>(pn, o);
    c.s = fx::atan2_fast(fx::abs_sat(fx::dot<q1_30>(pn, o)), length(q));
    // φ_L = atan2(V_L·Q', V_L·O) with Q' = P × O = (Pn × O)/|Pn|: both sides times |Pn|, in Q.60.
    const std::int64_t num = fx::dot<W>(vl, q).raw();
    const std::int64_t den = std::int64_t{fx::dot<q1_30>(vl, o).raw()} * pn_len.raw();
    c.phi_left = fx::atan2_fast(num, den);
    c.theta = pole_angle(pole, pn_len, fx::dot<q1_30>(vl, vr));
    return c;
  }
  const Arc arc = make_arc(vl, vr);
  if (!arc.has_direction()) {
    // V_L ≈ V_R: take the circle through O and V_L (s = 0, φ = angle(O, V_L)).
    c.constant = true;
    c.phi_left = fx::atan2_fast(length(fx::cross<q1_30>(vl, o)), fx::dot<q1_30>(vl, o));
    return c;
  }
  // Pole of the arc's plane; unit because from ⟂ tangent, both unit.
  const Unit p = fx::cross<q1_30>(arc.from, arc.tangent);
  const Unit q = fx::cross<q1_30>(p, o);
  c.s = fx::atan2_fast(fx::abs_sat(fx::dot<q1_30>(p, o)), length(q));
  c.phi_left = fx::atan2_fast(fx::dot<q1_30>(vl, q), fx::dot<q1_30>(vl, o));
  c.theta = arc.angle;
  return c;
}

// φ along the pixels of a span: φ(x) = φ_L + (x − x_L)·θ / (x_R − x_L), sampled at the
// first pixel centre and stepped by dφ per pixel.
struct SpanLine {
  angle_t phi_first{};
  dangle_t dphi{};
};

// φ_first is wrapped into [−π, π] (φ_L + θ may reach 2π, beyond angle_t's range, when V
// passes the point opposite S: f is even and 2π-periodic in that sense, cos φ being so).
// φ_first alone (span_line's, without the dφ division).
constexpr angle_t span_phi_first(const SpanCircle& c, xpos_t x_left, xpos_t x_right,
                                 xpos_t first_centre) {
  if (c.constant) return c.phi_left;
  const xpos_t width = fx::sub_sat(x_right, x_left);
  if (width.raw() <= 0) return c.phi_left;
  // Fraction of the span width at the first centre, clamped to [0, 1] (a centre is inside).
  q1_30 frac = fx::div<q1_30>(fx::sub_sat(first_centre, x_left), width);
  if (frac.raw() < 0) frac = q1_30::zero();
  if (frac > q1_30::one()) frac = q1_30::one();
  const std::int64_t phi =
      std::int64_t{c.phi_left.raw()} + fx::mul_sat<angle_t>(frac, c.theta).raw();  // < 2π + 1 LSB
  return angle_t::from_raw_sat(wrap_pi(phi));
}

constexpr SpanLine span_line(const SpanCircle& c, xpos_t x_left, xpos_t x_right,
                             xpos_t first_centre) {
  SpanLine line{span_phi_first(c, x_left, x_right, first_centre), dangle_t::zero()};
  if (c.constant) return line;
  const xpos_t width = fx::sub_sat(x_right, x_left);
  if (width.raw() <= 0) return line;
  line.dphi = fx::div<dangle_t>(c.theta, width);
  return line;
}

}  // namespace tp::fw::kb
