// The Kuijk-Blake lookup-free cos^n: parameters (a, b) of the piecewise-quadratic f.
//
//   f(θ) = 1 − θ²/(ab)            |θ| <= a
//          (|θ| − b)²/(b(b − a))  a < |θ| < b          (Kuijk-Blake section 2, labels
//          0                      |θ| >= b              corrected as in docs/ACCURACY.md: a < b)
//
// (a, b) depend on n only and replace n as the material attribute. Three sources, each a
// constexpr closed form n -> CosnParams (n is clamped to 1..10,000); no table is linked:
//   paper_params          the paper's closed forms, labels corrected; degrade past n = 125
//   closed_params         our closed form, fitted to the minimax optimum (docs/ACCURACY.md)
//   least_squares_params  our closed form, fitted to the least-squares optimum (the paper's
//                         criterion): the Kuijk-Blake methods' default
// The fits they were fitted to are generated in tables/ (tables/gen_cosn_fits.cpp) and read by
// the tests and the accuracy benchmark only (tables/cosn_fits_lookup.hpp).
// Integer-only (firmware rules): Q2.29 radians, no floating point.
#pragma once

#include <cstdint>

#include "firmware/types.hpp"
#include "fixedpoint/cordic.hpp"
#include "fixedpoint/divide.hpp"
#include "fixedpoint/q.hpp"

namespace tp::fw::cosn {

// Radians in Q2.29, the CORDIC's angle format (|θ| < 4 covers ±π).
using angle_t = fx::angle_t;

inline constexpr int kMinN = 1;
inline constexpr int kMaxN = 10000;
static_assert(kMaxN == kMaxExponent, "the device accepts every exponent the fits cover");

struct CosnParams {
  angle_t a;  // inner break: 1 − θ²/(ab) on |θ| <= a
  angle_t b;  // support: f = 0 for |θ| >= b
};

namespace detail {

constexpr std::int64_t clamp_n(int n) { return fx::clamp(n, kMinN, kMaxN); }

// round(num / den) for num >= 0, den > 0.
constexpr std::int64_t div_round(std::int64_t num, std::int64_t den) {
  return fx::idiv(num + den / 2, den);
}

// floor(sqrt(v)) for v >= 0 (bit-by-bit, no floating point).
constexpr std::int64_t isqrt(std::int64_t v) {
  std::uint64_t x = static_cast<std::uint64_t>(v), r = 0, bit = std::uint64_t{1} << 62;
  while (bit > x) bit >>= 2;
  while (bit != 0) {
    if (x >= r + bit) {
      x -= r + bit;
      r = (r >> 1) + bit;
    } else {
      r >>= 1;
    }
    bit >>= 2;
  }
  return static_cast<std::int64_t>(r);
}

constexpr angle_t angle_raw(std::int64_t raw) { return angle_t::from_raw_sat(raw); }

}  // namespace detail

// Kuijk-Blake's closed forms with the labels exchanged (docs/ACCURACY.md, "Lookup-free cos^n"):
//   a = (n + 5.6) / (n (0.09 n + 5.2)) = (100 n + 560) / (9 n² + 520 n)
//   b = (n + 65) / (5 n + 31.7)        = (10 n + 650) / (50 n + 317)
constexpr CosnParams paper_params(int n_in) {
  const std::int64_t n = detail::clamp_n(n_in);
  const std::int64_t one = angle_t::one_raw;
  return {detail::angle_raw(detail::div_round((100 * n + 560) * one, 9 * n * n + 520 * n)),
          detail::angle_raw(detail::div_round((10 * n + 650) * one, 50 * n + 317))};
}

// Our closed form. For large n, cos^n θ ≈ exp(−nθ²/2), so the optimum is (α, β)/√n with
// (α, β) the minimax fit of the Gaussian, α = 0.75318, β = 2.99243 (gen_cosn_fits --print at
// n = 10,000, times 100). A [2/2] rational correction in n bends it to the small-n optimum:
//   a = α (n² + p1 n + p0) / ((n² + q1 n + q0) √n), the same form for b.
// The eight coefficients were fitted by bench/fit_cosn_closed_form (Nelder-Mead, minimising
// max over n of the max error relative to the 1.5 % target, 2.5 % at n = 1) and are stored
// in Q16; see docs/ACCURACY.md. Max error: <= 1.469 % for 3 <= n <= 10,000, 1.812 % at n = 2
// (the minimax optimum there is 1.765 %, so 1.5 % is out of reach of this f), 2.449 % at n = 1.
struct ClosedForm {
  std::int64_t scale_q29;       // α or β in Q2.29
  std::int64_t p1, p0, q1, q0;  // rational correction, Q16
};
inline constexpr ClosedForm kClosedA{404360434, 261676, 148572, 241773, -41575};
inline constexpr ClosedForm kClosedB{1606548623, 98254, -50462, 119544, 15635};

namespace detail {
// scale · (n²+p1 n+p0)/((n²+q1 n+q0) √n), in Q2.29. Bounds for 1 <= n <= 10^4: the Q16
// numerator and denominator are < 2^43, the Q20 ratio < 2^22 (it lies in [0.5, 2.5]),
// scale · ratio < 2^31 · 2^22; all in int64.
constexpr std::int64_t closed_eval(const ClosedForm& c, std::int64_t n) {
  const std::int64_t n2 = n * n * 65536;
  const std::int64_t num = n2 + c.p1 * n + c.p0, den = n2 + c.q1 * n + c.q0;
  const std::int64_t ratio_q20 = div_round(num * (std::int64_t{1} << 20), den);
  const std::int64_t sqrt_q20 = isqrt(n << 40);  // √n in Q20, n << 40 < 2^54
  return div_round(c.scale_q29 * ratio_q20, sqrt_q20);
}
}  // namespace detail

constexpr CosnParams closed_params(int n_in) {
  const std::int64_t n = detail::clamp_n(n_in);
  return {detail::angle_raw(detail::closed_eval(kClosedA, n)),
          detail::angle_raw(detail::closed_eval(kClosedB, n))};
}

// Our closed form for the least-squares optimum, the same [2/2] form as closed_params with
// (α, β) the least-squares limits (a√n, b√n of the generated fit at n = 10,000):
//   α = 0.7833744, β = 2.9560430. The four coefficients per parameter were fitted by
// bench/fit_cosn_closed_form (mode "least-squares": Nelder-Mead minimising the max relative
// distance to the generated least-squares (a, b) at every n <= 200 and the grid to 10,000). It
// tracks them within 7.2e-5 (a) and 4.0e-5 (b) relative, Q16 rounding included (tested): the
// fit's own flat optimum, where that distance moves f by less than 1e-4 of the peak.
inline constexpr ClosedForm kLeastSquaresA{420570900, 256667, 75348, 224007, -48881};
inline constexpr ClosedForm kLeastSquaresB{1587013500, 40295, -28316, 66450, 417};

// Bounds as closed_eval's: the ratios lie in [0.58, 1.66] for 1 <= n <= 10^4 and both
// denominators are positive there.
constexpr CosnParams least_squares_params(int n_in) {
  const std::int64_t n = detail::clamp_n(n_in);
  return {detail::angle_raw(detail::closed_eval(kLeastSquaresA, n)),
          detail::angle_raw(detail::closed_eval(kLeastSquaresB, n))};
}

}  // namespace tp::fw::cosn
