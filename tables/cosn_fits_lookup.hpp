// (a, b) read from the generated fits (tables/cosn_fits.hpp), for the tests and the accuracy
// benchmark, which measure the firmware's closed forms (firmware/cosn.hpp) against them. The
// firmware links no fit table: it derives (a, b) from n by closed forms only.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fixedpoint/cordic.hpp"
#include "tables/cosn_fits.hpp"

namespace tp::tables::cosn_fits {

static_assert(fx::angle_t::frac_bits == kAngleFracBits, "fits are in Q2.29");

struct FitParams {
  fx::angle_t a;  // inner break, Q2.29 radians
  fx::angle_t b;  // support
};

// The minimax fit. Every n <= 200 is in the table; above, the grid has 64 points per decade and
// (a, b) are interpolated linearly in n between neighbours. n is clamped to the table's range.
constexpr FitParams minimax_params(int n_in) {
  const std::int64_t n = n_in < kN[0] ? kN[0] : (n_in > kN[kCount - 1] ? kN[kCount - 1] : n_in);
  int lo = 0, hi = kCount - 1;  // invariant: kN[lo] <= n <= kN[hi]
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (kN[static_cast<std::size_t>(mid)] <= n)
      lo = mid;
    else
      hi = mid;
  }
  const auto at = [](const auto& arr, int i) -> std::int64_t {
    return arr[static_cast<std::size_t>(i)];
  };
  const auto angle = [](std::int64_t raw) { return fx::angle_t::from_raw_sat(raw); };
  const std::int64_t n0 = at(kN, lo), n1 = at(kN, hi);
  if (n1 == n0 || n == n0) return {angle(at(kA_mm, lo)), angle(at(kB_mm, lo))};
  if (n == n1) return {angle(at(kA_mm, hi)), angle(at(kB_mm, hi))};
  // Interpolation: a1 - a0 is negative; round the signed product symmetrically.
  const auto lerp = [&](std::int64_t v0, std::int64_t v1) {
    const std::int64_t num = (v1 - v0) * (n - n0), den = n1 - n0;
    const std::int64_t q = num >= 0 ? (num + den / 2) / den : -((-num + den / 2) / den);
    return v0 + q;
  };
  return {angle(lerp(at(kA_mm, lo), at(kA_mm, hi))), angle(lerp(at(kB_mm, lo), at(kB_mm, hi)))};
}

}  // namespace tp::tables::cosn_fits
