// Quaternion accuracy cases (fixedpoint/quat.hpp), same conventions as measure.hpp: errors in
// LSB of Q1.30 (angles in units of 2^-30 rad) against long double. The inputs are exact unit
// vectors (long double, fixed seed) rounded to Q1.30; references are computed from the rounded
// inputs (normalised in long double) unless a case says otherwise. Host code.
#pragma once

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "fixedpoint/quat.hpp"
#include "tests/fixedpoint/measure.hpp"

namespace tp::fx::testing {

using v30 = Vec3<q1_30>;
using quat30 = Quat<q1_30>;
using LdVec = std::array<long double, 3>;

inline q1_30 round30(long double x) { return q_raw<q1_30>(std::llround(std::ldexp(x, 30))); }
inline v30 round30(const LdVec& a) { return {round30(a[0]), round30(a[1]), round30(a[2])}; }
inline LdVec to_ldv(v30 v) { return {to_ld(v.x), to_ld(v.y), to_ld(v.z)}; }

inline long double ld_dot(const LdVec& a, const LdVec& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
inline LdVec ld_cross(const LdVec& a, const LdVec& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline long double ld_len(const LdVec& a) { return std::sqrt(ld_dot(a, a)); }
inline LdVec ld_unit(const LdVec& a) {
  const long double l = ld_len(a);
  return {a[0] / l, a[1] / l, a[2] / l};
}
// Angle between two vectors, well conditioned near 0 and π.
inline long double ld_angle(const LdVec& a, const LdVec& b) {
  return std::atan2(ld_len(ld_cross(a, b)), ld_dot(a, b));
}

// Random exact unit vectors (Gaussian direction), fixed seed.
inline std::vector<LdVec> random_units(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  std::vector<LdVec> v(n);
  for (auto& a : v) {
    do a = {g(rng), g(rng), g(rng)};
    while (ld_len(a) < 1e-3L);
    a = ld_unit(a);
  }
  return v;
}
// A unit vector at exactly `angle` from unit a (towards the random unit p, made perpendicular).
inline LdVec at_angle(const LdVec& a, const LdVec& p, long double angle) {
  const long double d = ld_dot(a, p);
  const LdVec perp = ld_unit({p[0] - d * a[0], p[1] - d * a[1], p[2] - d * a[2]});
  const long double c = std::cos(angle), s = std::sin(angle);
  return {c * a[0] + s * perp[0], c * a[1] + s * perp[1], c * a[2] + s * perp[2]};
}

// Reference rotation between the directions of two (rounded) vectors: half vector of the
// exact unit directions, q = (|s|/2, (a x b)/|s|), s = a + b.
inline std::array<long double, 4> ld_rotation_between(v30 f, v30 t) {
  const LdVec a = ld_unit(to_ldv(f)), b = ld_unit(to_ldv(t));
  const LdVec s = {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
  const long double ls = ld_len(s);
  const LdVec c = ld_cross(a, b);
  return {ls / 2, c[0] / ls, c[1] / ls, c[2] / ls};
}
// The rotate formula v + 2w (u x v) + 2 u x (u x v) on the fixed q taken as exact.
inline LdVec ld_rotate(quat30 q, const LdVec& v) {
  const LdVec u = {to_ld(q.x), to_ld(q.y), to_ld(q.z)};
  const long double w = to_ld(q.w);
  const LdVec c = ld_cross(u, v), cc = ld_cross(u, c);
  return {v[0] + 2 * w * c[0] + 2 * cc[0], v[1] + 2 * w * c[1] + 2 * cc[1],
          v[2] + 2 * w * c[2] + 2 * cc[2]};
}

inline void add_quat_err(ErrStats& s, quat30 q, const std::array<long double, 4>& r) {
  s.add(err_lsb(q.w, r[0]));
  s.add(err_lsb(q.x, r[1]));
  s.add(err_lsb(q.y, r[2]));
  s.add(err_lsb(q.z, r[3]));
}
inline void add_vec_err(ErrStats& s, v30 v, const LdVec& r) {
  s.add(err_lsb(v.x, r[0]));
  s.add(err_lsb(v.y, r[1]));
  s.add(err_lsb(v.z, r[2]));
}
inline long double lsb30(long double x) { return std::ldexp(x, 30); }

// Pairs (from, to) of rounded unit vectors: random, or at angle π - eps.
struct UnitPair {
  v30 from, to;
  LdVec to_exact;  // the unit vector `to` was rounded from
};
inline std::vector<UnitPair> random_pairs(std::size_t n) {
  const auto a = random_units(n, 20261122u), b = random_units(n, 20261123u);
  std::vector<UnitPair> p;
  for (std::size_t i = 0; i < n; ++i) p.push_back({round30(a[i]), round30(b[i]), b[i]});
  return p;
}
inline std::vector<UnitPair> near_antipodal_pairs(std::size_t n, long double eps, unsigned seed) {
  const auto a = random_units(n, seed), d = random_units(n, seed + 1);
  std::vector<UnitPair> p;
  for (std::size_t i = 0; i < n; ++i) {
    const LdVec b = at_angle(a[i], d[i], std::acos(-1.0L) - eps);
    p.push_back({round30(a[i]), round30(b), b});
  }
  return p;
}

// rotation_between<Q1.30> against the long double reference, per component.
inline ErrStats measure_rotation_between(const std::vector<UnitPair>& ps) {
  ErrStats s;
  for (const auto& p : ps)
    add_quat_err(s, rotation_between<q1_30>(p.from, p.to), ld_rotation_between(p.from, p.to));
  return s;
}
// rotate<Q1.30>(q, v) against the same formula in long double on the same q: the rounding of
// rotate alone (q = rotation_between of the pair, v = a third random unit vector).
inline ErrStats measure_rotate_rounding(const std::vector<UnitPair>& ps) {
  ErrStats s;
  const auto ls = random_units(ps.size(), 99u);
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const quat30 q = rotation_between<q1_30>(ps[i].from, ps[i].to);
    const v30 v = round30(ls[i]);
    add_vec_err(s, rotate<q1_30>(q, v), ld_rotate(q, to_ldv(v)));
  }
  return s;
}
// rotate(rotation_between(from, to), from) against the direction of `to` (its rounded value,
// normalised): everything end to end.
inline ErrStats measure_maps_onto(const std::vector<UnitPair>& ps) {
  ErrStats s;
  for (const auto& p : ps)
    add_vec_err(s, rotate<q1_30>(rotation_between<q1_30>(p.from, p.to), p.from),
                ld_unit(to_ldv(p.to)));
  return s;
}
// |R L| - |L| (LSB) and angle(R L, R N) - angle(L, N) (2^-30 rad), R = rotation_between(N, T).
inline void measure_preservation(const std::vector<UnitPair>& ps, ErrStats& length,
                                 ErrStats& angle) {
  const auto ls = random_units(ps.size(), 77u);
  for (std::size_t i = 0; i < ps.size(); ++i) {
    const quat30 q = rotation_between<q1_30>(ps[i].from, ps[i].to);
    const v30 l = round30(ls[i]);
    const LdVec rl = to_ldv(rotate<q1_30>(q, l)), rn = to_ldv(rotate<q1_30>(q, ps[i].from));
    length.add(lsb30(ld_len(rl) - ld_len(to_ldv(l))));
    angle.add(lsb30(ld_angle(rl, rn) - ld_angle(to_ldv(l), to_ldv(ps[i].from))));
  }
}
// Kuijk-Blake eq. 4: V = R(N -> O) L with O = (0, 0, 1); angle(V, O) - angle(N, L) in 2^-30 rad.
inline ErrStats measure_kb_invariant(std::size_t n) {
  const auto ns = random_units(n, 555u), ls = random_units(n, 556u);
  const v30 o{q1_30::zero(), q1_30::zero(), q1_30::one()};
  ErrStats s;
  for (std::size_t i = 0; i < n; ++i) {
    const v30 nv = round30(ns[i]), lv = round30(ls[i]);
    const v30 v = rotate<q1_30>(rotation_between<q1_30>(nv, o), lv);
    s.add(lsb30(ld_angle(to_ldv(v), to_ldv(o)) - ld_angle(to_ldv(nv), to_ldv(lv))));
  }
  return s;
}

// End-to-end error of rotate(rotation_between_with(from, to, log2), from) against `to` over
// pairs at angle π - 2^-k, k = 26..34 (n each), plus n exactly opposite rounded pairs: the
// curve that fixes detail::kAntipodalLog2.
inline ErrStats measure_antipodal_sweep(int antipodal_log2, std::size_t n) {
  ErrStats s;
  const auto one = [&](v30 f, v30 t) {
    add_vec_err(s, rotate<q1_30>(detail::rotation_between_with<q1_30>(f, t, antipodal_log2), f),
                ld_unit(to_ldv(t)));
  };
  for (int k = 26; k <= 34; ++k)
    for (const auto& p :
         near_antipodal_pairs(n, std::ldexp(1.0L, -k), 900u + static_cast<unsigned>(k)))
      one(p.from, p.to);
  for (const auto& a : random_units(n, 4242u)) one(round30(a), neg_sat(round30(a)));
  return s;
}

inline std::vector<Case> quat_cases() {
  std::vector<Case> c;
  c.push_back({"rotation_between<Q1.30>(unit, unit)", "10^5 random unit pairs",
               [] { return measure_rotation_between(random_pairs(100000)); }});
  c.push_back({"rotation_between<Q1.30>(unit, unit)", "angle π - 1e-6, 10^4 pairs",
               [] { return measure_rotation_between(near_antipodal_pairs(10000, 1e-6L, 5u)); }});
  c.push_back({"rotate<Q1.30>(q, unit) (rounding only)", "10^5 random q, v",
               [] { return measure_rotate_rounding(random_pairs(100000)); }});
  c.push_back({"rotate(rotation_between(a, b), a) vs b", "10^5 random unit pairs",
               [] { return measure_maps_onto(random_pairs(100000)); }});
  c.push_back({"rotate(rotation_between(a, b), a) vs b", "angle π - 1e-6, 10^4 pairs",
               [] { return measure_maps_onto(near_antipodal_pairs(10000, 1e-6L, 5u)); }});
  c.push_back({"rotate(rotation_between(a, b), a) vs b",
               "angle π - 2^-k (k = 26..34) and exactly opposite, 10^4 each",
               [] { return measure_antipodal_sweep(detail::kAntipodalLog2, 10000); }});
  c.push_back({"norm(rotate(q, L)) - norm(L)", "10^5 random q, L", [] {
                 ErrStats len, ang;
                 measure_preservation(random_pairs(100000), len, ang);
                 return len;
               }});
  c.push_back({"angle(qL, qN) - angle(L, N) (2^-30 rad)", "10^5 random q, L, N", [] {
                 ErrStats len, ang;
                 measure_preservation(random_pairs(100000), len, ang);
                 return ang;
               }});
  c.push_back({"KB eq. 4: angle(R(N->O)L, O) - angle(N, L) (2^-30 rad)", "10^5 random N, L",
               [] { return measure_kb_invariant(100000); }});
  return c;
}

}  // namespace tp::fx::testing
