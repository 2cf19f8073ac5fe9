// CORDIC accuracy bounds over the shared input sets (measure_trig.hpp), in LSB of the output.
// Where the bounds come from: `build/release/bench/accuracy_fixedpoint` measured max |err| =
// 0.5018784 (sin_cos, 32-bit set), 0.5009528 (atan2), 0.5000000 (to_polar magnitude),
// 0.5009300 (acos_unit): 0.5 of output rounding plus the residual angle of 40 CORDIC steps
// (< 2^-39 rad = 0.002 LSB of Q1.30). Pinned at 0.503 (margin 0.001 LSB over the worst).
// Mean signed error: measured |mean| <= 0.0255 (to_polar Q7.8); pinned at 0.035.
#include <gtest/gtest.h>

#include "tests/fixedpoint/measure_trig.hpp"

TEST(TrigAccuracy, AllCases) {
  for (const auto& c : tp::fx::testing::trig_cases()) {
    const auto s = c.run();
    EXPECT_GT(s.n, 1000u) << c.name;
    EXPECT_LE(s.max_abs, 0.503L) << c.name << " / " << c.inputs;
    EXPECT_LE(std::fabs(s.mean()), 0.035L) << c.name << " / " << c.inputs;
  }
}

// The setup-grade variants (atan2_fast, sin_cos_fast: 8 CORDIC steps and a closed-form
// residual, used by firmware/kb). Measured by `build/release/bench/accuracy_fixedpoint` on
// 2026-12-01: max |err| = 0.5049800 (sin_cos_fast, 32-bit set), 0.5030424 (atan2_fast, random
// pairs); |mean| <= 0.0011. Pinned at 0.506 (margin 0.001 LSB) and 0.035 as above.
TEST(TrigAccuracy, SetupGradeCases) {
  for (const auto& c : tp::fx::testing::trig_fast_cases()) {
    const auto s = c.run();
    EXPECT_GT(s.n, 1000u) << c.name;
    EXPECT_LE(s.max_abs, 0.506L) << c.name << " / " << c.inputs;
    EXPECT_LE(std::fabs(s.mean()), 0.035L) << c.name << " / " << c.inputs;
  }
}
