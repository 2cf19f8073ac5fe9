// Build-time generator: fits the Kuijk-Blake parameters (a, b) of the piecewise-quadratic
// cos^n (tables/cosn_reference.hpp) for n = 1..10,000, by least squares (as the paper did for
// 1 <= n <= 125) and by minimax, and writes tables/cosn_fits.hpp.
//
// Domain: θ in [0, π] against max(0, cos θ)^n. f and the target are even, so [0, π] covers
// both signs; the target is zero past π/2 (the light is behind the surface), so for n >= 2,
// where b < π/2, this is the paper's [0, π/2]; for n = 1 the fitted b exceeds π/2 and the
// tail (π/2, b), where f > 0 = target, must count against the fit.
//
// Speed (runs at every clean build on slow cores): the target is sampled once per n on a grid
// that scales like 1/√n (for large n, cos^n θ ≈ exp(-u²/2) with u = θ√n, so the problem is
// the same in u), and each n is warm-started from the previous one scaled by √(n_prev/n).
//
// Usage: gen_cosn_fits OUT.hpp            writes the header
//        gen_cosn_fits --print            prints n, a_ls, b_ls, a_mm, b_mm, errors (for fitting
//                                          the firmware's closed form, see firmware/cosn.hpp)
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "tables/cosn_reference.hpp"

namespace {

using tp::tables::cosn::Sampled;

// 2-D Nelder-Mead on (ln a, ln(b - a)), which keeps 0 < a < b without constraints.
using Objective = std::function<double(double, double)>;
std::array<double, 2> nelder_mead(const Objective& obj, std::array<double, 2> x0, double step,
                                  int iters) {
  auto eval = [&](const std::array<double, 2>& p) {
    return obj(std::exp(p[0]), std::exp(p[0]) + std::exp(p[1]));
  };
  std::array<std::array<double, 2>, 3> s{x0, x0, x0};
  s[1][0] += step;
  s[2][1] += step;
  std::array<double, 3> v{eval(s[0]), eval(s[1]), eval(s[2])};
  for (int it = 0; it < iters; ++it) {
    // Order best..worst.
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j)
        if (v[j] < v[i]) std::swap(v[i], v[j]), std::swap(s[i], s[j]);
    const std::array<double, 2> c{(s[0][0] + s[1][0]) / 2, (s[0][1] + s[1][1]) / 2};
    auto along = [&](double t) {
      return std::array<double, 2>{c[0] + t * (s[2][0] - c[0]), c[1] + t * (s[2][1] - c[1])};
    };
    const auto r = along(-1.0);
    const double fr = eval(r);
    if (fr < v[0]) {
      const auto e = along(-2.0);
      const double fe = eval(e);
      if (fe < fr)
        s[2] = e, v[2] = fe;
      else
        s[2] = r, v[2] = fr;
    } else if (fr < v[1]) {
      s[2] = r, v[2] = fr;
    } else {
      const auto k = along(fr < v[2] ? -0.5 : 0.5);
      const double fk = eval(k);
      if (fk < std::min(fr, v[2])) {
        s[2] = k, v[2] = fk;
      } else {  // shrink towards the best
        for (int i = 1; i < 3; ++i) {
          s[i] = {(s[i][0] + s[0][0]) / 2, (s[i][1] + s[0][1]) / 2};
          v[i] = eval(s[i]);
        }
      }
    }
  }
  int best = 0;
  for (int i = 1; i < 3; ++i)
    if (v[i] < v[best]) best = i;
  return s[best];
}

struct Fit {
  double n, a_ls, b_ls, a_mm, b_mm, err_ls, err_mm;
};

// Fits one n, starting from (a0, b0). Minimax on a non-smooth max: restart twice from the
// best point with a smaller simplex so Nelder-Mead cannot stall on a kink.
Fit fit_one(double n, double a0, double b0, double a1, double b1) {
  const Sampled s = tp::tables::cosn::sample_target(n, 1500);
  auto ls = [&](double a, double b) { return tp::tables::cosn::sq_error(s, a, b); };
  auto mm = [&](double a, double b) { return tp::tables::cosn::sampled_max_error(s, a, b); };
  auto to_ab = [](std::array<double, 2> p) {
    return std::array<double, 2>{std::exp(p[0]), std::exp(p[0]) + std::exp(p[1])};
  };
  std::array<double, 2> p{std::log(a0), std::log(b0 - a0)};
  p = nelder_mead(ls, p, 0.05, 80);
  p = nelder_mead(ls, p, 0.005, 60);
  const auto ab_ls = to_ab(p);
  std::array<double, 2> q{std::log(a1), std::log(b1 - a1)};
  for (double step : {0.05, 0.01, 0.002}) q = nelder_mead(mm, q, step, 80);
  const auto ab_mm = to_ab(q);
  return {n,
          ab_ls[0],
          ab_ls[1],
          ab_mm[0],
          ab_mm[1],
          tp::tables::cosn::max_error(n, ab_ls[0], ab_ls[1]),
          tp::tables::cosn::max_error(n, ab_mm[0], ab_mm[1])};
}

