// Input sets shared by the fixed-point tests and bench/accuracy_fixedpoint.cpp, so that the
// bounds pinned in the tests and the table in docs/ACCURACY.md come from the same inputs.
// Host code: floating point allowed.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "fixedpoint/q.hpp"

namespace tp::fx::testing {

// Every raw value of a 16-bit format.
inline std::vector<std::int64_t> exhaustive16() {
  std::vector<std::int64_t> v;
  v.reserve(65536);
  for (std::int64_t r = -32768; r <= 32767; ++r) v.push_back(r);
  return v;
}

// Edge raw values of a 32-bit format: 0, ±1, ±2, ±2^k ± {0,1,2}, min/max ± k, carry and
// alternating-bit patterns. Clamped into [lo, hi] and deduplicated.
inline std::vector<std::int64_t> edge32(std::int64_t lo = INT32_MIN, std::int64_t hi = INT32_MAX) {
  std::vector<std::int64_t> v = {0, 1, 2, -1, -2};
  for (int k = 1; k <= 31; ++k) {
    const std::int64_t p = std::int64_t{1} << k;
    for (int d = -2; d <= 2; ++d) {
      v.push_back(p + d);
      v.push_back(-p + d);
    }
  }
  for (int d = 0; d <= 3; ++d) {
    v.push_back(INT32_MAX - d);
    v.push_back(INT32_MIN + d);
  }
  const std::int64_t patterns[] = {0x55555555, 0x2AAAAAAA, 0x33333333, 0x0F0F0F0F, 0x00FF00FF,
                                   0x7FFF0000, 0x0000FFFF, 0x00010000, 0x0001FFFF, 0x3FFFFFFF,
                                   0x40000001, 0x12345678, 0x7FFFFFFE, 0x00008000, 0x00007FFF};
  for (std::int64_t p : patterns) {
    v.push_back(p);
    v.push_back(-p);
  }
  for (auto& x : v) x = std::clamp(x, lo, hi);
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

// Dense uniform raw values in [lo, hi], fixed seed so every run sees the same set.
inline std::vector<std::int64_t> random32(std::size_t n, std::int64_t lo = INT32_MIN,
                                          std::int64_t hi = INT32_MAX, unsigned seed = 20261122u) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::int64_t> dist(lo, hi);
  std::vector<std::int64_t> v(n);
  for (auto& x : v) x = dist(rng);
  return v;
}

// Dense random raw values spread over every magnitude (log-uniform exponent, random mantissa
// bits), so that small inputs are as well covered as large ones. Positive only.
inline std::vector<std::int64_t> random_log32(std::size_t n, int max_bits = 31,
                                              unsigned seed = 20261122u) {
  std::mt19937_64 rng(seed);
  std::vector<std::int64_t> v(n);
  for (auto& x : v) {
    const int b = 1 + static_cast<int>(rng() % static_cast<unsigned>(max_bits));
    const std::int64_t top = std::int64_t{1} << (b - 1);
    x = top + static_cast<std::int64_t>(rng() % static_cast<std::uint64_t>(top));
  }
  return v;
}

template <QType Q>
long double to_ld(Q q) {
  return std::ldexp(static_cast<long double>(q.raw()), -Q::frac_bits);
}

// Error of `got` against the exact value `ref`, in LSB of Q; `ref` is clamped to Q's range
// first (saturation is the specified result outside it).
template <QType Q>
long double err_lsb(Q got, long double ref) {
  const long double scaled = std::ldexp(ref, Q::frac_bits);
  const long double clamped = std::clamp(scaled, static_cast<long double>(Q::min_raw),
                                         static_cast<long double>(Q::max_raw));
  return static_cast<long double>(got.raw()) - clamped;
}

// Running max |err|, mean |err| and mean signed err (all in LSB).
struct ErrStats {
  long double max_abs = 0, sum_abs = 0, sum = 0;
  std::size_t n = 0;
  void add(long double e) {
    max_abs = std::max(max_abs, std::fabs(e));
    sum_abs += std::fabs(e);
    sum += e;
    ++n;
  }
  void merge(const ErrStats& o) {
    max_abs = std::max(max_abs, o.max_abs);
    sum_abs += o.sum_abs;
    sum += o.sum;
    n += o.n;
  }
  long double mean_abs() const { return n ? sum_abs / static_cast<long double>(n) : 0; }
  long double mean() const { return n ? sum / static_cast<long double>(n) : 0; }
};

}  // namespace tp::fx::testing
