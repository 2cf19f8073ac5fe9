// Host-side (double) reference for the Kuijk-Blake piecewise-quadratic cos^n: the function f,
// the target max(0, cos θ)^n, and the error measures used by the fit generator, the tests and
// bench/accuracy_cosn. Floating point is fine here: this header is never part of the firmware.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace tp::tables::cosn {

// Kuijk-Blake section 2 with the labels corrected (docs/ACCURACY.md, "Lookup-free cos^n"): a < b,
// the inner parabola on |θ| <= a, the outer one up to b, zero beyond. Continuous in value and slope
// at ±a and ±b.
inline double f_quad(double theta, double a, double b) {
  const double t = std::fabs(theta);
  if (t >= b) return 0.0;
  if (t > a) return (t - b) * (t - b) / (b * (b - a));
  return 1.0 - t * t / (a * b);
}

// The light model clamps the cosine at zero (a surface facing away gets nothing), so the
// target is max(0, cos θ)^n, which is zero for |θ| >= π/2.
inline double cosn_target(double theta, double n) {
  const double c = std::cos(theta);
  return c <= 0.0 ? 0.0 : std::pow(c, n);
}

// Where both functions can be non-zero: [0, max(b, π/2)] covers everything (f is even and
// zero past b; the target is zero past π/2). For large n the target is negligible past
// 10/√n (cos^n θ ≈ exp(-nθ²/2) = exp(-50) there), so the sampled domain shrinks with n and the
// sampling density follows the width of the lobe.
inline double domain_end(double n, double b) {
  const double lobe = std::min(std::numbers::pi / 2, 10.0 / std::sqrt(n));
  return std::min(std::numbers::pi, std::max(lobe, b));
}

// max over θ in [0, π] of |f - max(0,cos)^n|, as a fraction of the peak (1). Dense uniform
// sampling of the (piecewise smooth) error plus the break points a, b and π/2 themselves.
inline double max_error(double n, double a, double b, int samples = 20000) {
  const double end = domain_end(n, b);
  double worst = 0.0;
  auto at = [&](double t) {
    if (t < 0.0 || t > std::numbers::pi) return;
    worst = std::max(worst, std::fabs(f_quad(t, a, b) - cosn_target(t, n)));
  };
  for (int i = 0; i <= samples; ++i) at(end * i / samples);
  at(a);
  at(b);
  at(std::numbers::pi / 2);
  return worst;
}

// Sampled target, reused across the many (a, b) trials of a fit for one n.
struct Sampled {
  double n = 1, step = 0;
  std::vector<double> theta, target;
};
inline Sampled sample_target(double n, int samples) {
  Sampled s;
  s.n = n;
  const double end = domain_end(n, 0.0);
  s.step = end / samples;
  for (int i = 0; i <= samples; ++i) {
    const double t = end * i / samples;
    s.theta.push_back(t);
    s.target.push_back(cosn_target(t, n));
  }
  return s;
}

// Least-squares objective: ∫ (f - target)² dθ over [0, end] (trapezoid rule), plus the part
// of f beyond the sampled end when b lies past it (the target is ~0 there; exact integral of
// the outer parabola's square from max(a, end) to b).
inline double sq_error(const Sampled& s, double a, double b) {
  double sum = 0.0;
  const std::size_t m = s.theta.size();
  for (std::size_t i = 0; i < m; ++i) {
    const double d = f_quad(s.theta[i], a, b) - s.target[i];
    sum += (i == 0 || i + 1 == m ? 0.5 : 1.0) * d * d;
  }
  sum *= s.step;
  const double end = s.theta.back();
  if (b > end) {
    const double lo = std::max(a, end), k = 1.0 / (b * (b - a));
    const double w = b - lo;  // ∫_lo^b k²(b-t)^4 dt = k² w^5 / 5
    sum += k * k * w * w * w * w * w / 5.0;
  }
  return sum;
}

// Sampled max error (the minimax objective); the exact one is max_error.
inline double sampled_max_error(const Sampled& s, double a, double b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < s.theta.size(); ++i)
    worst = std::max(worst, std::fabs(f_quad(s.theta[i], a, b) - s.target[i]));
  if (b > s.theta.back()) worst = std::max(worst, f_quad(s.theta.back(), a, b));
  return worst;
}

// The paper's closed forms with the labels corrected (docs/ACCURACY.md), in double.
inline double paper_a(double n) { return (n + 5.6) / (n * (0.09 * n + 5.2)); }
inline double paper_b(double n) { return (n + 65.0) / (5.0 * n + 31.7); }

}  // namespace tp::tables::cosn
