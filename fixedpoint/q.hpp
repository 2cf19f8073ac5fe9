// Q<IntBits, FracBits, Storage>: a signed fixed-point number whose format is in its type.
//
// Policy, visible in the names (after CNL / fpm):
//  - value = raw / 2^FracBits; the declared range is [-2^IntBits, 2^IntBits - 2^-FracBits].
//  - operator+ / operator- / unary - are exact and meant for sums whose bound is proven at the
//    call site (a comment there states it). They compute in Storage, so a violated bound is
//    signed overflow, which the sanitizer build turns into a test failure rather than a wrap.
//  - add_sat / sub_sat / neg_sat / mul_sat / convert saturate to the declared range instead.
//  - mul_wide is exact (the result type holds every product); convert<Q2> narrows with
//    round-to-nearest, ties away from zero (so round(-x) == -round(x): symmetric for negatives),
//    then saturates to Q2's range.
//  - No implicit conversions, to or from anything: from_raw / from_int / raw() only.
//
// Header-only and integer-only: no float, no heap, no exceptions, no I/O.
#pragma once

#include <bit>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "fixedpoint/build_goal.hpp"

namespace tp::fx {

// Size builds (TP_SIZE_BUILD, fixedpoint/build_goal.hpp; -Os by default) keep one out-of-line copy
// of round_shift_right and clamp below: on a 32-bit core each is a dozen instructions of 64-bit
// arithmetic, which GCC at -Os otherwise copies into about a hundred callers (2,084 bytes of the
// Cortex-M3 -Os image; docs/TARGET.md, "Footprint"). Speed builds inline them; the results are
// the same.
// TP_FX_INLINE marks the few helpers a size build copies into a hot loop all the same, where a
// call costs more time than the copy costs code (docs/TARGET.md, "Footprint").
#if TP_SIZE_BUILD
#define TP_FX_OUTLINE [[gnu::noinline]]
#define TP_FX_INLINE [[gnu::always_inline]]
#else
#define TP_FX_OUTLINE
#define TP_FX_INLINE
#endif

// Raw-integer vocabulary, for code that works on raw values between Q types (the rounding and
// saturation every Q operation below is built from):
//   round_shift_right(v, s)  v / 2^s rounded to nearest, ties away from zero (the rounding of
//                            convert and mul_sat); exact for |v| < 2^62.
//   clamp(v, lo, hi)         v limited to [lo, hi] (lo <= hi).
//   bit_width(m)             the bits of the magnitude m, std::bit_width's as an int (the
//                            shift that normalises m; 0 for 0).

namespace detail {
// round_shift_right's body, inlined wherever it is called, also in size builds (TP_FX_INLINE).
// For v < 0 the tie away from zero, −((−v + half) >> shift), is the floor (v + half − 1) >>
// shift: v >> 63 supplies the −1 without a branch on the sign.
TP_FX_INLINE constexpr std::int64_t round_shift_right_inline(std::int64_t v, int shift) {
  if (shift <= 0) return v;
  const std::int64_t half = std::int64_t{1} << (shift - 1);
  return (v + half + (v >> 63)) >> shift;
}
}  // namespace detail

TP_FX_OUTLINE constexpr std::int64_t round_shift_right(std::int64_t v, int shift) {
  return detail::round_shift_right_inline(v, shift);
}

TP_FX_OUTLINE constexpr std::int64_t clamp(std::int64_t v, std::int64_t lo, std::int64_t hi) {
  return v < lo ? lo : (v > hi ? hi : v);
}

// A count of leading zeros of a 64-bit value is some ten instructions on a 32-bit core.
TP_FX_OUTLINE constexpr int bit_width(std::uint64_t m) {
  return static_cast<int>(std::bit_width(m));
}

namespace detail {

// The widest integer a 32-bit target has natively; all intermediate results fit in it.
using wide_t = std::int64_t;

template <class S>
constexpr int storage_bits = std::numeric_limits<S>::digits;  // excludes the sign bit

}  // namespace detail

template <int IntBits, int FracBits, class Storage = std::int32_t>
class Q {
  static_assert(std::is_integral_v<Storage> && std::is_signed_v<Storage>,
                "Q stores a signed integer");
  static_assert(IntBits >= 0 && FracBits >= 0, "bit counts are non-negative");
  static_assert(IntBits + FracBits <= detail::storage_bits<Storage>,
                "IntBits + FracBits + sign must fit the storage");
  static_assert(IntBits + FracBits <= 62, "intermediate arithmetic is 64-bit");

 public:
  using storage_type = Storage;
  static constexpr int int_bits = IntBits;
  static constexpr int frac_bits = FracBits;
  static constexpr detail::wide_t one_raw = detail::wide_t{1} << FracBits;
  static constexpr detail::wide_t max_raw = (detail::wide_t{1} << (IntBits + FracBits)) - 1;
  static constexpr detail::wide_t min_raw = -(detail::wide_t{1} << (IntBits + FracBits));

  constexpr Q() = default;

