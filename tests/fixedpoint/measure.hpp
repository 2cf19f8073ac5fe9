// Error measurements of every fixed-point function against long double, over the input sets
// of input_sets.hpp. The tests pin bounds on these numbers; bench/accuracy_fixedpoint prints
// them (docs/ACCURACY.md). Host code.
#pragma once

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "fixedpoint/arith.hpp"
#include "fixedpoint/sqrt.hpp"
#include "fixedpoint/vec3.hpp"
#include "tests/fixedpoint/input_sets.hpp"

namespace tp::fx::testing {

using q7_8 = Q<7, 8, std::int16_t>;
using q4_11 = Q<4, 11, std::int16_t>;

template <QType Q>
Q q_raw(std::int64_t r) {
  return Q::from_raw(static_cast<typename Q::storage_type>(r));
}

// Unary f over raw inputs: err of f(x) against ref(x) in LSB of To.
template <QType To, QType From, class F, class R>
ErrStats measure_unary(const std::vector<std::int64_t>& raws, F f, R ref) {
  ErrStats s;
  for (std::int64_t r : raws) {
    const From x = q_raw<From>(r);
    s.add(err_lsb(f(x), ref(to_ld(x))));
  }
  return s;
}

// Binary f over the cartesian product of two raw sets.
template <QType To, QType A, QType B, class F, class R>
ErrStats measure_binary(const std::vector<std::int64_t>& as, const std::vector<std::int64_t>& bs,
                        F f, R ref) {
  ErrStats s;
  for (std::int64_t ra : as)
    for (std::int64_t rb : bs) {
      const A a = q_raw<A>(ra);
      const B b = q_raw<B>(rb);
      if (b.raw() == 0) continue;  // singular points are tested on their own
      s.add(err_lsb(f(a, b), ref(to_ld(a), to_ld(b))));
    }
  return s;
}

// Binary f over pairs (as[i], bs[i]).
template <QType To, QType A, QType B, class F, class R>
ErrStats measure_pairs(const std::vector<std::int64_t>& as, const std::vector<std::int64_t>& bs,
                       F f, R ref) {
  ErrStats s;
  for (std::size_t i = 0; i < as.size() && i < bs.size(); ++i) {
    const A a = q_raw<A>(as[i]);
    const B b = q_raw<B>(bs[i]);
    if (b.raw() == 0) continue;
    s.add(err_lsb(f(a, b), ref(to_ld(a), to_ld(b))));
  }
  return s;
}

inline std::vector<std::int64_t> positive(std::vector<std::int64_t> v) {
  std::erase_if(v, [](std::int64_t x) { return x <= 0; });
  return v;
}

// ---- the measured cases: one function per row of the docs table -------------------------
struct Case {
  std::string name;    // function and formats
  std::string inputs;  // description of the input set
  std::function<ErrStats()> run;
};

inline long double ld_div(long double a, long double b) { return a / b; }
inline long double ld_sqrt(long double a) { return std::sqrt(a); }
inline long double ld_rsqrt(long double a) { return 1.0L / std::sqrt(a); }

inline std::vector<Case> arith_cases() {
  using std::int64_t;
  std::vector<Case> c;
  c.push_back({"div<Q7.8>(Q7.8, Q7.8)", "all 2^16 num x 16-bit edge den", [] {
                 return measure_binary<q7_8, q7_8, q7_8>(
                     exhaustive16(), edge32(-32768, 32767),
                     [](q7_8 a, q7_8 b) { return div<q7_8>(a, b); }, ld_div);
               }});
  c.push_back({"div<Q7.8>(Q7.8, Q7.8)", "16-bit edge num x all 2^16 den", [] {
                 return measure_binary<q7_8, q7_8, q7_8>(
                     edge32(-32768, 32767), exhaustive16(),
                     [](q7_8 a, q7_8 b) { return div<q7_8>(a, b); }, ld_div);
               }});
  c.push_back({"div<Q15.16>(Q15.16, Q15.16)", "32-bit edge x edge pairs", [] {
                 return measure_binary<q15_16, q15_16, q15_16>(
                     edge32(), edge32(), [](q15_16 a, q15_16 b) { return div<q15_16>(a, b); },
                     ld_div);
               }});
  c.push_back({"div<Q15.16>(Q15.16, Q15.16)", "10^6 random pairs", [] {
                 return measure_pairs<q15_16, q15_16, q15_16>(
                     random32(1000000), random32(1000000, INT32_MIN, INT32_MAX, 7u),
                     [](q15_16 a, q15_16 b) { return div<q15_16>(a, b); }, ld_div);
               }});
  c.push_back({"div<Q1.30>(Q1.30, Q15.16)", "32-bit edge x edge pairs", [] {
                 return measure_binary<q1_30, q1_30, q15_16>(
                     edge32(), edge32(), [](q1_30 a, q15_16 b) { return div<q1_30>(a, b); },
                     ld_div);
               }});
  c.push_back({"mul_sat<Q15.16>(Q15.16, Q15.16)", "32-bit edge x edge pairs", [] {
                 return measure_binary<q15_16, q15_16, q15_16>(
                     edge32(), edge32(), [](q15_16 a, q15_16 b) { return mul_sat<q15_16>(a, b); },
                     [](long double a, long double b) { return a * b; });
               }});
  c.push_back({"sqrt<Q7.8>(Q7.8)", "all 2^15 positive inputs", [] {
                 return measure_unary<q7_8, q7_8>(
                     positive(exhaustive16()), [](q7_8 x) { return sqrt<q7_8>(x); }, ld_sqrt);
               }});
  c.push_back({"sqrt<Q1.14>(Q1.14)", "all 2^15 positive inputs", [] {
                 return measure_unary<q1_14, q1_14>(
                     positive(exhaustive16()), [](q1_14 x) { return sqrt<q1_14>(x); }, ld_sqrt);
               }});
  c.push_back({"sqrt<Q15.16>(Q15.16)", "32-bit edges + 10^6 random", [] {
                 auto in = positive(edge32());
                 auto r = random_log32(1000000);
                 in.insert(in.end(), r.begin(), r.end());
                 return measure_unary<q15_16, q15_16>(
                     in, [](q15_16 x) { return sqrt<q15_16>(x); }, ld_sqrt);
               }});
  c.push_back({"sqrt<Q1.30>(Q1.30)", "32-bit edges + 10^6 random", [] {
                 auto in = positive(edge32());
                 auto r = random_log32(1000000);
                 in.insert(in.end(), r.begin(), r.end());
                 return measure_unary<q1_30, q1_30>(
                     in, [](q1_30 x) { return sqrt<q1_30>(x); }, ld_sqrt);
               }});
  c.push_back({"rsqrt<Q4.11>(Q7.8)", "all 2^15 positive inputs", [] {
                 return measure_unary<q4_11, q7_8>(
                     positive(exhaustive16()), [](q7_8 x) { return rsqrt<q4_11>(x); }, ld_rsqrt);
               }});
  c.push_back({"rsqrt<Q15.16>(Q15.16)", "32-bit edges + 10^6 random", [] {
                 auto in = positive(edge32());
                 auto r = random_log32(1000000);
                 in.insert(in.end(), r.begin(), r.end());
                 return measure_unary<q15_16, q15_16>(
                     in, [](q15_16 x) { return rsqrt<q15_16>(x); }, ld_rsqrt);
               }});
  c.push_back({"rsqrt<Q1.30>(Q15.16)", "32-bit edges + 10^6 random", [] {
                 auto in = positive(edge32());
                 auto r = random_log32(1000000);
                 in.insert(in.end(), r.begin(), r.end());
                 return measure_unary<q1_30, q15_16>(
                     in, [](q15_16 x) { return rsqrt<q1_30>(x); }, ld_rsqrt);
               }});
  return c;
}

// Vectors: component raws drawn from a set; the error is the worst component.
template <QType To, QType T, class F, class R>
ErrStats measure_vec(const std::vector<Vec3<T>>& vs, F f, R ref) {
  ErrStats s;
  for (const auto& v : vs) {
    const Vec3<To> got = f(v);
    long double rx, ry, rz;
    ref(to_ld(v.x), to_ld(v.y), to_ld(v.z), rx, ry, rz);
    s.add(err_lsb(got.x, rx));
    s.add(err_lsb(got.y, ry));
    s.add(err_lsb(got.z, rz));
  }
  return s;
}

inline void ld_normalize(long double x, long double y, long double z, long double& ox,
                         long double& oy, long double& oz) {
  const long double l = std::sqrt(x * x + y * y + z * z);
  ox = x / l;
  oy = y / l;
  oz = z / l;
}

// x over all 2^16 raws of Q1.14 with (y, z) from a few fixed pairs (zero vector skipped).
inline std::vector<Vec3<q1_14>> vecs16() {
  std::vector<Vec3<q1_14>> v;
  const std::int64_t yz[][2] = {{0, 0},          {1, 0},      {-16384, 0}, {5000, -7000},
                                {32767, -32768}, {123, 4567}, {-2, 1}};
  for (auto [y, z] : yz)
    for (std::int64_t x : exhaustive16()) {
      if (x == 0 && y == 0 && z == 0) continue;
      v.push_back({q_raw<q1_14>(x), q_raw<q1_14>(y), q_raw<q1_14>(z)});
    }
  return v;
}
// Random Q1.30 vectors, components uniform in [-2, 2) and, separately, tiny ones.
inline std::vector<Vec3<q1_30>> vecs32(std::size_t n) {
  std::vector<Vec3<q1_30>> v;
  auto a = random32(3 * n, INT32_MIN, INT32_MAX, 11u);
  for (std::size_t i = 0; i < n; ++i)
    v.push_back({q_raw<q1_30>(a[3 * i]), q_raw<q1_30>(a[3 * i + 1]), q_raw<q1_30>(a[3 * i + 2])});
  auto b = random32(3 * n / 10, -1000, 1000, 12u);
  for (std::size_t i = 0; i + 2 < b.size(); i += 3) {
    if (b[i] == 0 && b[i + 1] == 0 && b[i + 2] == 0) continue;
    v.push_back({q_raw<q1_30>(b[i]), q_raw<q1_30>(b[i + 1]), q_raw<q1_30>(b[i + 2])});
  }
  const auto e = edge32();  // edge-valued components, in every position
  for (std::size_t i = 0; i < e.size(); ++i) {
    const std::int64_t a0 = e[i], a1 = e[(i * 7 + 3) % e.size()], a2 = e[(i * 13 + 5) % e.size()];
    if (a0 == 0 && a1 == 0 && a2 == 0) continue;
    v.push_back({q_raw<q1_30>(a0), q_raw<q1_30>(a1), q_raw<q1_30>(a2)});
  }
  return v;
}

inline std::vector<Case> vec_cases() {
  std::vector<Case> c;
  c.push_back({"normalize<Q1.14>(Vec3<Q1.14>)", "x: all 2^16, 7 (y,z) pairs", [] {
                 return measure_vec<q1_14>(
                     vecs16(), [](Vec3<q1_14> v) { return normalize<q1_14>(v); }, ld_normalize);
               }});
  c.push_back({"normalize<Q1.30>(Vec3<Q1.30>)", "32-bit: 10^6 random + small + edges", [] {
                 return measure_vec<q1_30>(
                     vecs32(1000000), [](Vec3<q1_30> v) { return normalize<q1_30>(v); },
                     ld_normalize);
               }});
  c.push_back({"dot<Q1.14>(Vec3<Q1.14>, unit)", "x: all 2^16, 7 (y,z) pairs", [] {
                 ErrStats s;
                 const Vec3<q1_14> u{q_raw<q1_14>(9459), q_raw<q1_14>(-9459), q_raw<q1_14>(9459)};
                 for (const auto& v : vecs16())
                   s.add(err_lsb(dot<q1_14>(v, u), to_ld(v.x) * to_ld(u.x) +
                                                       to_ld(v.y) * to_ld(u.y) +
                                                       to_ld(v.z) * to_ld(u.z)));
                 return s;
               }});
  c.push_back({"dot<Q1.30>(Vec3<Q1.30>, Vec3<Q1.30>)", "32-bit random + edge pairs", [] {
                 ErrStats s;
                 const auto vs = vecs32(300000);
                 for (std::size_t i = 0; i + 1 < vs.size(); ++i) {
                   const auto &a = vs[i], &b = vs[i + 1];
                   s.add(err_lsb(dot<q1_30>(a, b), to_ld(a.x) * to_ld(b.x) +
                                                       to_ld(a.y) * to_ld(b.y) +
                                                       to_ld(a.z) * to_ld(b.z)));
                 }
                 return s;
               }});
  c.push_back({"cross<Q1.30>(Vec3<Q1.30>, Vec3<Q1.30>)", "32-bit random + edge pairs", [] {
                 ErrStats s;
                 const auto vs = vecs32(300000);
                 for (std::size_t i = 0; i + 1 < vs.size(); ++i) {
                   const auto &a = vs[i], &b = vs[i + 1];
                   const auto r = cross<q1_30>(a, b);
                   s.add(err_lsb(r.x, to_ld(a.y) * to_ld(b.z) - to_ld(a.z) * to_ld(b.y)));
                   s.add(err_lsb(r.y, to_ld(a.z) * to_ld(b.x) - to_ld(a.x) * to_ld(b.z)));
                   s.add(err_lsb(r.z, to_ld(a.x) * to_ld(b.y) - to_ld(a.y) * to_ld(b.x)));
                 }
                 return s;
               }});
  return c;
}

}  // namespace tp::fx::testing
