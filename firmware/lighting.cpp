#include "firmware/lighting.hpp"

#include "firmware/vecmath.hpp"
#include "fixedpoint/vec3.hpp"

namespace tp::fw {
namespace {

q1_30 mul(q1_30 a, q1_30 b) { return fx::mul_sat<q1_30>(a, b); }
q1_30 clamp_positive(q1_30 x) { return x.raw() < 0 ? q1_30::zero() : x; }

}  // namespace

Radiance blinn_phong(const ShadeContext& ctx, const Vec3q16& p, const Vec3u& n) {
  const MaterialCmd& m = ctx.material;
  Counters& cnt = *ctx.counters;
  ++cnt.lighting_evaluations;
  Radiance out{};
  q1_30 diffuse_colour[3];
  for (int c = 0; c < 3; ++c) {
    out.c[c] = mul(m.ka, m.color[c]).raw();  // ka Ia O_c, Ia = 1
    diffuse_colour[c] = mul(m.kd, m.color[c]);
  }
  // V: toward the eye, at the origin (finite) or along +z (infinite).
  const Vec3u v = eye_direction(ctx, p);
  if (ctx.eye == EyeMode::kFinite) ++cnt.normalizations;
  for (const LightState& l : ctx.lights) {
    if (l.type == LightType::kOff) continue;
    const Vec3u lv = light_direction(l, p);
    if (l.type == LightType::kPoint) ++cnt.normalizations;
    const q1_30 ndl = clamp_positive(fx::dot<q1_30>(n, lv));
    q1_30 spec = q1_30::zero();
    if (m.ks.raw() != 0) {  // a material without specular evaluates none (Brown's vertices)
      const Vec3u h = halfway(lv, v);
      ++cnt.normalizations;
      const q1_30 ndh = clamp_positive(fx::dot<q1_30>(n, h));
      spec = mul(m.ks, power(ndh, m.n));
      ++cnt.specular_evaluations;
    }
    for (int c = 0; c < 3; ++c) {
      // kd O_c (N.L) + ks (N.H)^n <= 2 (q1_30 saturates at 2 - 2^-30), times Il_c <= 16.
      const std::int64_t term = std::int64_t{mul(diffuse_colour[c], ndl).raw()} + spec.raw();
      out.c[c] += fx::round_shift_right(term * l.color[c].raw(), 16);
    }
  }
  return out;
}

Rgb8 to_rgb8(const Radiance& r) {
  return Rgb8{to_level(r.c[0]), to_level(r.c[1]), to_level(r.c[2])};
}

}  // namespace tp::fw
