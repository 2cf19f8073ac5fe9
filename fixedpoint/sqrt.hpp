// Square root and reciprocal square root between Q formats.
//
//   sqrt<To>(x):  correctly rounded (error <= 0.5 LSB of To, ties away from zero -- a tie
//                 cannot actually occur), by the digit-by-digit integer method on the exact
//                 scaled radicand. x <= 0 -> To::zero() (documented: no NaN in integers).
//                 Saturates to To::max() when the root does not fit To.
//   rsqrt<To>(x): 1/sqrt(x) by Newton-Raphson r' = r (3 - y r^2) / 2 from the interpolated
//                 seed below (2^-11.4 relative -> four quadratic steps reach the 2^-61 working
//                 precision), carried in 64-bit Q2.62 with exact 128-bit products, then
//                 rounded once into To. Error <= 0.5 LSB of To plus ~2^-59 relative (so 0.5
//                 LSB for every To up to 32 bits; see docs/ACCURACY.md).
//                 x <= 0 -> To::max() (documented: the limit from the right). Saturates.
#pragma once

#include <array>
#include <bit>
#include <cstdint>

#include "fixedpoint/divide.hpp"
#include "fixedpoint/q.hpp"
#include "fixedpoint/wide.hpp"

namespace tp::fx {

namespace detail {

// floor(sqrt(u * 2^e)) for e >= 0, digit by digit (two radicand bits per step, from the top;
// the e appended zero bits are read virtually, so the radicand may be up to 64 + e bits).
// `round_up` reports remainder > root, i.e. sqrt >= root + 1/2 (an integer radicand is never
// exactly (root + 1/2)^2). Stops early with `over` once root > limit; limit < 2^60 keeps
// 4 * remainder + 3 <= 8 * root + 3 inside 64 bits.
struct RootResult {
  u64 root = 0;
  bool round_up = false;
  bool over = false;
};
constexpr RootResult isqrt_shifted(u64 u, int e, u64 limit) {
  RootResult r;
  if (u == 0) return r;
  const int bits = bit_width(u) + e;
  u64 rem = 0;
  for (int i = (bits + 1) / 2 - 1; i >= 0; --i) {
    // Radicand bits 2i+1 and 2i: bit j is bit j-e of u (zero below e).
    u64 pair = 0;
    for (int j = 2 * i + 1; j >= 2 * i; --j) {
      pair <<= 1;
      if (j >= e && j - e < 64) pair |= (u >> (j - e)) & 1u;
    }
    rem = (rem << 2) | pair;
    const u64 trial = (r.root << 2) | 1u;
    r.root <<= 1;
    if (rem >= trial) {
      rem -= trial;
      r.root |= 1u;
    }
    if (r.root > limit) {
      r.over = true;
      return r;
    }
  }
  r.round_up = rem > r.root;
  return r;
}

// 1/√T for T = t·2^-32 in [1/4, 1), as Q.15 in (2^15, 2^16], by linear interpolation between
// the 49 knots T_k = (16 + k)/64 (the knots' values rounded to Q.15 and stored less 2^15, so that
// 2^16 fits 16 bits): relative error below 2^-11.4 (3.59·10^-4 measured, largest near T = 1/4;
// tests/fixedpoint/test_arith.cpp, RsqrtSeed). One table of 98 bytes seeds the three roots:
// rsqrt_core (four Newton steps), rsqrt_fast (two) and isqrt_plain (√u = u·(1/√u), two integer
// Newton steps and a correction) — a table per root took 1,248 bytes (docs/DECISIONS.md).
inline constexpr std::array<std::uint16_t, 49> rsqrt_knots = [] {
  std::array<std::uint16_t, 49> t{};
  for (int k = 0; k < 49; ++k) {  // 2^15/√((16 + k)/64) = √(2^36/(16 + k)) = √(2^62/(16 + k))·2^-13
    const RootResult r = isqrt_shifted((u64{1} << 62) / static_cast<u64>(16 + k), 0, u64{1} << 40);
    t[static_cast<std::size_t>(k)] =
        static_cast<std::uint16_t>(((r.root + (1u << 12)) >> 13) - (1u << 15));
  }
  return t;
}();
#if TP_SIZE_BUILD || defined(__arm__)
#define TP_FX_DESKTOP_INLINE
constexpr std::uint32_t rsqrt_seed(std::uint32_t t) {        // 2^30 <= t < 2^32
  const std::uint16_t* knot = &rsqrt_knots[(t >> 26) - 16];  // the knot below T, 0..47
  const std::uint32_t frac = (t >> 10) & 0xffffu;            // T's place between knots, Q.16
  // 1/√T falls: knot[0] >= knot[1]. Truncated, not rounded: one instruction fewer per seed.
  return (1u << 15) + knot[0] - ((static_cast<std::uint32_t>(knot[0] - knot[1]) * frac) >> 16);
}
#else
// Speed builds on the desktop: the same seed, bit for bit, from one 64-bit entry per segment,
// indexed by t's top six bits as they are (16..63): the knot's value with its 2^15 above, its fall
// to the next knot below. A second load, the index's rebase, the fall's subtraction and the
// 2^15's addition fewer per root: 3 of kb-adaptive's 406 instructions per pixel on the teapot,
// 13 of 1,012 on teapot-l8 (docs/KUIJK-BLAKE.md, "Targets"), for 512 bytes. Not on the
// Cortex-M: there GCC then inlined the roots into more callers, 29 KB more code at -O2 (16 %),
// so every Arm image keeps the knots; and on the desktop GCC stopped inlining isqrt_plain into
// Duff's pixel loop, which TP_FX_DESKTOP_INLINE restores (Duff 449 -> 439 instructions per pixel
// on the teapot; docs/DECISIONS.md, "The root seed's segments and the stepper unrolled").
#define TP_FX_DESKTOP_INLINE [[gnu::always_inline]]
inline constexpr std::array<u64, 64> rsqrt_segments = [] {
  std::array<u64, 64> s{};
  for (int k = 0; k < 48; ++k)
    s[static_cast<std::size_t>(16 + k)] =
        (u64{(1u << 15) + rsqrt_knots[static_cast<std::size_t>(k)]} << 32) |
        static_cast<std::uint32_t>(rsqrt_knots[static_cast<std::size_t>(k)] -
                                   rsqrt_knots[static_cast<std::size_t>(k + 1)]);
  return s;
}();
constexpr std::uint32_t rsqrt_seed(std::uint32_t t) {  // 2^30 <= t < 2^32
  const u64 segment = rsqrt_segments[t >> 26];
  const std::uint32_t frac = (t >> 10) & 0xffffu;
  return static_cast<std::uint32_t>(segment >> 32) -
         ((static_cast<std::uint32_t>(segment) * frac) >> 16);
}
#endif

// The root for e = 0 (the common case: a Q2.60 square into Q1.30): the identical root, round_up
// and over, from the seed u·(1/√u) (2^-11.4 relative; 2^-8 for radicands below 2^30, where the
// shift drops bits of the root) and two integer Newton steps r' = (r + u / r) / 2 (2^-23.8, then
// 2^-48 relative: within one of the root below 2^32), then an exact correction by r² against u.
// Radicands below 2^16 take the digit-by-digit root.
TP_FX_DESKTOP_INLINE constexpr RootResult isqrt_plain(u64 u, u64 limit) {
  if (u < (u64{1} << 16)) return isqrt_shifted(u, 0, limit);
  int e = bit_width(u) - 32;  // t = u·2^-e in [2^30, 2^32) for an even e
  e += e & 1;
  const u64 t = e >= 0 ? u >> e : u << -e;
  u64 r = (t * rsqrt_seed(static_cast<std::uint32_t>(t))) >> 31;  // √t = 2^16·T·(1/√T), < 2^17
  r = e >= 0 ? r << (e / 2) : r >> (-e / 2);
  if (r == 0) r = 1;
  r = (r + udiv(u, r)) >> 1;
  r = (r + udiv(u, r)) >> 1;
  if (r > 0xffffffffu) r = 0xffffffffu;  // the root of any u64 is below 2^32
  while (r * r > u) --r;
  while (r < 0xffffffffu && (r + 1) * (r + 1) <= u) ++r;
  RootResult res;
  res.root = r;
  const u64 rem = u - r * r;
  res.round_up = rem > r;
  res.over = r > limit;
  return res;
}

// 1/sqrt(u * 2^-frac) = mantissa * 2^-(62 + exp2), for u > 0. mantissa is Q2.62 in (1, 2]
// (up to a few units of 2^-62 below the true value: Newton from below, truncating products).
struct RsqrtResult {
  u64 mantissa = 0;
  int exp2 = 0;
};
constexpr RsqrtResult rsqrt_core(u64 u, int frac) {
  // Normalise u = Y * 2^-s with Y in [2^62, 2^64), choosing s so that 64 - s - frac is even:
  // x = y * 2^(64 - s - frac) with y = Y / 2^64 in [1/4, 1), and 1/sqrt(x) = 1/sqrt(y) * 2^-h.
  int s = std::countl_zero(u);
  if (((64 - s - frac) & 1) != 0) --s;
  const u64 y = s >= 0 ? u << s : (u >> 1);  // s == -1 only for u >= 2^63: drops one low bit
  const int h = (64 - s - frac) / 2;
  u64 r = u64{rsqrt_seed(static_cast<std::uint32_t>(y >> 32))} << 47;  // Q.15 -> Q2.62
  bool over = false;
  for (int it = 0; it < 4; ++it) {
    const u64 r2 = round_shr(mul_u64(r, r), 64, over);  // r^2 in Q4.60 (r <= 2: r^2 <= 4)
    const u64 e = round_shr(mul_u64(y, r2), 62, over);  // y r^2 in Q2.62, ~1
    const u64 t = (u64{3} << 62) - e;                   // 3 - y r^2 > 0 (y r^2 < 1.1)
    r = round_shr(mul_u64(r, t), 63, over);             // r (3 - y r^2) / 2 in Q2.62
  }
  return RsqrtResult{r, h};
}

}  // namespace detail

// ⌊√u⌋ of an integer (the raw-integer root, for code between Q types).
constexpr std::uint64_t isqrt_floor(std::uint64_t u) {
  return detail::isqrt_plain(u, ~std::uint64_t{0}).root;
}

template <QType To, QType From>
constexpr To sqrt(From x) {
  static_assert(To::int_bits + To::frac_bits <= 60, "digit-by-digit root needs 4 spare bits");
  if (x.raw() <= 0) return To::zero();
  const auto u = static_cast<detail::u64>(x.raw());
  // Result raw = sqrt(raw * 2^e) with e = 2 FT - F.
  constexpr int e = 2 * To::frac_bits - From::frac_bits;
  if constexpr (e == 0) {
    const auto r = detail::isqrt_plain(u, static_cast<detail::u64>(To::max_raw));
    return detail::from_sign_mag<To>(false, r.root + (r.round_up ? 1u : 0u), r.over);
  } else if constexpr (e > 0) {
    const auto r = detail::isqrt_shifted(u, e, static_cast<detail::u64>(To::max_raw));
    return detail::from_sign_mag<To>(false, r.root + (r.round_up ? 1u : 0u), r.over);
  } else {
    // sqrt(u * 2^e) = sqrt(u * 2^(e + 2k)) / 2^k with e + 2k in {0, 1}; rounding the floor root
    // half up after the shift equals rounding the true root (the bias is an integer).
    constexpr int k = (-e + 1) / 2;
    const auto r = detail::isqrt_shifted(u, e + 2 * k, detail::u64{1} << 40);
    return detail::from_sign_mag<To>(false, detail::round_shr(r.root, k));
  }
}

template <QType To, QType From>
constexpr To rsqrt(From x) {
  if (x.raw() <= 0) return To::max();
  const auto r = detail::rsqrt_core(static_cast<detail::u64>(x.raw()), From::frac_bits);
  // Result raw = mantissa * 2^(FT - 62 - exp2).
  return detail::from_sign_mag_scaled<To>(false, r.mantissa, 62 + r.exp2 - To::frac_bits);
}

}  // namespace tp::fx