  static constexpr Q from_raw(Storage raw) { return Q(raw); }
  // Saturating construction from any integer raw value (e.g. a wide intermediate).
  static constexpr Q from_raw_sat(detail::wide_t raw) {
    return Q(static_cast<Storage>(clamp(raw, min_raw, max_raw)));
  }
  // Integer value; saturates when it does not fit the declared range.
  static constexpr Q from_int(detail::wide_t v) {
    const detail::wide_t lim = detail::wide_t{1} << IntBits;
    if (v >= lim) return max();
    if (v < -lim) return min();
    return Q(static_cast<Storage>(v * one_raw));
  }
  // A ratio num/den rounded to nearest (ties away from zero); den > 0. For constants.
  static constexpr Q from_ratio(detail::wide_t num, detail::wide_t den) {
    const detail::wide_t scaled = num * one_raw;  // callers keep |num| < 2^(62-FracBits)
    const detail::wide_t q = (scaled >= 0 ? scaled + den / 2 : scaled - den / 2) / den;
    return from_raw_sat(q);
  }
  static constexpr Q one() { return from_int(1); }
  static constexpr Q zero() { return Q(Storage{0}); }
  static constexpr Q max() { return Q(static_cast<Storage>(max_raw)); }
  static constexpr Q min() { return Q(static_cast<Storage>(min_raw)); }
  static constexpr Q epsilon() { return Q(Storage{1}); }

  constexpr Storage raw() const { return raw_; }

  // Exact arithmetic for proven-bounded use (see the header comment).
  friend constexpr Q operator+(Q a, Q b) { return Q(static_cast<Storage>(a.raw_ + b.raw_)); }
  friend constexpr Q operator-(Q a, Q b) { return Q(static_cast<Storage>(a.raw_ - b.raw_)); }
  friend constexpr Q operator-(Q a) { return Q(static_cast<Storage>(-a.raw_)); }
  constexpr Q& operator+=(Q b) { return *this = *this + b; }
  constexpr Q& operator-=(Q b) { return *this = *this - b; }

  friend constexpr bool operator==(Q a, Q b) { return a.raw_ == b.raw_; }
  friend constexpr auto operator<=>(Q a, Q b) { return a.raw_ <=> b.raw_; }

 private:
  constexpr explicit Q(Storage raw) : raw_(raw) {}
  Storage raw_ = 0;
};

template <class T>
struct is_q : std::false_type {};
template <int I, int F, class S>
struct is_q<Q<I, F, S>> : std::true_type {};
template <class T>
concept QType = is_q<T>::value;

namespace detail {
// x.raw() moved from From's to To's fractional bits, rounded, not yet saturated. A left shift
// that would leave 64 bits is clamped first; the clamped value is still outside To's range,
// so saturation (and its detection) stays correct.
template <QType To, QType From>
constexpr wide_t rescale(From x) {
  wide_t v = x.raw();
  constexpr int shift = From::frac_bits - To::frac_bits;
  if constexpr (shift > 0) {
    v = round_shift_right(v, shift);
  } else if constexpr (shift < 0) {
    constexpr wide_t lim = wide_t{1} << (62 + shift);
    v = clamp(v, -lim, lim - 1) * (wide_t{1} << -shift);
  }
  return v;
}
}  // namespace detail

// Round-to-nearest (ties away from zero) into another format, saturating to its range.
template <QType To, QType From>
constexpr To convert(From x) {
  return To::from_raw_sat(detail::rescale<To>(x));
}

// As convert, and reports whether it had to saturate.
template <QType To, QType From>
constexpr To convert_checked(From x, bool& saturated) {
  const detail::wide_t v = detail::rescale<To>(x);
  saturated = v > To::max_raw || v < To::min_raw;
  return To::from_raw_sat(v);
}

// Exact product: integer and fractional bits add, nothing is lost.
template <int I1, int F1, class S1, int I2, int F2, class S2>
constexpr Q<I1 + I2, F1 + F2, detail::wide_t> mul_wide(Q<I1, F1, S1> a, Q<I2, F2, S2> b) {
  static_assert(I1 + I2 + F1 + F2 <= 62, "exact product must fit 64 bits");
  return Q<I1 + I2, F1 + F2, detail::wide_t>::from_raw(detail::wide_t{a.raw()} * b.raw());
}

// Rounded, saturated product in the requested format.
template <QType To, QType A, QType B>
constexpr To mul_sat(A a, B b) {
  return convert<To>(mul_wide(a, b));
}

template <QType T>
constexpr T add_sat(T a, T b) {
  return T::from_raw_sat(detail::wide_t{a.raw()} + b.raw());
}
template <QType T>
constexpr T sub_sat(T a, T b) {
  return T::from_raw_sat(detail::wide_t{a.raw()} - b.raw());
}
template <QType T>
constexpr T neg_sat(T a) {
  return T::from_raw_sat(-detail::wide_t{a.raw()});
}
template <QType T>
constexpr T abs_sat(T a) {
  return a.raw() < 0 ? neg_sat(a) : a;
}

// The formats the firmware uses most.
using q1_14 = Q<1, 14, std::int16_t>;    // unit-vector components at 16-bit precision
using q1_30 = Q<1, 30, std::int32_t>;    // unit-vector components at 32-bit precision
using q15_16 = Q<15, 16, std::int32_t>;  // general coordinates
using q2_29 = Q<2, 29, std::int32_t>;    // angles in radians, |θ| <= 4 > π
// A plain 64-bit integer as a Q (no fraction bits), so that integers enter div and mul_sat.
using int_q = Q<62, 0, std::int64_t>;

}  // namespace tp::fx
