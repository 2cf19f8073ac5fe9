// Rotation quaternions q = (w, x, y, z) = (cos θ/2, sin θ/2 · axis), for Kuijk-Blake eq. 4:
// V = R(N->O) · L, the rotation taking the normal N onto the fixed O, applied to L (a rotation
// keeps angles, so angle(V, O) = angle(N, L)).
//
//   rotation_between<To>(from, to)  minimal rotation taking unit `from` onto unit `to`.
//   rotate<To>(q, v)                v + 2w (u x v) + 2 u x (u x v), u = (x, y, z).
//   multiply<To>(a, b)              Hamilton product a b (apply b, then a).
//   conjugate(q)                    (w, -x, -y, -z), the inverse of a unit quaternion.
//   normalize<To>(q)                q / |q|; the zero quaternion gives the identity (documented).
//   identity<T>()                   (1, 0, 0, 0).
//
// Every result is an exact wide (128-bit, built from 32x32 multiplies) integer expression
// rounded once per component: to nearest, ties away from zero, saturated to To (q.hpp).
// Measured accuracy and the antipodal threshold: docs/ACCURACY.md and
// tests/fixedpoint/test_quat.cpp.
#pragma once

#include <cstdint>

#include "fixedpoint/q.hpp"
#include "fixedpoint/sqrt.hpp"
#include "fixedpoint/vec3.hpp"
#include "fixedpoint/wide.hpp"

