// Fits the rational-correction coefficients of the firmware's closed forms for the Kuijk-Blake
// (a, b) (firmware/cosn.hpp).
//
// Default mode, closed_params (the minimax closed form):
//   a = α (n² + p1 n + p0) / ((n² + q1 n + q0) √n),  b = β (n² + r1 n + r0) / ((n² + s1 n + s0) √n)
// α, β are the large-n minimax limits (gen_cosn_fits --print: a√n, b√n at n = 10,000).
// Objective: max over n of (max error / target), target 1.5 %, 1.85 % at n = 2 (the minimax
// optimum there is 1.765 %), 2.5 % at n = 1; n = every value <= 200 and a 10 %-spaced grid
// to 10,000. 8-D Nelder-Mead with restarts. Prints the coefficients in Q16 (what cosn.hpp
// stores) and the worst error per n range of the rounded coefficients.
//   usage: fit_cosn_closed_form [rounds] [refine]   (about 5 s per round on one core)
// From scratch, 6 rounds reach objective 0.9964 (worst 1.494 % for n >= 3). The coefficients
// stored in cosn.hpp came from a longer run of the same objective through an intermediate
// [1/1] form and one round of "refine" (objective 0.9796: 2.449 % at n = 1, 1.812 % at
// n = 2, 1.469 % for n >= 3); "refine" restarts from them.
//
// Mode "least-squares", least_squares_params (the Kuijk-Blake methods' default):
//   a = α (n² + p1 n + p0) / ((n² + q1 n + q0) √n), the same form for b, with α, β the
//   least-squares fit's a√n, b√n at n = 10,000 (tables/cosn_fits.hpp). Objective: the max
//   relative distance to the generated least-squares (a, b) over every grid point (every
//   n <= 200, 64 per decade to 10,000); a and b are fitted apart, 4-D Nelder-Mead with 12
//   restarts, under a second. Prints the Q16 coefficients and the rounded form's distances.
//   usage: fit_cosn_closed_form least-squares
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "host/standard_output.hpp"
#include "tables/cosn_fits.hpp"
#include "tables/cosn_reference.hpp"

