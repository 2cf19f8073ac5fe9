// Integer division of 64-bit operands, truncating as C++'s / and % do, without the compiler's
// 64-bit division helper on cores that lack a 64-bit divide.
//
//   udivmod(n, d) = {n / d, n % d} for u64, d != 0;
//   idivmod(n, d) = {n / d, n % d} for i64, d != 0, (n, d) != (INT64_MIN, -1);
//   udiv, idiv: the quotient alone.
//
// Exact: the results equal / and % bit for bit for every operand pair (tests/fixedpoint,
// DivideByHalves). On x86-64 they are / and %. On a 32-bit Arm core with a 32-bit hardware
// divide (Cortex-M3, M4, M7: __ARM_FEATURE_IDIV) GCC would call __aeabi_uldivmod /
// __aeabi_ldivmod, a general 64-by-64 long division in software; here the quotient is built
// from 32-by-32 hardware divisions instead: one when both operands fit 32 bits; for a wider
// dividend over a 32-bit divisor, one for the dividend's high word and one per 16-bit quotient
// digit of Knuth's Algorithm D (TAOCP vol. 2, 4.3.1) for the rest; for a divisor of 33 bits or
// more, one 64-by-32 step on the divisor's normalised top word and a single correction
// (Hacker's Delight, 2nd ed., 9-5). docs/TARGET.md, "Division on the core".
#pragma once

#include <bit>
#include <cstdint>

namespace tp::fx {

struct UDivMod {
  std::uint64_t quot;
  std::uint64_t rem;
};
struct IDivMod {
  std::int64_t quot;
  std::int64_t rem;
};

namespace detail {

using u32 = std::uint32_t;

// One 16-bit digit of Algorithm D: the quotient of (r * 2^16 + next16) / v for a partial
// remainder r < v and a normalised v (top bit set); r becomes the new partial remainder. The
// estimate r / (v's top 16 bits) is at most two too large; each correction adds v back to the
// remainder, and a carry out of that addition means the remainder is right.
constexpr u32 quotient_digit(u32& r, u32 next16, u32 v) {
  const u32 v_top = v >> 16;
  u32 q = r / v_top;  // <= 2^16 + 1
  u32 rem = ((r - q * v_top) << 16) | next16;
  const u32 m = q * (v & 0xffffu);  // <= (2^16 + 1)(2^16 - 1): no overflow
  if (rem < m) {
    --q;
    rem += v;
    if (rem >= v && rem < m) {  // rem >= v: the addition did not carry
      --q;
      rem += v;
    }
  }
  r = rem - m;
  return q;
}

// (hi * 2^32 + lo) / v and its remainder, for hi < v, so that the quotient fits 32 bits: two
// digits of 16 bits after normalising v.
constexpr u32 div_two_words(u32 hi, u32 lo, u32 v, u32& rem) {
  const int s = std::countl_zero(v);
  v <<= s;
  u32 r = (hi << s) | ((lo >> 1) >> (31 - s));  // the two shifts: no shift by 32 when s = 0
  lo <<= s;
  const u32 q1 = quotient_digit(r, lo >> 16, v);
  const u32 q0 = quotient_digit(r, lo & 0xffffu, v);
  rem = r >> s;
  return (q1 << 16) | q0;
}

// n / d when n or d has 33 bits or more. Out of line, and returning the quotient alone (in
// registers), since most division sites on the Cortex-M3 see 32-bit operands: the remainder,
// where wanted, is n - q * d.
[[gnu::noinline]] constexpr std::uint64_t udiv_wide(std::uint64_t n, std::uint64_t d) {
  u32 unused = 0;
  if ((d >> 32) == 0) {
    const auto v = static_cast<u32>(d), hi = static_cast<u32>(n >> 32);
    const u32 q_hi = hi / v;
    const u32 q_lo = div_two_words(hi - q_hi * v, static_cast<u32>(n), v, unused);
    return (std::uint64_t{q_hi} << 32) | q_lo;
  }
  // d >= 2^32, so the quotient is below 2^32 (Hacker's Delight, 9-5): n/2 divided by the
  // divisor's top 32 bits, normalised, and shifted back gives a quotient at most one above the
  // true one; one decrement makes it at most one below, and one comparison settles it.
  const int s = std::countl_zero(static_cast<u32>(d >> 32));
  const auto v = static_cast<u32>((d << s) >> 32);
  const std::uint64_t half = n >> 1;  // half >> 32 < 2^31 <= v: div_two_words' condition
  u32 q =
      div_two_words(static_cast<u32>(half >> 32), static_cast<u32>(half), v, unused) >> (31 - s);
  if (q != 0) --q;
  const std::uint64_t qd =
      std::uint64_t{q} * static_cast<u32>(d) + (std::uint64_t{q * static_cast<u32>(d >> 32)} << 32);
  if (n - qd >= d) ++q;
  return q;
}

// udivmod from 32-bit divisions: what the Arm build runs, and what the tests check on x86.
// Both operands within 32 bits (most of the firmware's divisions): one hardware division.
constexpr UDivMod udivmod_by_halves(std::uint64_t n, std::uint64_t d) {
  if (((n | d) >> 32) == 0) {
    const auto a = static_cast<u32>(n), b = static_cast<u32>(d);
    return {a / b, a % b};
  }
  const std::uint64_t q = udiv_wide(n, d);
  return {q, n - q * d};
}

// idivmod from udivmod_by_halves on the magnitudes: the quotient truncated toward zero, the
// remainder with the dividend's sign, as C++ defines them.
constexpr IDivMod idivmod_by_halves(std::int64_t n, std::int64_t d) {
  const auto magnitude = [](std::int64_t x) {
    return x < 0 ? std::uint64_t{0} - static_cast<std::uint64_t>(x) : static_cast<std::uint64_t>(x);
  };
  const UDivMod m = udivmod_by_halves(magnitude(n), magnitude(d));
  const std::uint64_t q = (n < 0) != (d < 0) ? std::uint64_t{0} - m.quot : m.quot;
  const std::uint64_t r = n < 0 ? std::uint64_t{0} - m.rem : m.rem;
  return {static_cast<std::int64_t>(q), static_cast<std::int64_t>(r)};
}

}  // namespace detail

#if defined(__arm__) && defined(__ARM_FEATURE_IDIV)
inline constexpr bool kDivideByHalves = true;
#else
inline constexpr bool kDivideByHalves = false;
#endif

constexpr UDivMod udivmod(std::uint64_t n, std::uint64_t d) {
  if constexpr (kDivideByHalves) {
    return detail::udivmod_by_halves(n, d);
  } else {
    return {n / d, n % d};
  }
}

constexpr std::uint64_t udiv(std::uint64_t n, std::uint64_t d) { return udivmod(n, d).quot; }

constexpr IDivMod idivmod(std::int64_t n, std::int64_t d) {
  if constexpr (kDivideByHalves) {
    return detail::idivmod_by_halves(n, d);
  } else {
    return {n / d, n % d};
  }
}

constexpr std::int64_t idiv(std::int64_t n, std::int64_t d) { return idivmod(n, d).quot; }

}  // namespace tp::fx
