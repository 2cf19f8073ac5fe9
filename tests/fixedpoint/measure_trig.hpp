// CORDIC accuracy cases (fixedpoint/cordic.hpp), same conventions as measure.hpp: error in LSB
// of the output format against long double. Host code.
#pragma once

#include <cmath>
#include <vector>

#include "fixedpoint/cordic.hpp"
#include "tests/fixedpoint/measure.hpp"

namespace tp::fx::testing {

using angle16 = Q<2, 13, std::int16_t>;  // 16-bit angles, widened exactly into angle_t

// fn: sin_cos or the setup-grade sin_cos_fast.
inline ErrStats measure_sin_cos(const std::vector<std::int64_t>& angle_raws,
                                SinCos (*fn)(angle_t) = sin_cos) {
  ErrStats s;
  for (std::int64_t r : angle_raws) {
    const angle_t a = q_raw<angle_t>(r);
    const SinCos sc = fn(a);
    s.add(err_lsb(sc.sin, std::sin(to_ld(a))));
    s.add(err_lsb(sc.cos, std::cos(to_ld(a))));
  }
  return s;
}

inline std::vector<std::int64_t> angles16_as_angle_t() {
  std::vector<std::int64_t> v;
  for (std::int64_t r : exhaustive16()) v.push_back(r << 16);
  return v;
}

// fast: the setup-grade atan2_fast instead of atan2.
template <QType T>
ErrStats measure_atan2(const std::vector<std::int64_t>& ys, const std::vector<std::int64_t>& xs,
                       bool pairs, bool fast = false) {
  ErrStats s;
  auto one = [&](std::int64_t ry, std::int64_t rx) {
    if (ry == 0 && rx == 0) return;
    const T y = q_raw<T>(ry), x = q_raw<T>(rx);
    s.add(err_lsb(fast ? atan2_fast(y, x) : atan2(y, x), std::atan2(to_ld(y), to_ld(x))));
  };
  if (pairs)
    for (std::size_t i = 0; i < ys.size() && i < xs.size(); ++i) one(ys[i], xs[i]);
  else
    for (auto ry : ys)
      for (auto rx : xs) one(ry, rx);
  return s;
}

template <QType T>
ErrStats measure_magnitude(const std::vector<std::int64_t>& ys, const std::vector<std::int64_t>& xs,
                           bool pairs) {
  ErrStats s;
  auto one = [&](std::int64_t ry, std::int64_t rx) {
    const T y = q_raw<T>(ry), x = q_raw<T>(rx);
    s.add(err_lsb(to_polar(x, y).magnitude, std::hypot(to_ld(x), to_ld(y))));
  };
  if (pairs)
    for (std::size_t i = 0; i < ys.size() && i < xs.size(); ++i) one(ys[i], xs[i]);
  else
    for (auto ry : ys)
      for (auto rx : xs) one(ry, rx);
  return s;
}

inline ErrStats measure_acos(const std::vector<std::int64_t>& c_raws) {
  ErrStats s;
  for (std::int64_t r : c_raws) {
    const q1_30 c = q_raw<q1_30>(r);
    const long double cl = std::clamp(to_ld(c), -1.0L, 1.0L);
    s.add(err_lsb(acos_unit(c), std::acos(cl)));
  }
  return s;
}

inline std::vector<Case> trig_cases() {
  std::vector<Case> c;
  c.push_back({"sin_cos(angle_t) -> Q1.30", "all 2^16 Q2.13 angles",
               [] { return measure_sin_cos(angles16_as_angle_t()); }});
  c.push_back({"sin_cos(angle_t) -> Q1.30", "32-bit edges + 10^6 random", [] {
                 auto in = edge32();
                 auto r = random32(1000000);
                 in.insert(in.end(), r.begin(), r.end());
                 return measure_sin_cos(in);
               }});
  c.push_back({"atan2(Q7.8, Q7.8) -> angle_t", "y: all 2^16 x 16-bit edge x",
               [] { return measure_atan2<q7_8>(exhaustive16(), edge32(-32768, 32767), false); }});
  c.push_back({"atan2(Q15.16, Q15.16) -> angle_t", "32-bit edge x edge pairs",
               [] { return measure_atan2<q15_16>(edge32(), edge32(), false); }});
  c.push_back({"atan2(Q15.16, Q15.16) -> angle_t", "10^6 random pairs", [] {
                 return measure_atan2<q15_16>(random32(1000000),
                                              random32(1000000, INT32_MIN, INT32_MAX, 7u), true);
               }});
  c.push_back({"to_polar(Q7.8, Q7.8).magnitude", "y: all 2^16 x 16-bit edge x", [] {
                 return measure_magnitude<q7_8>(exhaustive16(), edge32(-32768, 32767), false);
               }});
  c.push_back({"to_polar(Q15.16, Q15.16).magnitude", "32-bit edge x edge + 10^6 random", [] {
                 ErrStats s = measure_magnitude<q15_16>(edge32(), edge32(), false);
                 s.merge(measure_magnitude<q15_16>(
                     random32(1000000), random32(1000000, INT32_MIN, INT32_MAX, 7u), true));
                 return s;
               }});
  c.push_back({"acos_unit(Q1.30) -> angle_t", "all 2^16 Q1.14 cosines", [] {
                 std::vector<std::int64_t> in;
                 for (auto r : exhaustive16()) in.push_back(r << 16);
                 return measure_acos(in);
               }});
  c.push_back({"acos_unit(Q1.30) -> angle_t", "32-bit edges + 10^6 random in [-1, 1]", [] {
                 auto in = edge32();
                 auto r = random32(1000000, -(1 << 30), 1 << 30);
                 in.insert(in.end(), r.begin(), r.end());
                 return measure_acos(in);
               }});
  return c;
}

// The setup-grade variants (8 CORDIC steps + closed-form residual), over the same input sets.
inline std::vector<Case> trig_fast_cases() {
  std::vector<Case> c;
  c.push_back({"sin_cos_fast(angle_t) -> Q1.30", "all 2^16 Q2.13 angles",
               [] { return measure_sin_cos(angles16_as_angle_t(), sin_cos_fast); }});
  c.push_back({"sin_cos_fast(angle_t) -> Q1.30", "32-bit edges + 10^6 random", [] {
                 auto in = edge32();
                 auto r = random32(1000000);
                 in.insert(in.end(), r.begin(), r.end());
                 return measure_sin_cos(in, sin_cos_fast);
               }});
  c.push_back({"atan2_fast(Q7.8, Q7.8) -> angle_t", "y: all 2^16 x 16-bit edge x", [] {
                 return measure_atan2<q7_8>(exhaustive16(), edge32(-32768, 32767), false, true);
               }});
  c.push_back({"atan2_fast(Q15.16, Q15.16) -> angle_t", "32-bit edge x edge pairs",
               [] { return measure_atan2<q15_16>(edge32(), edge32(), false, true); }});
  c.push_back({"atan2_fast(Q15.16, Q15.16) -> angle_t", "10^6 random pairs", [] {
                 return measure_atan2<q15_16>(
                     random32(1000000), random32(1000000, INT32_MIN, INT32_MAX, 7u), true, true);
               }});
  return c;
}

}  // namespace tp::fx::testing
