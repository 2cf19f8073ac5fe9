// fixedpoint/divide.hpp: the division built from 32-bit divisions (what the Cortex-M build runs
// instead of the compiler's 64-bit helper) equals C++'s / and % bit for bit. Run on x86, where
// / and % are the hardware's, over the operand classes where Algorithm D's estimate needs its
// corrections: powers of two and their neighbours, all-ones patterns, every pair of bit lengths.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <vector>

#include "fixedpoint/divide.hpp"

namespace fx = tp::fx;
using u64 = std::uint64_t;
using i64 = std::int64_t;

namespace {

u64 splitmix(u64& state) {
  u64 z = (state += 0x9e3779b97f4a7c15u);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
  return z ^ (z >> 31);
}

// Values that stress a digit-wise division: 2^k and 2^k +- 1, 2^k - 2^j (runs of ones), and
// 0x8000.., 0xffff.. patterns in both halves.
std::vector<u64> special_values() {
  std::vector<u64> v = {0,
                        1,
                        2,
                        3,
                        0xffffu,
                        0x10000u,
                        0xffffffffu,
                        0x100000000u,
                        0xffffffff00000000u,
                        0x80000000u,
                        0x8000000080000000u,
                        0x7fffffffffffffffu,
                        0x8000000000000000u,
                        ~u64{0}};
  for (int k = 1; k < 64; ++k) {
    const u64 p = u64{1} << k;
    v.insert(v.end(), {p, p - 1, p + 1});
    for (int j = 0; j < k; j += 7) v.push_back(p - (u64{1} << j));
  }
  return v;
}

void expect_unsigned(u64 n, u64 d) {
  const fx::UDivMod m = fx::detail::udivmod_by_halves(n, d);
  ASSERT_EQ(m.quot, n / d) << n << " / " << d;
  ASSERT_EQ(m.rem, n % d) << n << " % " << d;
}

void expect_signed(i64 n, i64 d) {
  if (n == std::numeric_limits<i64>::min() && d == -1) return;  // overflows, undefined
  const fx::IDivMod m = fx::detail::idivmod_by_halves(n, d);
  ASSERT_EQ(m.quot, n / d) << n << " / " << d;
  ASSERT_EQ(m.rem, n % d) << n << " % " << d;
}

}  // namespace

// Usable where the firmware needs constants.
static_assert(fx::detail::udivmod_by_halves(~u64{0}, 3).quot == 0x5555555555555555u);
static_assert(fx::detail::udivmod_by_halves(~u64{0}, u64{1} << 40).rem == (u64{1} << 40) - 1);
static_assert(fx::detail::idivmod_by_halves(-7, 2).quot == -3);
static_assert(fx::detail::idivmod_by_halves(-7, 2).rem == -1);

TEST(DivideByHalves, SpecialValuesPairwise) {
  const std::vector<u64> v = special_values();
  for (u64 n : v)
    for (u64 d : v)
      if (d != 0) expect_unsigned(n, d);
}

TEST(DivideByHalves, RandomOperandsOfEveryBitLength) {
  u64 state = 12345;
  for (int bn = 1; bn <= 64; ++bn)
    for (int bd = 1; bd <= 64; ++bd)
      for (int i = 0; i < 200; ++i) {
        const u64 n = splitmix(state) >> (64 - bn), d = (splitmix(state) >> (64 - bd)) | 1u;
        expect_unsigned(n, d);
        if (d > 1) expect_unsigned(n, d & ~u64{1});  // even divisors too
      }
}

TEST(DivideByHalves, ThirtyTwoBitDivisorsNearTheQuotientDigitLimits) {
  // n = q * d + r with q just below and above the 16- and 32-bit digit boundaries, r = 0 and
  // r = d - 1: where the first estimate of a quotient digit is too large.
  u64 state = 99;
  for (int i = 0; i < 20000; ++i) {
    const u64 d = (splitmix(state) >> 32) | 0x80000000u >> (i % 32);
    for (u64 q : {u64{0xffff}, u64{0x10000}, u64{0xffffffff}, u64{0x100000000}}) {
      if (q > ~u64{0} / d) continue;
      const u64 base = q * d;
      expect_unsigned(base, d);
      if (base <= ~u64{0} - (d - 1)) expect_unsigned(base + d - 1, d);
    }
  }
}

TEST(DivideByHalves, SignedTruncatesTowardZero) {
  const std::vector<u64> v = special_values();
  for (u64 a : v)
    for (u64 b : v) {
      const auto n = static_cast<i64>(a), d = static_cast<i64>(b);
      if (d == 0) continue;
      expect_signed(n, d);
      if (n != std::numeric_limits<i64>::min()) expect_signed(-n, d);
      if (d != std::numeric_limits<i64>::min()) expect_signed(n, -d);
    }
  u64 state = 7;
  for (int i = 0; i < 200000; ++i) {
    const auto n = static_cast<i64>(splitmix(state)) >> (i % 63);
    const auto d = static_cast<i64>(splitmix(state)) >> (1 + i % 62);
    if (d != 0) expect_signed(n, d);
  }
}

TEST(DivideByHalves, TheDispatchedFunctionsAreExact) {
  // On x86 these are / and %; on the Cortex-M images the target tests check whole frames.
  EXPECT_EQ(fx::udiv(~u64{0}, 10), ~u64{0} / 10);
  EXPECT_EQ(fx::idiv(-1000000000007, 13), -1000000000007 / 13);
  EXPECT_EQ(fx::idivmod(-1000000000007, 13).rem, -1000000000007 % 13);
  EXPECT_EQ(fx::udivmod(u64{1} << 63, (u64{1} << 33) + 5).rem,
            (u64{1} << 63) % ((u64{1} << 33) + 5));
}