// All n <= 200, then 64 per decade up to 10,000, plus every n a test or bench names.
std::vector<int> n_grid() {
  std::set<int> ns;
  for (int n = 1; n <= 200; ++n) ns.insert(n);
  for (int k = 0;; ++k) {
    const double v = 200.0 * std::pow(10.0, k / 64.0);
    if (v > 10000.0) break;
    ns.insert(static_cast<int>(std::lround(v)));
  }
  for (int n : {250, 300, 500, 1000, 2000, 3000, 5000, 7500, 10000}) ns.insert(n);
  return {ns.begin(), ns.end()};
}

std::vector<Fit> fit_all() {
  std::vector<Fit> fits;
  // n = 1 starting point: the paper's formulas (labels corrected).
  double a_ls = tp::tables::cosn::paper_a(1), b_ls = tp::tables::cosn::paper_b(1);
  double a_mm = a_ls, b_mm = b_ls, prev = 1;
  for (int n : n_grid()) {
    const double sc = std::sqrt(prev / n);  // the optimum scales like 1/√n
    const Fit f = fit_one(n, a_ls * sc, b_ls * sc, a_mm * sc, b_mm * sc);
    fits.push_back(f);
    a_ls = f.a_ls, b_ls = f.b_ls, a_mm = f.a_mm, b_mm = f.b_mm, prev = n;
  }
  return fits;
}

// Angle in the firmware's format: Q2.29 radians (fixedpoint angle_t), rounded to nearest.
long long q29(double x) { return std::llround(std::ldexp(x, 29)); }
// Errors as integer parts per million of the peak (the header must stay integer-only).
long long ppm(double e) { return std::llround(e * 1e6); }

void write_array(FILE* out, const char* type, const char* name, const std::vector<Fit>& fits,
                 const std::function<long long(const Fit&)>& get) {
  std::fprintf(out, "inline constexpr std::array<%s, kCount> %s = {", type, name);
  for (std::size_t i = 0; i < fits.size(); ++i)
    std::fprintf(out, "%s%lld,", i % 8 == 0 ? "\n    " : " ", get(fits[i]));
  std::fprintf(out, "\n};\n");
}

int write_header(const char* path, const std::vector<Fit>& fits) {
  FILE* out = std::fopen(path, "w");
  if (!out) return 1;
  std::fprintf(out,
               "// Generated by tables/gen_cosn_fits.cpp -- do not edit.\n"
               "// Fitted Kuijk-Blake (a, b) for max(0,cos θ)^n over θ in [0, π]: least squares\n"
               "// (ls) and minimax (mm). Angles are Q2.29 raw radians; errors are the achieved\n"
               "// max |f - cos^n| in parts per million of the peak.\n"
               "#pragma once\n#include <array>\n#include <cstdint>\n\n"
               "namespace tp::tables::cosn_fits {\n\n"
               "inline constexpr int kCount = %zu;\n"
               "inline constexpr int kAngleFracBits = 29;\n",
               fits.size());
  write_array(out, "std::int32_t", "kN", fits, [](const Fit& f) { return std::llround(f.n); });
  write_array(out, "std::int32_t", "kA_ls", fits, [](const Fit& f) { return q29(f.a_ls); });
  write_array(out, "std::int32_t", "kB_ls", fits, [](const Fit& f) { return q29(f.b_ls); });
  write_array(out, "std::int32_t", "kA_mm", fits, [](const Fit& f) { return q29(f.a_mm); });
  write_array(out, "std::int32_t", "kB_mm", fits, [](const Fit& f) { return q29(f.b_mm); });
  write_array(out, "std::int32_t", "kErrPpm_ls", fits, [](const Fit& f) { return ppm(f.err_ls); });
  write_array(out, "std::int32_t", "kErrPpm_mm", fits, [](const Fit& f) { return ppm(f.err_mm); });
  std::fprintf(out, "\n}  // namespace tp::tables::cosn_fits\n");
  return std::fclose(out) == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: gen_cosn_fits OUT.hpp | --print\n");
    return 2;
  }
  const std::vector<Fit> fits = fit_all();
  if (std::strcmp(argv[1], "--print") == 0) {
    for (const Fit& f : fits)
      std::printf("%g %.9f %.9f %.9f %.9f %.6f %.6f\n", f.n, f.a_ls, f.b_ls, f.a_mm, f.b_mm,
                  100 * f.err_ls, 100 * f.err_mm);
    return 0;
  }
  return write_header(argv[1], fits);
}
