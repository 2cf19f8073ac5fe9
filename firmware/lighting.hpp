// Blinn-Phong in fixed point, per colour channel c (docs/CONVENTIONS.md):
//   I_c = ka O_c + sum_lights Il_c [ kd O_c max(0, N.L) + ks max(0, N.H)^n ],  H = norm(L + V)
// (specular not gated by N.L). Ia = 1. Shared by flat, Gouraud and Phong.
//
// Formats: dot products and powers in q1_30 (each rounded once); the sum over lights in a
// 64-bit Q.30 accumulator: at most 16 lights x intensity 16 x (1 + 1) < 2^10, far inside.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>

#include "firmware/build.hpp"
#include "firmware/method.hpp"
#include "firmware/vecmath.hpp"
#include "fixedpoint/arith.hpp"
#include "fixedpoint/normalize_fast.hpp"

namespace tp::fw {

// The lighting vectors at an eye-space point p, the one copy that Blinn-Phong here and the
// Kuijk-Blake methods' per-vertex directions (kb/) both use, so that they are the same bits.
// Each costs one normalize_fast (sample grade: at most 1.81 LSB per component, where the
// correctly rounded normalize_wide is 0.5 and cost seven times as much: docs/DECISIONS.md,
// "Gouraud in the pixel loop"), except a directional light's L and the eye at infinity.

// Unit vector toward the light from p.
inline Vec3u light_direction(const LightState& l, const Vec3q16& p) {
  if (l.type == LightType::kDirectional) return l.direction;
  return fx::normalize_fast(std::int64_t{l.position.x.raw()} - p.x.raw(),
                            std::int64_t{l.position.y.raw()} - p.y.raw(),
                            std::int64_t{l.position.z.raw()} - p.z.raw());
}

// Unit vector toward the eye from p: toward the origin (finite eye), or +z (eye at infinity).
inline Vec3u eye_direction(const ShadeContext& ctx, const Vec3q16& p) {
  if (ctx.eye == EyeMode::kInfinite) return Vec3u{q1_30::zero(), q1_30::zero(), q1_30::one()};
  return fx::normalize_fast(-std::int64_t{p.x.raw()}, -std::int64_t{p.y.raw()},
                            -std::int64_t{p.z.raw()});
}

// Blinn's halfway vector H = normalize(L + E).
inline Vec3u halfway(const Vec3u& l, const Vec3u& e) {
  return fx::normalize_fast(std::int64_t{l.x.raw()} + e.x.raw(),
                            std::int64_t{l.y.raw()} + e.y.raw(),
                            std::int64_t{l.z.raw()} + e.z.raw());
}

// Where L and E are opposite (a light straight behind the object, seen from an eye at
// infinity), H is undefined and halfway() gives the zero vector, as light_direction() does for a
// point light at the point itself; N·H (N·L) is then 0, as the shared contract takes it
// (docs/CONVENTIONS.md). Kuijk-Blake's methods, which interpolate these vectors angularly between
// the vertices, cannot start from one: its angle reads as 0, a full highlight over the whole
// triangle. They leave the term out of a triangle where its vector is undefined at a vertex:
// whether one of v[0..count) is.
TP_SIZE_OUTLINE inline bool undefined_direction(const Vec3u* v, int count) {
  for (int i = 0; i < count; ++i)
    if (v[i].x.raw() == 0 && v[i].y.raw() == 0 && v[i].z.raw() == 0) return true;
  return false;
}

// A light's L and H at eye-space point p, where the eye's direction is e: the vectors Duff and
// Bishop-Weimer hold constant over a triangle (at its centroid) and the Blinn maps take at each
// point. Adds the unit vectors it forms to normalizations (a point light's L, and H).
struct LightAndHalfway {
  Vec3u l, h;
};
inline LightAndHalfway light_and_halfway(const LightState& light, const Vec3q16& p, const Vec3u& e,
                                         Counters& counters) {
  const Vec3u l = light_direction(light, p);
  counters.normalizations += light.type == LightType::kPoint ? 2u : 1u;
  return LightAndHalfway{l, halfway(l, e)};
}

struct Radiance {
  std::int64_t c[3];  // I_c, Q.30, not yet clamped
};

namespace detail {
// One product of power(): Q1.30 × Q1.30 rounded half up.
inline std::int64_t power_mul(std::int64_t a, std::int64_t b) {
  return (a * b + (std::int64_t{1} << 29)) >> 30;
}
}  // namespace detail

// x^n by repeated squaring, x in [0, 1] (q1_30; every caller clamps, a dot of unit vectors may
// exceed 1 by a few LSB), n >= 1; each product rounded to q1_30, half up. For such x that is the
// rounding of fx::mul_sat (ties away from zero = half up for non-negative values) without its
// saturation, which no product reaches (x^n < 2). Inline: exact Phong and kb-adaptive take it at
// every exact pixel and sample (point_shader.hpp).
//
// The first product of the result, 1·x^(2^k), is exact ((2^30·b + 2^29) >> 30 = b), so it is
// taken as is: the same value with one multiplication and test less.
inline q1_30 power(q1_30 x, std::uint32_t n) {
  if (n == 0) return q1_30::one();
  std::int64_t base = x.raw();
  for (; (n & 1u) == 0; n >>= 1) base = detail::power_mul(base, base);
  std::int64_t result = base;
  for (n >>= 1; n != 0; n >>= 1) {
    base = detail::power_mul(base, base);
    if ((n & 1u) != 0) result = detail::power_mul(result, base);
  }
  return q1_30::from_raw(static_cast<std::int32_t>(result));
}

// power(x, N) with N fixed at compile time: the same products in the same order, unrolled (no
// loop over the exponent's bits). PointShader takes it through unrolled_power's table.
namespace detail {
// Bit 0 of N with base = x^(2^k); kStarted: result already holds a product.
template <std::uint32_t N, bool kStarted>
[[gnu::always_inline]] inline std::int64_t power_steps(std::int64_t base, std::int64_t result) {
  if constexpr ((N & 1u) != 0) result = kStarted ? power_mul(result, base) : base;
  constexpr bool kNext = kStarted || (N & 1u) != 0;
  if constexpr ((N >> 1) == 0) {
    return result;
  } else {
    return power_steps<(N >> 1), kNext>(power_mul(base, base), result);
  }
}
template <std::uint32_t N>
std::int64_t power_unrolled(std::int64_t x) {
  return power_steps<N, false>(x, 0);
}
}  // namespace detail

// The unrolled power for exponents 1..kUnrolledPowers (nullptr above: power() takes them),
// for a caller that takes many powers of one exponent (firmware/point_shader.hpp). Size builds
// have none (firmware/build.hpp): the table's code is their loop's many times over.
inline constexpr std::uint32_t kUnrolledPowers = kSizeBuild ? 0 : 32;
using PowerFn = std::int64_t (*)(std::int64_t);
namespace detail {
template <std::size_t... N>
constexpr std::array<PowerFn, sizeof...(N)> power_table(std::index_sequence<N...>) {
  return {&power_unrolled<N + 1>...};
}
}  // namespace detail
inline PowerFn unrolled_power(std::uint32_t n) {
  if constexpr (kUnrolledPowers == 0) {
    static_cast<void>(n);
    return nullptr;
  } else {
    static constexpr auto kTable = detail::power_table(std::make_index_sequence<kUnrolledPowers>{});
    return n >= 1 && n <= kUnrolledPowers ? kTable[n - 1] : nullptr;
  }
}

// Whether a light adds anything: switched on, and not black. The methods that set up per-light
// terms per triangle leave the others out (they would add zero).
inline bool contributes(const LightState& l) {
  return l.type != LightType::kOff &&
         (l.color[0].raw() != 0 || l.color[1].raw() != 0 || l.color[2].raw() != 0);
}

// Lighting at eye-space point p with unit normal n.
Radiance blinn_phong(const ShadeContext& ctx, const Vec3q16& p, const Vec3u& n);

// The eye-space centroid of a triangle (each coordinate rounded once): where flat evaluates, and
// where Duff takes a point light's L and a finite eye's V.
inline Vec3q16 eye_centroid(const Triangle& tri) {
  const auto mean = [&](auto get) {
    const std::int64_t sum =
        std::int64_t{get(tri.v[0]).raw()} + get(tri.v[1]).raw() + get(tri.v[2]).raw();
    return q15_16::from_raw(static_cast<std::int32_t>(
        fx::div<fx::int_q>(fx::int_q::from_raw(sum), fx::int_q::from_raw(3)).raw()));
  };
  return Vec3q16{mean([](const ShadeVertex& v) { return v.eye.x; }),
                 mean([](const ShadeVertex& v) { return v.eye.y; }),
                 mean([](const ShadeVertex& v) { return v.eye.z; })};
}

// round(255 I) (ties away from zero) of an I already in [0, 1]: what the span loops take where
// their range is known.
inline std::uint8_t to_level_in_range(std::int64_t i_q30) {
  return static_cast<std::uint8_t>((i_q30 * 255 + (std::int64_t{1} << 29)) >> 30);
}
// Clamp to [0, 1], then round(255 I) (ties away from zero).
inline std::uint8_t to_level(std::int64_t i_q30) {
  constexpr std::int64_t one = std::int64_t{1} << 30;
  return to_level_in_range(i_q30 < 0 ? 0 : (i_q30 > one ? one : i_q30));
}
Rgb8 to_rgb8(const Radiance& r);

}  // namespace tp::fw
