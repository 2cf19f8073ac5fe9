// The quadratic forward differencing in y of the coherent span setup (kb_coherence.hpp): after
// h1 and h2 steps it reproduces the exact samples it was fitted to, within the rounding of its
// coefficients (below one unit of the parameter's raw format over a chunk).
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "firmware/kb/kb_coherence.hpp"

namespace kb = tp::fw::kb;

TEST(KbCoherence, QuadraticHitsItsSamples) {
  std::mt19937_64 rng(9);
  std::uniform_int_distribution<std::int64_t> value(-(std::int64_t{1} << 40),
                                                    std::int64_t{1} << 40);
  std::int64_t worst = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const std::int64_t h2 =
        kb::kMinChunkRows +
        static_cast<std::int64_t>(rng() % (kb::kChunkRows + 2 - kb::kMinChunkRows));
    const std::int64_t h1 =
        1 + static_cast<std::int64_t>(rng() % static_cast<std::uint64_t>(h2 - 1));
    const std::int64_t p0 = value(rng), p1 = value(rng), p2 = value(rng);
    kb::QuadY q;
    q.fit(p0, p1, p2, h1, h2);
    EXPECT_EQ(q.value(), p0);
    for (std::int64_t k = 1; k <= h2; ++k) {
      q.step();
      if (k == h1) worst = std::max(worst, std::abs(q.value() - p1));
      if (k == h2) worst = std::max(worst, std::abs(q.value() - p2));
    }
  }
  std::printf("quadratic in y: max |error| at the samples %lld raw units\n",
              static_cast<long long>(worst));
  // Measured 0 (`kb_coherence_test`): the coefficients are rounded to 2^-10 of a unit, and over
  // at most 17 rows k·|δB| + k²·|δA| <= (17 + 289)/2 · 2^-10 < 0.3 unit. Pinned at 1.
  EXPECT_LE(worst, 1);
}
