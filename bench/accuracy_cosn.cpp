// Prints the per-n accuracy table of the Kuijk-Blake (a, b) sources for docs/ACCURACY.md:
// max |f − max(0,cos θ)^n| over θ in [0, π], in % of the peak, for the paper's closed forms
// (labels corrected), our two closed forms (minimax and least squares; the firmware's), the
// least-squares fit and the minimax fit, with a, b. All (a, b) are Q2.29 integers converted to
// double.
//   usage: accuracy_cosn            (markdown table, then the worst n of each source)
#include <cmath>
#include <cstdio>

#include "firmware/cosn.hpp"
#include "host/standard_output.hpp"
#include "tables/cosn_fits.hpp"
#include "tables/cosn_fits_lookup.hpp"
#include "tables/cosn_reference.hpp"

namespace {

using namespace tp::fw::cosn;
namespace ref = tp::tables::cosn;
namespace fits = tp::tables::cosn_fits;

constexpr int kSamples = 20000;

double d29(long long raw) { return std::ldexp(static_cast<double>(raw), -29); }

struct AB {
  double a, b;
};
AB of(const CosnParams& p) { return {d29(p.a.raw()), d29(p.b.raw())}; }
AB of(const fits::FitParams& p) { return {d29(p.a.raw()), d29(p.b.raw())}; }

int grid_index(int n) {
  for (int i = 0; i < fits::kCount; ++i)
    if (fits::kN[i] == n) return i;
  return -1;
}
AB ls_fit(int i) { return {d29(fits::kA_ls[i]), d29(fits::kB_ls[i])}; }

double err(int n, AB p, int samples = kSamples) { return ref::max_error(n, p.a, p.b, samples); }

void row(int n) {
  const int i = grid_index(n);
  const AB pp = of(paper_params(n)), cf = of(closed_params(n)), lc = of(least_squares_params(n)),
           mm = of(fits::minimax_params(n));
  const AB ls = i >= 0 ? ls_fit(i) : AB{NAN, NAN};
  std::printf(
      "| %5d | %6.2f | %6.3f | %6.3f | %6.3f | %6.3f | %.5f %.5f | %.5f %.5f | %.5f %.5f | "
      "%.5f %.5f | %.5f %.5f |\n",
      n, 100 * err(n, pp), 100 * err(n, cf), 100 * err(n, lc), 100 * err(n, ls), 100 * err(n, mm),
      pp.a, pp.b, cf.a, cf.b, lc.a, lc.b, ls.a, ls.b, mm.a, mm.b);
}

template <class Source>
void worst(const char* name, Source src, int from) {
  double w = 0;
  int wn = 0;
  for (int n = from; n <= kMaxN; ++n) {
    const double e = err(n, of(src(n)), 4000);
    if (e > w) w = e, wn = n;
  }
  std::printf("| %s, n = %d..10000 | %d | %.3f |\n", name, from, wn, 100 * err(wn, of(src(wn))));
}

}  // namespace

int main(int argc, char**) {
  if (argc > 1) {  // it takes none: --help or a typo ran the whole table and exited 0
    std::fprintf(stderr, "usage: accuracy_cosn (no arguments): the table of docs/ACCURACY.md\n");
    return 2;
  }
  std::printf(
      "| n | paper %% | closed %% | LS closed %% | LS fit %% | minimax %% | paper a b | "
      "closed a b | LS closed a b | LS a b | minimax a b |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (int n : {1, 2, 3, 5, 10, 20, 50, 100, 125, 200, 500, 1000, 2000, 5000, 10000}) row(n);
  std::printf("\n| source | worst n | max error %% |\n|---|---|---|\n");
  worst(
      "paper", [](int n) { return paper_params(n); }, 1);
  worst(
      "paper", [](int n) { return paper_params(n); }, 126);
  worst(
      "closed form", [](int n) { return closed_params(n); }, 1);
  worst(
      "closed form", [](int n) { return closed_params(n); }, 3);
  worst(
      "least-squares closed form", [](int n) { return least_squares_params(n); }, 1);
  worst(
      "least-squares closed form", [](int n) { return least_squares_params(n); }, 3);
  worst(
      "minimax table (interpolated past 200)", [](int n) { return fits::minimax_params(n); }, 1);
  worst(
      "minimax table (interpolated past 200)", [](int n) { return fits::minimax_params(n); }, 3);
  double w = 0;
  int wn = 0;
  for (int i = 0; i < fits::kCount; ++i) {
    const double e = err(fits::kN[i], ls_fit(i));
    if (e > w) w = e, wn = fits::kN[i];
  }
  std::printf("| least squares (grid points) | %d | %.3f |\n", wn, 100 * w);
  return tp::host::standard_output_written("accuracy_cosn") ? 0 : 1;
}