namespace {

using namespace tp::tables::cosn;
constexpr int P = 8;
using V = std::array<double, P>;
namespace fits = tp::tables::cosn_fits;
constexpr double kAlpha = 0.75318, kBeta = 2.99243;

double rational(double s, double n, double u1, double u0, double v1, double v0) {
  return s * (n * n + u1 * n + u0) / ((n * n + v1 * n + v0) * std::sqrt(n));
}
double a_of(const V& p, double n) { return rational(kAlpha, n, p[0], p[1], p[2], p[3]); }
double b_of(const V& p, double n) { return rational(kBeta, n, p[4], p[5], p[6], p[7]); }
double target(int n) { return n == 1 ? 0.025 : (n == 2 ? 0.0185 : 0.015); }

struct Problem {
  std::vector<int> ns;
  std::vector<Sampled> samples;
  double operator()(const V& p) const {
    double worst = 0;
    for (std::size_t i = 0; i < ns.size(); ++i) {
      const double a = a_of(p, ns[i]), b = b_of(p, ns[i]);
      if (!(a > 0 && b > a)) return 1e9;
      worst = std::max(worst, sampled_max_error(samples[i], a, b) / target(ns[i]));
    }
    return worst;
  }
};

// Nelder-Mead in D dimensions (called as nelder_mead<D>).
template <int D, class F>
std::array<double, D> nelder_mead(const F& f, std::array<double, D> x, double step, int iters) {
  constexpr int P = D;
  using V = std::array<double, D>;
  std::array<V, P + 1> s;
  std::array<double, P + 1> v;
  for (int i = 0; i <= P; ++i) {
    s[i] = x;
    if (i) s[i][i - 1] += step * std::max(0.1, std::fabs(x[i - 1]));
    v[i] = f(s[i]);
  }
  for (int k = 0; k < iters; ++k) {
    std::array<int, P + 1> o;
    for (int i = 0; i <= P; ++i) o[i] = i;
    std::sort(o.begin(), o.end(), [&](int l, int r) { return v[l] < v[r]; });
    const auto s0 = s;
    const auto v0 = v;
    for (int i = 0; i <= P; ++i) s[i] = s0[o[i]], v[i] = v0[o[i]];
    V c{};
    for (int i = 0; i < P; ++i)
      for (int j = 0; j < P; ++j) c[j] += s[i][j] / P;
    auto along = [&](double t) {
      V r;
      for (int j = 0; j < P; ++j) r[j] = c[j] + t * (s[P][j] - c[j]);
      return r;
    };
    const V r = along(-1);
    const double fr = f(r);
    if (fr < v[0]) {
      const V e = along(-2);
      const double fe = f(e);
      if (fe < fr)
        s[P] = e, v[P] = fe;
      else
        s[P] = r, v[P] = fr;
    } else if (fr < v[P - 1]) {
      s[P] = r, v[P] = fr;
    } else {
      const V kk = along(fr < v[P] ? -0.5 : 0.5);
      const double fk = f(kk);
      if (fk < std::min(fr, v[P])) {
        s[P] = kk, v[P] = fk;
      } else {
        for (int i = 1; i <= P; ++i) {
          for (int j = 0; j < P; ++j) s[i][j] = (s[i][j] + s[0][j]) / 2;
          v[i] = f(s[i]);
        }
      }
    }
  }
  return s[static_cast<std::size_t>(std::min_element(v.begin(), v.end()) - v.begin())];
}

// Mode "least-squares": one parameter (a or b) of least_squares_params against the generated
// least-squares fit, as Q2.29 raw values.
struct Tracking {
  const std::array<std::int32_t, fits::kCount>& fit;
  double scale() const { return std::ldexp(fit[fits::kCount - 1], -29) * 100; }  // √10,000
  double at(const std::array<double, 4>& c, int i) const {
    return rational(scale(), fits::kN[i], c[0], c[1], c[2], c[3]);
  }
  double distance(const std::array<double, 4>& c, int i) const {
    return std::fabs(at(c, i) / std::ldexp(fit[i], -29) - 1);
  }
  double operator()(const std::array<double, 4>& c) const {
    double worst = 0;
    for (int i = 0; i < fits::kCount; ++i) {
      if (!(at(c, i) > 0)) return 1e9;
      worst = std::max(worst, distance(c, i));
    }
    return worst;
  }
};

void fit_least_squares(const char* name, const Tracking& f, std::array<double, 4> c) {
  for (int r = 0; r < 12; ++r) c = nelder_mead<4>(f, c, 0.2 / (r + 1), 3000);
  std::array<double, 4> q;
  std::printf("%s: scale Q2.29 %lld, Q16:", name, std::llround(f.scale() * (1 << 29)));
  for (int i = 0; i < 4; ++i) {
    const long long raw = std::llround(c[i] * 65536);
    q[i] = raw / 65536.0;
    std::printf(" %lld", raw);
  }
  std::printf("; max relative distance %.2e (rounded %.2e)\n", f(c), f(q));
}

int least_squares_mode() {
  fit_least_squares("a", Tracking{fits::kA_ls}, {2.6, 1.6, 1.8, 0.8});
  fit_least_squares("b", Tracking{fits::kB_ls}, {0.8, -0.2, 1.3, 0.3});
  return tp::host::standard_output_written("fit_cosn_closed_form") ? 0 : 1;
}

int usage(const std::string& problem) {
  std::fprintf(stderr,
               "fit_cosn_closed_form: %s\nusage: fit_cosn_closed_form [rounds] [refine]\n"
               "       fit_cosn_closed_form least-squares\n",
               problem.c_str());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string_view(argv[1]) == "least-squares") {
    if (argc > 2) return usage("least-squares takes no more arguments");
    return least_squares_mode();
  }
  // Rounds as a whole number in 1..1000 (atoi made "refine" alone, "-3" and "x" zero rounds, and
  // printed the starting point's coefficients as a fit).
  int rounds = 6;
  if (argc > 1) {
    const std::string_view text = argv[1];
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), rounds);
    if (ec != std::errc() || end != text.data() + text.size() || rounds < 1 || rounds > 1000)
      return usage("rounds must be a whole number in 1..1000, got '" + std::string(text) + "'");
  }
  if (argc > 3 || (argc > 2 && std::string_view(argv[2]) != "refine"))
    return usage("the second argument can only be 'refine'");
  Problem f;
  for (int n = 1; n <= 200; ++n) f.ns.push_back(n);
  for (double v = 220; v < 10000; v *= 1.1) f.ns.push_back(static_cast<int>(v));
  f.ns.push_back(10000);
  for (int n : f.ns) f.samples.push_back(sample_target(n, 1500));
  // Start: a [1/1] correction matched by hand to the minimax a√n, b√n at n = 2 and 10,
  // written as [2/2] with a common factor (n + 1).
  V p{2.656, 1.656, 1.77, 0.77, 0.815, -0.185, 1.293, 0.293};
  if (argc > 2 && std::string_view(argv[2]) == "refine") {
    const long long stored[P] = {261676, 148572, 241773, -41575, 98254, -50462, 119544, 15635};
    for (int i = 0; i < P; ++i) p[i] = stored[i] / 65536.0;
  }
  std::printf("start objective %.6f\n", f(p));
  for (int r = 0; r < rounds; ++r) {
    p = nelder_mead<P>(f, p, 0.1 / (r + 1), 1500);
    std::printf("round %d objective %.6f\n", r, f(p));
  }
  V q;
  std::printf("Q16:");
  for (int i = 0; i < P; ++i) {
    const long long raw = std::llround(p[i] * 65536);
    q[i] = raw / 65536.0;
    std::printf(" %lld", raw);
  }
  double w1 = 0, w2 = 0, w3 = 0;
  int n3 = 0;
  for (int n = 1; n <= 10000; ++n) {
    const double e = max_error(n, a_of(q, n), b_of(q, n), 4000);
    if (n == 1)
      w1 = e;
    else if (n == 2)
      w2 = e;
    else if (e > w3)
      w3 = e, n3 = n;
  }
  std::printf("\nmax error: n=1 %.3f %%, n=2 %.3f %%, 3..10000 %.3f %% (n=%d)\n", 100 * w1,
              100 * w2, 100 * w3, n3);
  return tp::host::standard_output_written("fit_cosn_closed_form") ? 0 : 1;
}
