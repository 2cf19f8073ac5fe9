// Division between any two Q formats into a third.
//
//   div<To>(num, den) = num / den rounded to nearest, ties away from zero, saturated to To.
//   Division by zero (documented, tested): To::max() if num > 0, To::min() if num < 0,
//   To::zero() if num == 0 -- the limit from the side of a positive denominator, and no trap.
//
// Exact: the quotient is the correctly rounded value of the true ratio for every input pair
// (the long division below keeps the full remainder), so its error is <= 0.5 LSB of To.
#pragma once

#include <bit>

#include "fixedpoint/divide.hpp"
#include "fixedpoint/q.hpp"
#include "fixedpoint/wide.hpp"

namespace tp::fx {

namespace detail {

// round(n * 2^s / d), half up, for magnitudes n < 2^63, 0 < d < 2^63. Returns limit + 1 as
// soon as the quotient is known to exceed `limit` (limit < 2^63), so callers saturate.
constexpr u64 div_round_shifted(u64 n, u64 d, int s, u64 limit) {
  if (s <= 0) {
    const int t = -s;
    // d * 2^t >= 2^64 > 2n: the ratio is below one half and rounds to zero.
    if (t >= 64 || d > (~u64{0} >> t)) return 0;
    const u64 dd = d << t;
    const UDivMod m = udivmod(n, dd);
    return m.rem >= dd - m.rem ? m.quot + 1 : m.quot;  // 2r >= dd without forming 2r
  }
  // n * 2^s fits in 64 bits: one division gives the same floor and remainder as the long
  // division below, hence the same rounding and saturation.
  if (s < 64 && n <= (~u64{0} >> s)) {
    const u64 ns = n << s;
    const UDivMod m = udivmod(ns, d);
    const u64 q1 = m.rem >= d - m.rem ? m.quot + 1 : m.quot;
    return q1 > limit ? limit + 1 : q1;
  }
  // limit >> k for any k >= 0 (a shift by 64+ is undefined).
  const auto lim_shr = [limit](int k) { return k >= 63 ? u64{0} : limit >> k; };
  const UDivMod first = udivmod(n, d);
  u64 q = first.quot, r = first.rem;
  int remaining = s;
  if (q > lim_shr(remaining)) return limit + 1;
  // Bring down as many zero bits at once as the remainder has headroom for (r < d < 2^63, so
  // at least one); q <= limit throughout, so q << k never overflows.
  while (remaining > 0) {
    if (r == 0) {
      if (q != 0) q <<= remaining;  // q <= limit >> remaining, so remaining < 63 here
      break;
    }
    int k = std::countl_zero(r);
    if (k > remaining) k = remaining;
    const u64 rk = r << k;
    const UDivMod m = udivmod(rk, d);
    q = (q << k) + m.quot;
    r = m.rem;
    remaining -= k;
    if (q > lim_shr(remaining)) return limit + 1;
  }
  if (r >= d - r) ++q;
  return q > limit ? limit + 1 : q;
}

// div's raw quotient round(n * 2^s / d), saturated to [min_raw, max_raw]: not a template, so
// that size builds keep one copy (TP_FX_OUTLINE) for all of div's formats, 900 bytes less on a
// Cortex-M3. Speed builds keep div's own body, whose inlining GCC judges as before (through
// div_raw, SteppedBarycentrics::start was inlined into three span loops).
TP_FX_OUTLINE constexpr wide_t div_raw(wide_t n, wide_t d, int s, wide_t min_raw, wide_t max_raw) {
  if (d == 0) return n > 0 ? max_raw : (n < 0 ? min_raw : 0);
  const bool negative = (n < 0) != (d < 0);
  const u64 limit = static_cast<u64>(negative ? -min_raw : max_raw);
  const u64 q = div_round_shifted(magnitude(n), magnitude(d), s, limit);
  if (!negative) return q > static_cast<u64>(max_raw) ? max_raw : static_cast<wide_t>(q);
  return q >= static_cast<u64>(-min_raw) ? min_raw : -static_cast<wide_t>(q);
}

}  // namespace detail

template <QType To, QType A, QType B>
constexpr To div(A num, B den) {
  // Quotient raw = n * 2^(FT + FB - FA) / d.
  constexpr int s = To::frac_bits + B::frac_bits - A::frac_bits;
#if TP_SIZE_BUILD
  const detail::wide_t q = detail::div_raw(num.raw(), den.raw(), s, To::min_raw, To::max_raw);
  return To::from_raw(static_cast<typename To::storage_type>(q));
#else
  const detail::wide_t n = num.raw(), d = den.raw();
  if (d == 0) return n > 0 ? To::max() : (n < 0 ? To::min() : To::zero());
  const bool negative = (n < 0) != (d < 0);
  const auto limit = static_cast<detail::u64>(negative ? -To::min_raw : To::max_raw);
  const detail::u64 q =
      detail::div_round_shifted(detail::magnitude(n), detail::magnitude(d), s, limit);
  return detail::from_sign_mag<To>(negative, q);
#endif
}

}  // namespace tp::fx
