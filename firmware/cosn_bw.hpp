// Bishop-Weimer exponentiation by table (fast Phong, 1986), the baseline the lookup-free
// Kuijk-Blake f is compared with. Layout (tables/gen_bw_exponent.cpp documents why):
// one table per exponent n, `size` one-byte entries T[i] = round(255 (i/(size−1))^n),
// addressed by the dot product N·H in [0, 1] scaled to [0, size−1] and rounded.
// 1 KiB (size 1,024) serves n <= 20 and 8 KiB (size 8,192) n <= 164 within ~1 % (measured in
// tests/cosn). Filled once per material, integer-only: x^n by repeated squaring in Q.48
// (relative error < n·2^-47, far below the 1/510 of the 8-bit entries).
#pragma once

#include <cstdint>

#include "fixedpoint/divide.hpp"
#include "fixedpoint/q.hpp"
#include "fixedpoint/wide.hpp"

namespace tp::fw::cosn {

inline constexpr int kBwSize1K = 1024;
inline constexpr int kBwMaxN1K = 20;
inline constexpr int kBwSize8K = 8192;
inline constexpr int kBwMaxN8K = 164;

namespace bw_detail {
using u64 = std::uint64_t;
inline constexpr int kFrac = 48;

constexpr u64 mul_q48(u64 a, u64 b) {
  // a, b <= 2^48: the signed product's rounding (ties away from zero) is half up here.
  return static_cast<u64>(
      fx::mul_shift_right(static_cast<std::int64_t>(a), static_cast<std::int64_t>(b), kFrac));
}

// x^n for x in Q.48, 0 <= x <= 1, n >= 0 (square-and-multiply).
constexpr u64 pow_q48(u64 x, int n) {
  u64 r = u64{1} << kFrac;
  while (n > 0) {
    if (n & 1) r = mul_q48(r, x);
    x = mul_q48(x, x);
    n >>= 1;
  }
  return r;
}
}  // namespace bw_detail

// Fills table[0..size) for exponent n (size >= 2, size <= 2^13, n >= 1).
constexpr void bw_fill(int n, std::uint8_t* table, int size) {
  using bw_detail::u64;
  const u64 last = static_cast<u64>(size - 1);
  for (int i = 0; i < size; ++i) {
    // x = i/(size−1) in Q.48: i·2^48 < 2^61.
    const u64 x = fx::udiv((static_cast<u64>(i) << bw_detail::kFrac) + last / 2, last);
    const u64 p = bw_detail::pow_q48(x, n);
    const u64 one = u64{1} << bw_detail::kFrac;
    table[i] = static_cast<std::uint8_t>((255 * p + one / 2) >> bw_detail::kFrac);
  }
}

// T[round(c·(size−1))] for the dot product c (Q1.30); c <= 0 reads T[0] = 0, c >= 1 the top.
constexpr std::uint8_t bw_lookup(const std::uint8_t* table, int size, fx::q1_30 c) {
  const std::int64_t raw = c.raw();
  if (raw <= 0) return table[0];
  const std::int64_t idx = (raw * (size - 1) + (std::int64_t{1} << 29)) >> 30;
  return table[idx >= size ? size - 1 : idx];
}

}  // namespace tp::fw::cosn
