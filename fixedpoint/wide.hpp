// Unsigned magnitude helpers shared by div / sqrt / rsqrt / vec3: a 64x64 -> 128-bit product
// built from 32x32 -> 64 multiplies (the Cortex-M build has no __int128), round-half-up right
// shifts of magnitudes, and the final "sign + magnitude -> saturated Q" step.
//
// Rounding convention (same as q.hpp): round to nearest, ties away from zero. Working on the
// magnitude with round-half-up and applying the sign afterwards gives exactly that, and makes
// every function here odd-symmetric: f(-x) == -f(x) bit for bit.
#pragma once

#include <bit>
#include <cstdint>

#include "fixedpoint/q.hpp"

namespace tp::fx::detail {

using u64 = std::uint64_t;

struct U128 {
  u64 hi = 0;
  u64 lo = 0;
};

// |v| without overflow, also for INT64_MIN.
constexpr u64 magnitude(wide_t v) {
  return v < 0 ? u64{0} - static_cast<u64>(v) : static_cast<u64>(v);
}

// Exact 128-bit product of two 64-bit magnitudes (schoolbook on 32-bit limbs).
constexpr U128 mul_u64(u64 a, u64 b) {
  constexpr u64 m32 = 0xffffffffu;
  const u64 a0 = a & m32, a1 = a >> 32, b0 = b & m32, b1 = b >> 32;
  const u64 p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0, p11 = a1 * b1;
  const u64 mid = (p00 >> 32) + (p01 & m32) + (p10 & m32);  // < 3 * 2^32: no overflow
  return U128{p11 + (p01 >> 32) + (p10 >> 32) + (mid >> 32), (mid << 32) | (p00 & m32)};
}

// round(m / 2^sh), half up, for sh >= 0 (any size).
constexpr u64 round_shr(u64 m, int sh) {
  if (sh <= 0) return m;
  if (sh > 64) return 0;
  if (sh == 64) return m >> 63;  // m / 2^64 < 1; it rounds to 1 iff m >= 2^63
  return (m >> sh) + ((m >> (sh - 1)) & 1u);
}

// round(v / 2^sh), half up, for 0 <= sh < 128. Sets `over` when the result needs 64+ bits.
// The bias is added as the bit below the cut, so v may be any 128-bit value.
constexpr u64 round_shr(U128 v, int sh, bool& over) {
  over = false;
  if (sh <= 0) {
    over = v.hi != 0;
    return v.lo;
  }
  if (sh >= 64) {
    const int s = sh - 64;
    const u64 q = s == 0 ? v.hi : v.hi >> s;
    const u64 half = s == 0 ? (v.lo >> 63) : ((v.hi >> (s - 1)) & 1u);
    return q + half;  // q < 2^64 - 1 here unless v.hi is all ones, which no caller produces
  }
  if ((v.hi >> sh) != 0) {
    over = true;
    return ~u64{0};
  }
  const u64 q = (v.hi << (64 - sh)) | (v.lo >> sh);
  const u64 half = (v.lo >> (sh - 1)) & 1u;
  if (q == ~u64{0} && half != 0) over = true;
  return q + half;
}

// m * 2^k for k >= 0, or `over` when it leaves 63 bits (callers saturate then).
constexpr u64 shl_checked(u64 m, int k, bool& over) {
  over = false;
  if (k <= 0 || m == 0) return m;
  if (k >= 63 || m > (u64{1} << (63 - k)) - 1) {
    over = true;
    return ~u64{0};
  }
  return m << k;
}

// A magnitude and a sign to To, saturated: |raw| above the range gives To::max() / To::min().
template <QType To>
constexpr To from_sign_mag(bool negative, u64 mag, bool over = false) {
  using S = typename To::storage_type;
  if (!negative) {
    if (over || mag > static_cast<u64>(To::max_raw)) return To::max();
    return To::from_raw(static_cast<S>(mag));
  }
  if (over || mag >= static_cast<u64>(-To::min_raw)) return To::min();
  return To::from_raw(static_cast<S>(-static_cast<wide_t>(mag)));
}

// To-raw = mag * 2^-sh (sh of either sign), rounded half up on the magnitude, then signed and
// saturated: round to nearest, ties away from zero.
template <QType To>
constexpr To from_sign_mag_scaled(bool negative, u64 mag, int sh) {
  bool over = false;
  const u64 m = sh >= 0 ? round_shr(mag, sh) : shl_checked(mag, -sh, over);
  return from_sign_mag<To>(negative, m, over);
}

// Exact sum of signed 64-bit terms, each of magnitude <= 2^62, at most three of them: the
// positive and the negative parts are accumulated apart in u64 (<= 3 * 2^62 < 2^64), so no
// intermediate can overflow even when the signed total would not fit int64.
struct SignMag {
  bool negative = false;
  u64 mag = 0;
};
constexpr SignMag exact_sum(const wide_t* terms, int count) {
  u64 pos = 0, neg = 0;
  for (int i = 0; i < count; ++i) {
    if (terms[i] >= 0)
      pos += static_cast<u64>(terms[i]);
    else
      neg += magnitude(terms[i]);
  }
  return pos >= neg ? SignMag{false, pos - neg} : SignMag{true, neg - pos};
}

}  // namespace tp::fx::detail

namespace tp::fx {

// Raw-integer products wider than 64 bits, public for code between Q types:
//   mul_shift_right(a, b, s)  round(a·b / 2^s), ties away from zero, from the exact 128-bit
//                             product; the caller keeps the result below 2^63.
//   Sum128                    an exact signed sum of 64×64-bit products, without __int128
//                             (Cortex-M has none): its sign (what orientation tests need), or
//                             the sum rounded once to 64 bits (a polynomial evaluated exactly).
constexpr std::int64_t mul_shift_right(std::int64_t a, std::int64_t b, int s) {
  const bool negative = (a < 0) != (b < 0);
  bool over = false;
  const auto m = static_cast<std::int64_t>(
      detail::round_shr(detail::mul_u64(detail::magnitude(a), detail::magnitude(b)), s, over));
  return negative ? -m : m;
}

struct Sum128 {
  std::uint64_t lo = 0;
  std::uint64_t hi = 0;  // two's complement high word
  constexpr void add_product(std::int64_t a, std::int64_t b) {
    const bool negative = (a < 0) != (b < 0);
    detail::U128 p = detail::mul_u64(detail::magnitude(a), detail::magnitude(b));
    if (negative) {  // −p = ~p + 1
      p.lo = ~p.lo + 1;
      p.hi = ~p.hi + (p.lo == 0 ? 1u : 0u);
    }
    const std::uint64_t lo2 = lo + p.lo;
    hi += p.hi + (lo2 < lo ? 1u : 0u);
    lo = lo2;
  }
  constexpr int sign() const {
    if ((hi >> 63) != 0) return -1;
    return (hi | lo) != 0 ? 1 : 0;
  }
  // round(sum / 2^s), ties away from zero, for 0 <= s < 128; `over` when it needs 64 bits.
  constexpr std::int64_t shifted(int s, bool& over) const {
    const bool negative = (hi >> 63) != 0;
    detail::U128 m{hi, lo};
    if (negative) {  // |sum| = ~sum + 1
      m.lo = ~lo + 1;
      m.hi = ~hi + (m.lo == 0 ? 1u : 0u);
    }
    const detail::u64 r = detail::round_shr(m, s, over);
    if (r > static_cast<detail::u64>(INT64_MAX)) over = true;
    const auto v = static_cast<std::int64_t>(over ? static_cast<detail::u64>(INT64_MAX) : r);
    return negative ? -v : v;
  }
};

}  // namespace tp::fx
