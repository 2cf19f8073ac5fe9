// Three-component fixed-point vectors.
//
//   dot<To>(a, b)        exact wide sum of the three products, one rounding (<= 0.5 LSB).
//   cross<To>(a, b)      each component an exact difference of two products, one rounding.
//   normalize<To>(v)     v / |v| with the exact squared length and rsqrt_core (Q2.62), one
//                        rounding per component: <= 0.5 LSB + ~2^-59 relative.
//                        The zero vector gives the zero vector (documented, tested).
//   try_normalize<To>    as normalize, false (and `out` untouched) for the zero vector.
//   add_sat / sub_sat / neg_sat / scale (saturating, per component), length_squared<To>.
// All results round to nearest, ties away from zero, and saturate to To.
#pragma once

#include "fixedpoint/q.hpp"
#include "fixedpoint/sqrt.hpp"
#include "fixedpoint/wide.hpp"

namespace tp::fx {

template <QType T>
struct Vec3 {
  T x, y, z;
  friend constexpr bool operator==(const Vec3&, const Vec3&) = default;
};

namespace detail {
// Products a.raw * b.raw of two formats whose exact product fits 62 bits (so that up to three
// of them sum exactly in detail::exact_sum).
template <QType A, QType B>
constexpr wide_t raw_product(A a, B b) {
  static_assert(A::int_bits + A::frac_bits + B::int_bits + B::frac_bits <= 62,
                "exact product must fit 62 bits");
  return wide_t{a.raw()} * wide_t{b.raw()};
}
template <QType To, QType A, QType B>
constexpr To round_products(const wide_t* terms, int count) {
  const SignMag s = exact_sum(terms, count);
  return from_sign_mag_scaled<To>(s.negative, s.mag, A::frac_bits + B::frac_bits - To::frac_bits);
}
}  // namespace detail

template <QType To, QType A, QType B>
constexpr To dot(const Vec3<A>& a, const Vec3<B>& b) {
  const detail::wide_t t[3] = {detail::raw_product(a.x, b.x), detail::raw_product(a.y, b.y),
                               detail::raw_product(a.z, b.z)};
  return detail::round_products<To, A, B>(t, 3);
}

template <QType To, QType A, QType B>
constexpr Vec3<To> cross(const Vec3<A>& a, const Vec3<B>& b) {
  const detail::wide_t x[2] = {detail::raw_product(a.y, b.z), -detail::raw_product(a.z, b.y)};
  const detail::wide_t y[2] = {detail::raw_product(a.z, b.x), -detail::raw_product(a.x, b.z)};
  const detail::wide_t z[2] = {detail::raw_product(a.x, b.y), -detail::raw_product(a.y, b.x)};
  return {detail::round_products<To, A, B>(x, 2), detail::round_products<To, A, B>(y, 2),
          detail::round_products<To, A, B>(z, 2)};
}

template <QType To, QType T>
constexpr To length_squared(const Vec3<T>& v) {
  return dot<To>(v, v);
}

template <QType T>
constexpr Vec3<T> add_sat(const Vec3<T>& a, const Vec3<T>& b) {
  return {add_sat(a.x, b.x), add_sat(a.y, b.y), add_sat(a.z, b.z)};
}
template <QType T>
constexpr Vec3<T> sub_sat(const Vec3<T>& a, const Vec3<T>& b) {
  return {sub_sat(a.x, b.x), sub_sat(a.y, b.y), sub_sat(a.z, b.z)};
}
template <QType T>
constexpr Vec3<T> neg_sat(const Vec3<T>& a) {
  return {neg_sat(a.x), neg_sat(a.y), neg_sat(a.z)};
}
// Each component times a scalar, rounded and saturated into To.
template <QType To, QType T, QType S>
constexpr Vec3<To> scale(const Vec3<T>& v, S s) {
  return {mul_sat<To>(v.x, s), mul_sat<To>(v.y, s), mul_sat<To>(v.z, s)};
}
// Per-component format change, rounded and saturated.
template <QType To, QType T>
constexpr Vec3<To> convert(const Vec3<T>& v) {
  return {convert<To>(v.x), convert<To>(v.y), convert<To>(v.z)};
}

template <QType To, QType T>
constexpr bool try_normalize(const Vec3<T>& v, Vec3<To>& out) {
  static_assert(2 * (T::int_bits + T::frac_bits) <= 62, "squares must sum exactly in 64 bits");
  const detail::wide_t sq[3] = {detail::raw_product(v.x, v.x), detail::raw_product(v.y, v.y),
                                detail::raw_product(v.z, v.z)};
  const detail::SignMag len_sq = detail::exact_sum(sq, 3);  // >= 0, <= 3 * 2^62
  if (len_sq.mag == 0) return false;
  const auto r = detail::rsqrt_core(len_sq.mag, 2 * T::frac_bits);
  // Component raw in To = c * mantissa * 2^(FT - F - 62 - exp2): one exact 128-bit product and
  // one rounding.
  const int sh = T::frac_bits + 62 + r.exp2 - To::frac_bits;
  const auto one = [&](T c) {
    const detail::wide_t raw = c.raw();
    const detail::U128 p = detail::mul_u64(detail::magnitude(raw), r.mantissa);
    bool over = false;
    detail::u64 m = 0;
    if (sh >= 0) {
      m = detail::round_shr(p, sh, over);
    } else {
      m = detail::round_shr(p, 0, over);
      if (!over) m = detail::shl_checked(m, -sh, over);
    }
    return detail::from_sign_mag<To>(raw < 0, m, over);
  };
  out = {one(v.x), one(v.y), one(v.z)};
  return true;
}

template <QType To, QType T>
constexpr Vec3<To> normalize(const Vec3<T>& v) {
  Vec3<To> out{To::zero(), To::zero(), To::zero()};
  (void)try_normalize(v, out);
  return out;
}

}  // namespace tp::fx