namespace tp::fx {

template <QType T>
struct Quat {
  T w, x, y, z;
  friend constexpr bool operator==(const Quat&, const Quat&) = default;
};

template <QType T>
constexpr Quat<T> identity() {
  return {T::one(), T::zero(), T::zero(), T::zero()};
}

namespace detail {

// Signed 128-bit values as two's complement in U128; every caller keeps |value| < 2^127.
constexpr U128 add128(U128 a, U128 b) {
  U128 r{a.hi + b.hi, a.lo + b.lo};
  if (r.lo < a.lo) ++r.hi;  // carry
  return r;
}
constexpr U128 neg128(U128 a) {
  U128 r{~a.hi, ~a.lo};
  if (++r.lo == 0) ++r.hi;
  return r;
}
constexpr bool is_neg128(U128 a) { return (a.hi >> 63) != 0; }
constexpr U128 mul_s64(wide_t a, wide_t b) {
  const U128 m = mul_u64(magnitude(a), magnitude(b));
  return (a < 0) != (b < 0) ? neg128(m) : m;
}
// v * 2^k, 0 <= k < 64, for |v| * 2^k < 2^127.
constexpr U128 shl128(U128 v, int k) {
  if (k == 0) return v;
  return U128{(v.hi << k) | (v.lo >> (64 - k)), v.lo << k};
}

// round(|m| / 2^sh) signed and saturated into To; sh may be negative (then m * 2^-sh).
template <QType To>
constexpr To round_mag128(bool negative, U128 m, int sh) {
  bool over = false;
  u64 r = 0;
  if (sh >= 0) {
    r = round_shr(m, sh, over);
  } else {
    r = round_shr(m, 0, over);
    if (!over) r = shl_checked(r, -sh, over);
  }
  return from_sign_mag<To>(negative, r, over);
}
template <QType To>
constexpr To round128(U128 v, int sh) {
  const bool negative = is_neg128(v);
  return round_mag128<To>(negative, negative ? neg128(v) : v, sh);
}

// 1/sqrt(p * 2^-frac) for p > 0 given in 128 bits: the top 64 bits go to rsqrt_core. The
// truncated low bits change p by < 2^-63 relative, 1/sqrt(p) by < 2^-64: far below any output.
constexpr RsqrtResult rsqrt128(U128 p, int frac) {
  if (p.hi == 0) return rsqrt_core(p.lo, frac);
  const int k = bit_width(p.hi);  // 1..64: bits to drop so that p fits u64
  const u64 u = k == 64 ? p.hi : (p.hi << (64 - k)) | (p.lo >> k);
  return rsqrt_core(u, frac - k);
}

// num * r.mantissa / 2^sh (r an rsqrt_core result), rounded once into To; the caller folds
// the units of num, r.exp2 and To's fractional bits into sh.
template <QType To>
constexpr To scale_by_rsqrt(wide_t num, RsqrtResult r, int sh) {
  return round_mag128<To>(num < 0, mul_u64(magnitude(num), r.mantissa), sh);
}

constexpr wide_t clamp_unit_raw(wide_t raw, int frac) {
  const wide_t one = wide_t{1} << frac;
  return clamp(raw, -one, one);
}

constexpr wide_t abs_wide(wide_t v) { return v < 0 ? -v : v; }  // callers: |v| <= 2^32

// Antipodal threshold: rotation_between takes the 180-degree path when |p| < 2^(kLog2 - F),
// p = (|s|^2/2, from x to) (see rotation_between), F the inputs' fractional bits. Below it the
// input rounding (| |from| - |to| |^2 / 2 <= 1.5 * 2^-2F enters w, and from x to may vanish
// for rounded vectors that are exactly anti-parallel) outweighs the rotation itself. kLog2 = 0,
// i.e. |p| below one input LSB, was chosen by measurement: sweeping kLog2 in -2..3 over pairs
// at angle π - 2^-k (k = 26..34) and exactly opposite rounded pairs, the worst error of
// rotate(q, from) against `to` is smallest at 0 (3.66 LSB; +1: 3.72, -1: 4.75, +2: 5.26;
// tests/fixedpoint/test_quat.cpp, QuatAntipodal.ThresholdIsTheMeasuredBest).
inline constexpr int kAntipodalLog2 = 0;

// true iff p < 2^e (e < 128; false for e < 0).
constexpr bool below_pow2(U128 p, int e) {
  if (e < 0) return false;
  if (e >= 64) return p.hi < (u64{1} << (e - 64));
  return p.hi == 0 && p.lo < (u64{1} << e);
}

// 180 degrees about normalize(from x e), e the basis axis least aligned with `from` (smallest
// |component|; ties go to the lower index x < y < z), so the axis is deterministic and as far
// from degenerate as the basis allows.
template <QType To, QType T>
constexpr Quat<To> half_turn_perpendicular(Vec3<T> f) {
  const wide_t ax = abs_wide(f.x.raw()), ay = abs_wide(f.y.raw()), az = abs_wide(f.z.raw());
  Vec3<T> c{T::zero(), T::zero(), T::zero()};
  if (ax <= ay && ax <= az) {
    c = {T::zero(), f.z, neg_sat(f.y)};  // f x (1, 0, 0)
  } else if (ay <= az) {
    c = {neg_sat(f.z), T::zero(), f.x};  // f x (0, 1, 0)
  } else {
    c = {f.y, neg_sat(f.x), T::zero()};  // f x (0, 0, 1)
  }
  const Vec3<To> axis = normalize<To>(c);
  return {To::zero(), axis.x, axis.y, axis.z};
}

// rotation_between with the antipodal threshold as a parameter (the tests sweep it to measure
// the crossover; everything else calls rotation_between).
template <QType To, QType T>
constexpr Quat<To> rotation_between_with(Vec3<T> from, Vec3<T> to, int antipodal_log2) {
  static_assert(T::int_bits + T::frac_bits <= 31 && T::frac_bits >= 1,
                "inputs up to 32-bit storage");
  static_assert(To::frac_bits <= 62, "output format");
  wide_t f[3] = {from.x.raw(), from.y.raw(), from.z.raw()};
  wide_t t[3] = {to.x.raw(), to.y.raw(), to.z.raw()};
  if ((f[0] == 0 && f[1] == 0 && f[2] == 0) || (t[0] == 0 && t[1] == 0 && t[2] == 0))
    return identity<To>();
  int frac = T::frac_bits;
  // |raw| <= 2^30 keeps |s_i| <= 2^31, s_i^2 and every product <= 2^62. Unit inputs in up to
  // 30 fractional bits already satisfy it; otherwise one halving suffices (|raw| <= 2^31).
  constexpr wide_t kRawLimit = wide_t{1} << 30;
  bool big = false;
  for (int i = 0; i < 3; ++i)
    big = big || detail::abs_wide(f[i]) > kRawLimit || detail::abs_wide(t[i]) > kRawLimit;
  if (big) {
    for (int i = 0; i < 3; ++i) {
      f[i] = round_shift_right(f[i], 1);
      t[i] = round_shift_right(t[i], 1);
    }
    --frac;
  }
  // s = from + to; W = |s|^2 (units 2^-2F) = 2 w_num in units 2^-(2F+1): w_num = |s|^2 / 2.
  detail::u64 w_num = 0;
  for (int i = 0; i < 3; ++i) {
    const wide_t s = f[i] + t[i];
    w_num += detail::magnitude(s * s);  // <= 3 * 2^62 in total
  }
  // Vector part from x to, doubled into the same units 2^-(2F+1) as w_num.
  const wide_t v[3] = {2 * (f[1] * t[2] - f[2] * t[1]), 2 * (f[2] * t[0] - f[0] * t[2]),
                       2 * (f[0] * t[1] - f[1] * t[0])};  // each |.| <= 2 * 2^61 = 2^62
  // |p|^2 in units 2^-(4F+2): w_num^2 + |v|^2 <= 9 * 2^124 + 3 * 2^124 < 2^128.
  detail::U128 p2 = detail::mul_u64(w_num, w_num);
  for (int i = 0; i < 3; ++i) p2 = detail::add128(p2, detail::mul_s64(v[i], v[i]));
  // |p| < 2^(k - F)  <=>  p2 < 2^(2k - 2F + 4F + 2) = 2^(2k + 2F + 2).
  if (detail::below_pow2(p2, 2 * antipodal_log2 + 2 * frac + 2))
    return detail::half_turn_perpendicular<To>(from);
  // Component = num / sqrt(p2) (same units cancel): raw = num * mantissa * 2^(FT - 62 - exp2).
  const detail::RsqrtResult r = detail::rsqrt128(p2, 0);
  const int sh = 62 + r.exp2 - To::frac_bits;
  return {detail::round_mag128<To>(false, detail::mul_u64(w_num, r.mantissa), sh),
          detail::scale_by_rsqrt<To>(v[0], r, sh), detail::scale_by_rsqrt<To>(v[1], r, sh),
          detail::scale_by_rsqrt<To>(v[2], r, sh)};
}
}  // namespace detail

// Minimal rotation taking unit `from` onto unit `to` (Kuijk-Blake's R(N->O), eq. 4).
//
// Half-vector construction: with s = from + to and h = s/|s|, q = (from.h, from x h). Taken
// literally with rounded inputs, from.h = (|from|^2 + from.to)/|s| carries (|from|^2 - |to|^2)/2
// / |s| of input rounding, amplified without bound as |s| -> 0. So w is symmetrised to
// s.s/2 / |s| = |s|/2 (exact for unit inputs, error (|from| - |to|)^2/2 ~ 2^-2F otherwise), and
// the whole quaternion p = (|s|^2/2, from x to) is divided by its own exact length: q = p/|p|,
// integer numerators, one 128-bit |p|^2, one rsqrt, one rounding per component.
//
// Degenerate inputs (documented, tested):
//  - from or to the zero vector: identity.
//  - antipodal (|p| < 2^(kAntipodalLog2 - F) = one input LSB, i.e. from = -to up to the
//    input rounding; for unit inputs |p| = 2 cos(θ/2) ~ π - θ, so θ > π - 2^-F): 180
//    degrees about normalize(from x e), e the basis axis least aligned with `from`.
// Non-unit inputs are outside the contract: components beyond [-1, 1] are first halved,
// rounded, so that no intermediate can overflow, and the result is a unit quaternion; it is
// the rotation between the directions only as far as |from| = |to| (w assumes it).
template <QType To, QType T>
constexpr Quat<To> rotation_between(Vec3<T> from, Vec3<T> to) {
  return detail::rotation_between_with<To>(from, to, detail::kAntipodalLog2);
}

// v + 2w (u x v) + 2 u x (u x v), u = (q.x, q.y, q.z): the rotation of v by unit q. Exact in
// 128 bits (units 2^-(2 Fq + Fv)), one rounding per component. q's components are clamped to
// [-1, 1] first (a unit quaternion's already are), which bounds every intermediate.
template <QType To, QType Tq, QType Tv>
constexpr Vec3<To> rotate(Quat<Tq> q, Vec3<Tv> v) {
  using detail::U128;
  using detail::wide_t;
  static_assert(Tq::frac_bits <= 30 && Tq::frac_bits >= 1,
                "quaternion components in Q?.30 at most");
  static_assert(Tv::int_bits + Tv::frac_bits <= 31, "vectors up to 32-bit storage");
  constexpr int fq = Tq::frac_bits;
  const wide_t w = detail::clamp_unit_raw(q.w.raw(), fq);
  const wide_t u[3] = {detail::clamp_unit_raw(q.x.raw(), fq), detail::clamp_unit_raw(q.y.raw(), fq),
                       detail::clamp_unit_raw(q.z.raw(), fq)};
  const wide_t a[3] = {v.x.raw(), v.y.raw(), v.z.raw()};
  // c = u x v: |u_i| <= 2^30, |v_i| <= 2^31, so each difference is <= 2^62.
  const wide_t c[3] = {u[1] * a[2] - u[2] * a[1], u[2] * a[0] - u[0] * a[2],
                       u[0] * a[1] - u[1] * a[0]};
  const auto component = [&](int i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    // v_i 2^(2 Fq) + 2 (w c_i + (u x c)_i); magnitudes <= 2^91 + 2 (2^92 + 2^93) < 2^95.
    U128 acc = detail::mul_s64(w, c[i]);
    acc = detail::add128(acc, detail::mul_s64(u[j], c[k]));
    acc = detail::add128(acc, detail::neg128(detail::mul_s64(u[k], c[j])));
    acc = detail::shl128(acc, 1);
    acc = detail::add128(acc, detail::shl128(detail::mul_s64(a[i], 1), 2 * fq));
    return detail::round128<To>(acc, 2 * fq + Tv::frac_bits - To::frac_bits);
  };
  return {component(0), component(1), component(2)};
}

// Hamilton product a b: rotating by it applies b first, then a. Each component an exact sum of
// four products (128-bit), rounded once.
template <QType To, QType A, QType B>
constexpr Quat<To> multiply(Quat<A> a, Quat<B> b) {
  using detail::mul_s64;
  using detail::U128;
  static_assert(A::int_bits + A::frac_bits <= 31 && B::int_bits + B::frac_bits <= 31,
                "components up to 32-bit storage");
  const detail::wide_t aw = a.w.raw(), ax = a.x.raw(), ay = a.y.raw(), az = a.z.raw();
  const detail::wide_t bw = b.w.raw(), bx = b.x.raw(), by = b.y.raw(), bz = b.z.raw();
  const auto sum4 = [](U128 p0, U128 p1, U128 p2, U128 p3) {
    return detail::add128(detail::add128(p0, p1), detail::add128(p2, p3));
  };
  constexpr auto neg = [](U128 v) { return detail::neg128(v); };
  constexpr int sh = A::frac_bits + B::frac_bits - To::frac_bits;
  return {detail::round128<To>(sum4(mul_s64(aw, bw), neg(mul_s64(ax, bx)), neg(mul_s64(ay, by)),
                                    neg(mul_s64(az, bz))),
                               sh),
          detail::round128<To>(
              sum4(mul_s64(aw, bx), mul_s64(ax, bw), mul_s64(ay, bz), neg(mul_s64(az, by))), sh),
          detail::round128<To>(
              sum4(mul_s64(aw, by), neg(mul_s64(ax, bz)), mul_s64(ay, bw), mul_s64(az, bx)), sh),
          detail::round128<To>(
              sum4(mul_s64(aw, bz), mul_s64(ax, by), neg(mul_s64(ay, bx)), mul_s64(az, bw)), sh)};
}

// (w, -x, -y, -z); saturating, so a component at T::min() becomes T::max().
template <QType T>
constexpr Quat<T> conjugate(Quat<T> q) {
  return {q.w, neg_sat(q.x), neg_sat(q.y), neg_sat(q.z)};
}

// q / |q| with the exact 128-bit |q|^2 and one rounding per component. The zero quaternion
// has no direction; it gives the identity (documented, tested), the neutral rotation.
template <QType To, QType T>
constexpr Quat<To> normalize(Quat<T> q) {
  static_assert(T::int_bits + T::frac_bits <= 31, "components up to 32-bit storage");
  const detail::wide_t c[4] = {q.w.raw(), q.x.raw(), q.y.raw(), q.z.raw()};
  detail::U128 n2{0, 0};  // <= 4 * 2^62
  for (detail::wide_t ci : c) n2 = detail::add128(n2, detail::mul_s64(ci, ci));
  if (n2.hi == 0 && n2.lo == 0) return identity<To>();
  const detail::RsqrtResult r = detail::rsqrt128(n2, 2 * T::frac_bits);
  const int sh = T::frac_bits + 62 + r.exp2 - To::frac_bits;
  return {detail::scale_by_rsqrt<To>(c[0], r, sh), detail::scale_by_rsqrt<To>(c[1], r, sh),
          detail::scale_by_rsqrt<To>(c[2], r, sh), detail::scale_by_rsqrt<To>(c[3], r, sh)};
}

}  // namespace tp::fx
