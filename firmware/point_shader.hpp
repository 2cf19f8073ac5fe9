// The exact per-pixel evaluation at a point of a triangle: exact Phong's pixels (shade_phong.cpp),
// and kb-adaptive's samples (the values its quadratics are fitted to) and per-pixel path. The same
// Blinn-Phong as firmware/lighting.hpp (specular not gated by N·L, Ia = 1) at the
// perspective-correct point: normal and eye-space position interpolated with hyperbolic
// barycentrics, the normal renormalised, L, the eye direction and H exact there (so that near point
// lights are right), with the sample-grade normalize_fast (2.8·10^-9 per component;
// fixedpoint/normalize_fast.hpp) instead of normalize's four 128-bit Newton steps. The result is
// the 8-bit output level in Q.14 before the output's clamp to [0, 255].
#pragma once

#include <bit>
#include <cstdint>

#include "firmware/build.hpp"
#include "firmware/interp.hpp"
#include "firmware/lighting.hpp"
#include "firmware/method.hpp"
#include "fixedpoint/arith.hpp"
#include "fixedpoint/normalize_fast.hpp"

namespace tp::fw {

// a·b of two vectors of magnitude <= 1 + 2^-28 (Q1.30), rounded half away from zero: the same
// value as fx::dot<q1_30> (the exact sum, |.| < 3·2^60, fits 64 bits; no saturation is possible),
// without its general 128-bit-safe path. Samples take several per light.
inline std::int64_t dot_unit(const Vec3u& a, const Vec3u& b) {
  return fx::round_shift_right(std::int64_t{a.x.raw()} * b.x.raw() +
                                   std::int64_t{a.y.raw()} * b.y.raw() +
                                   std::int64_t{a.z.raw()} * b.z.raw(),
                               30);
}

// a·b in Q1.30 of a in [0, 2) and b in (−2, 2) (Q1.30), rounded half away from zero: fx::mul_sat's
// value where no saturation can occur (|a·b| < 2 here: material weights and cosines).
inline std::int64_t mul_q30(std::int64_t a, std::int64_t b) {
  return fx::round_shift_right(a * b, 30);
}

// A vector cut by `cut` bits to at most 30 bits per component (rounding half up: only its
// direction matters) and the reciprocal root of its squared length; a zero vector keeps
// inv.r == 0.
struct CutVector {
  std::int64_t c[3] = {0, 0, 0};
  fx::RsqrtFast inv{0, 1};  // zero: over_length gives (x·0 + 1) >> 1 = 0
};
// bias: 2^(cut − 1), or 0 for cut 0 (cut_bias; a caller with one cut for many vectors keeps it).
constexpr std::int64_t cut_bias(int cut) { return cut > 0 ? std::int64_t{1} << (cut - 1) : 0; }
inline CutVector cut_vector(const std::int64_t v[3], int cut, std::int64_t bias) {
  CutVector r;
  for (int j = 0; j < 3; ++j) r.c[j] = (v[j] + bias) >> cut;
  const auto s = static_cast<std::uint64_t>(r.c[0] * r.c[0] + r.c[1] * r.c[1] + r.c[2] * r.c[2]);
  if (s != 0) r.inv = fx::rsqrt_fast(s);  // s <= 3·2^60
  return r;
}
inline CutVector cut_vector(const std::int64_t v[3], int cut) {
  return cut_vector(v, cut, cut_bias(cut));
}
// The cut that brings components below 2^bits to at most 30 bits.
constexpr int cut_for(int bits) { return bits > 30 ? bits - 30 : 0; }
// x / |v| in Q1.30 for x in v's units, |x| <= 3·2^30: (x·r) >> shift, rounded (x·r < 2^63).
inline std::int64_t over_length(std::int64_t x, const CutVector& v) {
  return (x * v.inv.r + (std::int64_t{1} << (v.inv.shift - 1))) >> v.inv.shift;
}
// The cosine between a and b, a·b / (|a||b|), in Q1.30 (0 if either is zero).
inline std::int64_t cosine(const CutVector& a, const CutVector& b) {
  const std::int64_t dot = a.c[0] * b.c[0] + a.c[1] * b.c[1] + a.c[2] * b.c[2];  // |.| <= 3·2^60
  return over_length(over_length(fx::round_shift_right(dot, 30), a), b);
}
// The cosine between a and the unit vector u (Q1.30).
inline std::int64_t cosine(const CutVector& a, const Vec3u& u) {
  const std::int64_t dot = a.c[0] * u.x.raw() + a.c[1] * u.y.raw() + a.c[2] * u.z.raw();
  return over_length(fx::round_shift_right(dot, 30), a);
}

class PointShader {
 private:
  // The Blinn-Phong sum at a point: the coloured lights' terms per channel, and for the grey lights
  // (the same intensity I in every channel) the sums of their I·N·L and of their I·(N·H)^n, which
  // take kd·O_c and ks once per point instead of once per light.
  struct Sums {
    std::int64_t grey_ndl = 0, grey_power = 0;  // Q1.30 each, |.| <= 16·16·2^30 = 2^38
    std::int64_t coloured[3] = {0, 0, 0};       // the other lights' terms, Q.30
  };

 public:
  static constexpr int kFrac = 14;  // output: levels, Q.14

  // skipping = false evaluates every light at every point, also where it adds exactly 0.
  void setup(const Triangle& tri, const ShadeContext& ctx, bool skipping = true) {
    tri_ = &tri;
    skipping_ = skipping;
    ctx_ = &ctx;
    q15_16 wmin = tri.v[0].w;
    for (const ShadeVertex& v : tri.v) wmin = v.w < wmin ? v.w : wmin;
    for (int i = 0; i < 3; ++i) r_[i] = fx::div<q1_30>(wmin, tri.v[i].w).raw();
    prepare_lights(ctx, skipping);
    // The stepped per-pixel evaluation (SpanStepper): a triangle small enough that its weights
    // keep 30 bits (area2 < 2^30); r_i·N_i and r_i·P_i are scaled by 2^-bits(area2) so that
    // Σ k_i·(.) stays below 2^61 for the pixels inside (k_i >= 0, Σ k_i = area2), and each point
    // light's r_i·(L − P_i) only as far as keeps its plane below 2^60 inside (prepare_planes).
    // The per-pixel steps dk_i·(.) must fit as well: |dk_i| < 2^bits(area2), which only slivers
    // (long edges around a small area) fail; they keep the per-pixel weights.
    const int scale = fx::bit_width(static_cast<std::uint64_t>(tri.area2));
    const Lambdas dk = lambdas_step_x(tri);
    const auto mag = [](std::int64_t x) { return static_cast<std::uint64_t>(x < 0 ? -x : x); };
    const int step_bits = fx::bit_width(mag(dk.l[0]) | mag(dk.l[1]) | mag(dk.l[2]));
    steppable_ = tri.area2 < (std::int64_t{1} << 30) && step_bits <= scale;
    planes_ready_ = false;  // formed by the first span_stepper: a sampled triangle needs none
  }

 private:
  // The material's and the lights' part of setup: the same for every triangle of a draw, so it is
  // kept while the context and its revision are (ShadeContext::revision; revision 0, a context
  // that never counted its changes, is taken afresh every time).
  void prepare_lights(const ShadeContext& ctx, bool skipping) {
    if (ctx.revision != 0 && &ctx == lights_ctx_ && ctx.revision == lights_revision_ &&
        skipping == lights_skipping_)
      return;
    lights_ctx_ = &ctx;
    lights_revision_ = ctx.revision;
    lights_skipping_ = skipping;
    const MaterialCmd& m = ctx.material;
    for (int c = 0; c < 3; ++c) {
      ambient_[c] = fx::mul_sat<q1_30>(m.ka, m.color[c]).raw();
      diffuse_[c] = fx::mul_sat<q1_30>(m.kd, m.color[c]).raw();
    }
    update_spec_zero(m);
    margin2_ = skipping ? spec_margin2_ : 0;
    lights_ = 0;
    point_lights_ = false;
    std::int64_t grey_total = 0;  // Σ of the grey lights' intensities, Q15.16
    for (std::size_t i = 0; i < kMaxLights; ++i) {
      const LightState& l = ctx.lights[i];
      if (l.type == LightType::kOff) continue;
      const bool dark = l.color[0].raw() == 0 && l.color[1].raw() == 0 && l.color[2].raw() == 0;
      if (skipping && dark) continue;  // adds exactly 0
      grey_[lights_] = l.color[0].raw() == l.color[1].raw() && l.color[1].raw() == l.color[2].raw();
      white_[lights_] = grey_[lights_] && l.color[0].raw() == kUnitIntensity;
      // A directional light seen from an eye at infinity has one H everywhere.
      fixed_h_[lights_] = l.type == LightType::kDirectional && ctx.eye == EyeMode::kInfinite;
      if (fixed_h_[lights_])
        h_[lights_] =
            fx::normalize_fast(std::int64_t{l.direction.x.raw()}, std::int64_t{l.direction.y.raw()},
                               std::int64_t{l.direction.z.raw()} + (std::int64_t{1} << 30));
      point_lights_ = point_lights_ || l.type == LightType::kPoint;
      direction_[lights_] = l.direction;
      if (grey_[lights_]) grey_total += l.color[0].raw();
      light_[lights_++] = &l;
    }
    few_grey_ = grey_total <= 2 * kUnitIntensity;
  }

 public:
  // The per-pixel path along a span: the numerators n = Σ k_i r_i N_i and p = Σ k_i r_i P_i (at
  // the triangle's scale) are linear in screen x and y, so they start each span from the
  // triangle's planes and step along it by additions, exactly, and N·L, N·E, L·E and N·H are
  // cosines between them and the light directions (no unit vector is formed: one reciprocal
  // root per vector, and one for |L + E|). A point light's direction is that of
  // v = Σ k_i r_i (L − P_i), a plane of its own (the point's s·L − s·P without forming s).
  struct SpanStepper {
    std::int64_t n[3] = {0, 0, 0}, p[3] = {0, 0, 0};
  };
  // The point lights' v, by light_[] index (entries of the other lights are not set). Apart from
  // SpanStepper, so that a triangle lit by directional lights alone keeps n and p in registers.
  struct LightStepper {
    std::int64_t v[kMaxLights][3];
  };
  // At the centre of pixel (x, y) of a span. The planes are kept modulo 2^64 (unsigned: their
  // value at the screen's origin may not fit), and the value at a pixel inside the triangle,
  // below 2^61, comes out exact.
  SpanStepper span_stepper(std::int32_t x, std::int32_t y) const {
    if (!planes_ready_) prepare_planes();
    const auto ux = static_cast<std::uint64_t>(static_cast<std::int64_t>(x));
    const auto uy = static_cast<std::uint64_t>(static_cast<std::int64_t>(y));
    SpanStepper st;
    for (int j = 0; j < 3; ++j) {
      st.n[j] = static_cast<std::int64_t>(normal_plane_[0][j] + ux * normal_plane_[1][j] +
                                          uy * normal_plane_[2][j]);
      st.p[j] = static_cast<std::int64_t>(eye_plane_[0][j] + ux * eye_plane_[1][j] +
                                          uy * eye_plane_[2][j]);
    }
    return st;
  }
  // The point lights' v at the same pixel (after span_stepper, which forms the planes).
  void start_lights(LightStepper& ls, std::int32_t x, std::int32_t y) const {
    const auto ux = static_cast<std::uint64_t>(static_cast<std::int64_t>(x));
    const auto uy = static_cast<std::uint64_t>(static_cast<std::int64_t>(y));
    for (int li = 0; li < lights_; ++li) {
      if (light_[li]->type != LightType::kPoint) continue;
      for (int j = 0; j < 3; ++j)
        ls.v[li][j] = static_cast<std::int64_t>(
            light_plane_[li][0][j] + ux * light_plane_[li][1][j] + uy * light_plane_[li][2][j]);
    }
  }

 private:
  // The stepped path's planes and cuts, once per triangle that has per-pixel spans (setup
  // decided steppable_; the values depend on the triangle alone, so when they are formed does
  // not change a bit).
  void prepare_planes() const {
    const Triangle& tri = *tri_;
    const int scale = fx::bit_width(static_cast<std::uint64_t>(tri.area2));
    const auto mag = [](std::int64_t x) { return static_cast<std::uint64_t>(x < 0 ? -x : x); };
    const PlaneBasis basis = plane_basis(tri);
    std::int64_t weighted_normal[3][3], weighted_eye[3][3];  // r_i·N_i, r_i·P_i · 2^-bits(area2)
    std::uint64_t max_normal = 0, max_eye = 0;
    for (int i = 0; i < 3; ++i) {
      const ShadeVertex& v = tri.v[i];
      const std::int64_t n[3] = {v.normal.x.raw(), v.normal.y.raw(), v.normal.z.raw()};
      const std::int64_t e[3] = {v.eye.x.raw(), v.eye.y.raw(), v.eye.z.raw()};
      for (int j = 0; j < 3; ++j) {
        weighted_normal[i][j] = fx::round_shift_right(r_[i] * n[j], scale);
        weighted_eye[i][j] = fx::round_shift_right(r_[i] * e[j], scale);
        max_normal |= mag(weighted_normal[i][j]);
        max_eye |= mag(weighted_eye[i][j]);
      }
    }
    plane_of(basis, weighted_normal, normal_plane_);
    plane_of(basis, weighted_eye, eye_plane_);
    for (int j = 0; j < 3; ++j) {
      normal_step_[j] = static_cast<std::int64_t>(normal_plane_[1][j]);
      eye_step_[j] = static_cast<std::int64_t>(eye_plane_[1][j]);
    }
    // Inside the triangle n and p are convex combinations of area2·(r_i N_i) and area2·(r_i P_i)
    // (k_i >= 0, Σ k_i = area2): every component below 2^(bits(area2) + bits(max)). One cut for
    // the whole triangle brings them to 30 bits, instead of measuring every pixel's.
    normal_cut_ = cut_for(scale + fx::bit_width(max_normal));
    eye_cut_ = cut_for(scale + fx::bit_width(max_eye));
    normal_bias_ = cut_bias(normal_cut_);
    eye_bias_ = cut_bias(eye_cut_);
    // Each point light's v = Σ k_i r_i (L − P_i) (|L − P_i| < 2^32 raw, r_i <= 2^30): the
    // weights r_i (L − P_i) shifted just enough that v stays below 2^60 inside the triangle
    // (Σ k_i = area2 < 2^scale; 2^62 one step past a span's end), so that a light near the
    // triangle, whose weights are small, keeps their every bit. v's length is measured at
    // every pixel: near such a light it is far below its bound.
    for (int li = 0; li < lights_; ++li) {
      const LightState& l = *light_[li];
      if (l.type != LightType::kPoint) continue;
      const std::int64_t lp[3] = {l.position.x.raw(), l.position.y.raw(), l.position.z.raw()};
      std::int64_t w[3][3];
      std::uint64_t max_w = 0;
      for (int i = 0; i < 3; ++i) {
        const ShadeVertex& v = tri.v[i];
        const std::int64_t e[3] = {v.eye.x.raw(), v.eye.y.raw(), v.eye.z.raw()};
        for (int j = 0; j < 3; ++j) {
          w[i][j] = r_[i] * (lp[j] - e[j]);
          max_w |= mag(w[i][j]);
        }
      }
      const int sh = scale + fx::bit_width(max_w) - 60;
      if (sh > 0)
        for (auto& row : w)
          for (std::int64_t& x : row) x = fx::round_shift_right(x, sh);
      plane_of(basis, w, light_plane_[li]);
      for (int j = 0; j < 3; ++j)
        light_step_[li][j] = static_cast<std::int64_t>(light_plane_[li][1][j]);
    }
    planes_ready_ = true;
  }

 public:
  // To the next pixel in x (|n|, |p| and the point lights' |v| stay below 2^62 one pixel past
  // the span's end).
  void step(SpanStepper& st) const {
    TP_UNROLL_XYZ for (int j = 0; j < 3; ++j) {
      st.n[j] += normal_step_[j];
      st.p[j] += eye_step_[j];
    }
  }
  void step(LightStepper& ls) const {
    for (int li = 0; li < lights_; ++li)
      if (light_[li]->type == LightType::kPoint)
        for (int j = 0; j < 3; ++j) ls.v[li][j] += light_step_[li][j];
  }
  // The n pixels of a span from the stepper's: shade_stepped at each, inlined into the loop so
  // that the triangle's state stays in registers (the same values as one call per pixel).
  // kPoint: some light is a point light (ls then holds their v).
  template <bool kPoint>
  void shade_run(SpanStepper st, LightStepper* ls, std::int32_t n, Rgb8* out) const {
    for (std::int32_t x = 0; x < n; ++x, step(st)) {
      out[x] = shade_stepped<kPoint>(st, ls);
      if constexpr (kPoint) step(*ls);
    }
  }
  // The n pixels of row y from x = xa: stepped along the row where the triangle allows it
  // (steppable_: exact integer steps, so a pixel gets the same value whichever run it starts),
  // else the point formed at each pixel. The same bits either way a run is cut.
  void shade_pixels(std::int32_t y, std::int32_t xa, std::int32_t n, Rgb8* out) const {
    // Without point lights the kPoint loop computes the same values; a size build keeps it alone.
    if (!kSizeBuild && steppable_ && !point_lights_) {
      shade_run<false>(span_stepper(xa, y), nullptr, n, out);
      return;
    }
    if (steppable_) {
      const SpanStepper st = span_stepper(xa, y);
      start_lights(light_stepper_, xa, y);
      shade_run<true>(st, &light_stepper_, n, out);
      return;
    }
    Lambdas lam = lambdas_at(*tri_, 16 * std::int64_t{xa} + 8, 16 * std::int64_t{y} + 8);
    const Lambdas step = lambdas_step_x(*tri_);
    for (std::int32_t x = 0; x < n; ++x) {
      std::int64_t sum[3];
      radiance(point(lam.l[0], lam.l[1], lam.l[2]), sum);
      out[x] = Rgb8{output_level(sum[0]), output_level(sum[1]), output_level(sum[2])};
      for (int i = 0; i < 3; ++i) lam.l[i] += step.l[i];
    }
  }
  // The output colour at the stepper's pixel (output_level of each channel's sum).
  template <bool kPoint>
  TP_PIXEL_INLINE Rgb8 shade_stepped(const SpanStepper& st, const LightStepper* ls) const {
    Sums acc;
    const bool finite = ctx_->eye == EyeMode::kFinite;
    const CutVector n = cut_vector(st.n, normal_cut_, normal_bias_);
    CutVector e;  // toward the point from the eye (−E), finite eye only
    if (finite) e = cut_vector(st.p, eye_cut_, eye_bias_);
    const std::int64_t normal_eye = finite ? -cosine(n, e) : over_length(n.c[2], n);  // N·E
    if (!kPoint && finite) {  // directional lights, finite eye: the common case, its loop lean
      for (int li = 0; li < lights_; ++li) {
        const Vec3u& d = direction_[li];
        const std::int64_t normal_light = cosine(n, d);
        const std::int64_t ndh = specular_cosine(normal_light + normal_eye, -cosine(e, d));
        add_light(li, normal_light > 0 ? normal_light : 0, ndh, acc);
      }
    } else {
      shade_lights<kPoint>(n, e, normal_eye, ls, acc);
    }
    std::int64_t sum[3];
    totals(acc, sum);
    return Rgb8{output_level(sum[0]), output_level(sum[1]), output_level(sum[2])};
  }
  // shade_stepped's lights in general: point lights (kPoint), or the eye at infinity.
  template <bool kPoint>
  TP_PIXEL_INLINE void shade_lights(const CutVector& n, const CutVector& e, std::int64_t normal_eye,
                                    const LightStepper* ls, Sums& acc) const {
    const bool finite = ctx_->eye == EyeMode::kFinite;
    for (int li = 0; li < lights_; ++li) {
      const LightState& l = *light_[li];
      std::int64_t normal_light = 0, ndh = 0;
      if (kPoint && l.type == LightType::kPoint) {
        const std::int64_t* v = ls->v[li];
        const auto mag = [](std::int64_t x) { return static_cast<std::uint64_t>(x < 0 ? -x : x); };
        const CutVector lv =
            cut_vector(v, cut_for(fx::bit_width(mag(v[0]) | mag(v[1]) | mag(v[2]))));
        normal_light = cosine(n, lv);
        const std::int64_t light_eye = finite ? -cosine(e, lv) : over_length(lv.c[2], lv);
        ndh = specular_cosine(normal_light + normal_eye, light_eye);
      } else {
        normal_light = cosine(n, l.direction);
        if (fixed_h_[li]) {
          const std::int64_t d = cosine(n, h_[li]);
          ndh = d > 0 ? d : 0;
        } else {
          const std::int64_t light_eye = finite ? -cosine(e, l.direction) : l.direction.z.raw();
          ndh = specular_cosine(normal_light + normal_eye, light_eye);
        }
      }
      add_light(li, normal_light > 0 ? normal_light : 0, ndh, acc);
    }
  }

  // The geometry at a point: normal, eye direction, and the eye-space position as s·P (p, in
  // the eye coordinates' Q15.16 units times s): the directions at the point depend on P only
  // through P − X for a fixed X, whose direction is that of s·X − p, so no division is needed.
  struct Point {
    Vec3u normal, eye;
    std::int64_t p[3] = {0, 0, 0};
    std::int64_t s = 0;           // the scale of p, < 2^30
    std::int64_t normal_eye = 0;  // N·E, Q1.30
    bool inside = false;
  };

  // The point whose screen-space barycentric weights are k0 : k1 : k2 (any common scale, each
  // >= 0 and < 2^62, sum > 0).
  Point point(std::int64_t k0, std::int64_t k1, std::int64_t k2) const {
    k0 = k0 < 0 ? 0 : k0;  // on an edge the exact weight is 0; never below
    k1 = k1 < 0 ? 0 : k1;
    k2 = k2 < 0 ? 0 : k2;
    const int sh = shift_for(k0 | k1 | k2);
    std::int64_t mu[3] = {(k0 >> sh) * r_[0], (k1 >> sh) * r_[1], (k2 >> sh) * r_[2]};
    return point_of(mu);
  }

  // The point of edge (a, b) with screen-space weights ka : kb (0 <= k <= 2^20): weighted by
  // ka·w_b : kb·w_a, the exact integers of the hyperbolic interpolation, so that the result
  // depends on the edge alone — the same bits from either triangle of the edge, in either order.
  Point edge_point(int a, int b, std::int64_t ka, std::int64_t kb) const {
    std::int64_t mu[3] = {0, 0, 0};
    mu[a] = ka * tri_->v[b].w.raw();
    mu[b] = kb * tri_->v[a].w.raw();
    return point_of(mu);
  }

 private:
  // The point with hyperbolic weights mu (each >= 0, sum < 2^62). The weights are brought to a
  // sum in [2^29, 2^30) by a shift alone (exact when shifted up, 2^-29 relative when down): N,
  // the eye direction and L are directions of sums weighted by them, whatever their scale, so
  // the barycentrics are never divided out.
  Point point_of(std::int64_t mu[3]) const {
    const Triangle& t = *tri_;
    Point pt;
    std::int64_t sum = mu[0] + mu[1] + mu[2];
    if (sum == 0) return pt;  // not inside the triangle
    const int sh = fx::bit_width(static_cast<std::uint64_t>(sum)) - 30;
    for (int i = 0; i < 3; ++i) mu[i] = sh > 0 ? mu[i] >> sh : mu[i] << -sh;
    pt.s = mu[0] + mu[1] + mu[2];
    // n: |mu|·2^30 <= 2^60; p: |mu|·2^31 <= 2^61.
    std::int64_t n[3] = {0, 0, 0};
    for (int i = 0; i < 3; ++i) {
      n[0] += mu[i] * t.v[i].normal.x.raw();
      n[1] += mu[i] * t.v[i].normal.y.raw();
      n[2] += mu[i] * t.v[i].normal.z.raw();
      pt.p[0] += mu[i] * t.v[i].eye.x.raw();
      pt.p[1] += mu[i] * t.v[i].eye.y.raw();
      pt.p[2] += mu[i] * t.v[i].eye.z.raw();
    }
    pt.normal = fx::normalize_fast(n[0], n[1], n[2]);
    if (ctx_->eye == EyeMode::kFinite) {
      pt.eye = fx::normalize_fast(-pt.p[0], -pt.p[1], -pt.p[2]);
      pt.normal_eye = dot_unit(pt.normal, pt.eye);
    } else {
      pt.eye = Vec3u{q1_30::zero(), q1_30::zero(), q1_30::one()};
      pt.normal_eye = pt.normal.z.raw();
    }
    pt.inside = true;
    return pt;
  }

 public:
  int lights() const { return lights_; }
  bool point_lights() const { return point_lights_; }
  const LightState& light(int i) const { return *light_[i]; }

  // L toward light i from the point, and the halfway vector H = normalize(L + E).
  Vec3u light_direction(const Point& pt, int i) const {
    const LightState& l = *light_[i];
    if (l.type != LightType::kPoint) return l.direction;
    // s·L_pos − s·P: |.| < 2^31·2^30 + 2^61 = 2^62.
    return fx::normalize_fast(l.position.x.raw() * pt.s - pt.p[0],
                              l.position.y.raw() * pt.s - pt.p[1],
                              l.position.z.raw() * pt.s - pt.p[2]);
  }
  Vec3u halfway(const Point& pt, int i, const Vec3u& lv) const {
    return fixed_h_[i] ? h_[i] : halfway(pt, lv);
  }
  static Vec3u halfway(const Point& pt, const Vec3u& lv) {
    return fx::normalize_fast(std::int64_t{lv.x.raw()} + pt.eye.x.raw(),
                              std::int64_t{lv.y.raw()} + pt.eye.y.raw(),
                              std::int64_t{lv.z.raw()} + pt.eye.z.raw());
  }
  // N·H (Q1.30, clamped to [0, 1]) without forming H: N·(L + E) / |L + E|, with
  // |L + E|² = 2 + 2 L·E — one scalar reciprocal root instead of a normalised vector. Where L
  // and E are opposite, H is undefined; the vector form gives 0 there, and so does this.
  std::int64_t normal_halfway(const Point& pt, int i, const Vec3u& lv,
                              std::int64_t normal_light) const {
    if (fixed_h_[i]) {
      const std::int64_t d = dot_unit(pt.normal, h_[i]);
      return d > 0 ? d : 0;
    }
    const std::int64_t light_eye =
        ctx_->eye == EyeMode::kFinite ? dot_unit(lv, pt.eye) : lv.z.raw();
    return specular_cosine(normal_light + pt.normal_eye, light_eye);
  }
  // N·H from x = N·(L + E) and L·E (Q1.30): x / √(2 + 2 L·E), clamped to [0, 1] — or 0 where
  // that is certainly below spec_zero_below_ (the power is 0 either way, and add_light needs no
  // more): x² < t²·|L + E|², t = spec_zero_below_ − 8, decides it without the reciprocal root.
  // The computed N·H is within 2^-28 relative (4 units at most) and half a unit of rounding of the
  // true x/|L + E|, so a true value <= t leaves it below spec_zero_below_ (x <= 2^31 + 8 and
  // |L + E|² <= 2^32 + 16 in Q.30: both sides below 2^63). margin2_ is 0 where nothing is skipped.
  // Where L and E are opposite, H is undefined; the vector form gives 0 there, and so does this.
  std::int64_t specular_cosine(std::int64_t x, std::int64_t light_eye) const {
    const std::int64_t length2 = (std::int64_t{2} << 30) + 2 * light_eye;  // |L + E|², Q.30
    if (length2 <= 0 || x <= 0) return 0;
    if (static_cast<std::uint64_t>(x) * static_cast<std::uint64_t>(x) <
        static_cast<std::uint64_t>(margin2_) * static_cast<std::uint64_t>(length2))
      return 0;
    // x / √(length2·2^-30) in Q1.30: (x·r) >> shift is x/√length2 in Q1.30, times 2^15.
    const fx::RsqrtFast inv = fx::rsqrt_fast(static_cast<std::uint64_t>(length2));
    const int sh = inv.shift + 15;
    const std::int64_t d = (x * inv.r + (std::int64_t{1} << (sh - 1))) >> sh;
    return d < (std::int64_t{1} << 30) ? d : (std::int64_t{1} << 30);
  }

  // The level (Q.14, before the output clamp) of each channel at the point: out[0..2]. Lights of
  // the `unclamped` mask (bit i: light(i); the terminators of kb-adaptive) have their diffuse
  // left unclamped — N·L may be negative — and their N·L reported, in order, in out[3..] (Q.24).
  void shade(const Point& pt, std::int32_t out[], std::uint32_t unclamped = 0) const {
    std::int64_t sum[3];
    radiance(pt, sum, out + 3, unclamped);
    for (int c = 0; c < 3; ++c) out[c] = level_of(sum[c]);
    if (!pt.inside)
      for (int i = 0; i < std::popcount(unclamped); ++i) out[3 + i] = 0;
  }

 private:
  // The radiance per channel at the point, Q.30 (before any clamp), and the unclamped lights' N·L
  // (Q.24) in nl[0..].
  void radiance(const Point& pt, std::int64_t sum[3], std::int32_t* nl = nullptr,
                std::uint32_t unclamped = 0) const {
    Sums acc;
    int k = 0;
    if (!kSizeBuild && pt.inside && !point_lights_ && ctx_->eye == EyeMode::kFinite) {
      // Directional lights, finite eye (as shade_stepped's lean loop). The two loops repeat the
      // terminator's handling on purpose: one lambda for both cost 16 instructions per pixel on
      // teapot-l8 (its captured state left the registers). A size build keeps the general loop
      // alone: for these lights it computes the same values.
      for (int li = 0; li < lights_; ++li) {
        const Vec3u& d = direction_[li];
        const std::int64_t dot_l = dot_unit(pt.normal, d);
        const bool open = ((unclamped >> li) & 1u) != 0;
        if (open) nl[k++] = static_cast<std::int32_t>(fx::round_shift_right(dot_l, 6));
        const std::int64_t ndl = open || dot_l > 0 ? dot_l : 0;
        add_light(li, ndl, specular_cosine(dot_l + pt.normal_eye, dot_unit(d, pt.eye)), acc);
      }
    } else if (pt.inside) {
      for (int li = 0; li < lights_; ++li) {
        const Vec3u lv = light_direction(pt, li);
        const std::int64_t dot_l = dot_unit(pt.normal, lv);
        const bool open = ((unclamped >> li) & 1u) != 0;
        if (open) nl[k++] = static_cast<std::int32_t>(fx::round_shift_right(dot_l, 6));
        const std::int64_t ndl = open || dot_l > 0 ? dot_l : 0;
        const std::int64_t ndh = normal_halfway(pt, li, lv, dot_l);
        add_light(li, ndl, ndh, acc);
      }
    }
    totals(acc, sum);
  }

  // Channel c: ambient_c + coloured_c + ⌊(kd·O_c·Σ I·N·L + ks·Σ I·(N·H)^n + 2^29) / 2^30⌋, the grey
  // lights rounded once. Where their intensities add up to at most 2 each product is at most about
  // 2^61 and the plain sum fits; above, the sums' whole and fractional parts are multiplied apart
  // (the same value).
  TP_PIXEL_INLINE void totals(const Sums& s, std::int64_t out[3]) const {
    const std::int64_t ks = ctx_->material.ks.raw();
    constexpr std::int64_t half = std::int64_t{1} << 29;
    if (few_grey_) {
      const std::int64_t spec = ks * s.grey_power + half;
      TP_UNROLL_XYZ for (int c = 0; c < 3; ++c) {
        out[c] = ambient_[c] + s.coloured[c] + ((diffuse_[c] * s.grey_ndl + spec) >> 30);
      }
      return;
    }
    constexpr std::int64_t kFraction = (std::int64_t{1} << 30) - 1;
    const std::int64_t ndl_whole = s.grey_ndl >> 30, ndl_fraction = s.grey_ndl & kFraction;
    const std::int64_t spec_whole = ks * (s.grey_power >> 30);
    const std::int64_t spec_fraction = ks * (s.grey_power & kFraction) + half;
    for (int c = 0; c < 3; ++c)
      out[c] = ambient_[c] + s.coloured[c] + diffuse_[c] * ndl_whole + spec_whole +
               ((diffuse_[c] * ndl_fraction + spec_fraction) >> 30);
  }
  // One light's Blinn-Phong term, from max(0, N·L) (or the unclamped N·L of a terminator) and
  // max(0, N·H). Below spec_zero_below_ the power is exactly 0, so it is not taken: the same
  // bits (kNoSkip takes it, and its images are tested to be identical).
  TP_PIXEL_INLINE void add_light(int li, std::int64_t ndl, std::int64_t ndh, Sums& sums) const {
    const bool no_spec = skipping_ && ndh < spec_zero_below_;
    if (no_spec && ndl == 0) return;  // adds exactly 0
    const MaterialCmd& m = ctx_->material;
    const std::int64_t pw = no_spec ? 0
                            : power_fn_ != nullptr
                                ? power_fn_(ndh)
                                : power(q1_30::from_raw(static_cast<std::int32_t>(ndh)), m.n).raw();
    if (white_[li]) {  // I = 1: I·x rounds to x
      sums.grey_ndl += ndl;
      sums.grey_power += pw;
      return;
    }
    const LightState& l = *light_[li];
    if (grey_[li]) {  // I·x, Q1.30 × Q15.16 (|.| < 2^51), rounded to Q1.30
      sums.grey_ndl += fx::round_shift_right(ndl * l.color[0].raw(), 16);
      sums.grey_power += fx::round_shift_right(pw * l.color[0].raw(), 16);
      return;
    }
    const std::int64_t spec = mul_q30(m.ks.raw(), pw);
    for (int c = 0; c < 3; ++c) {
      const std::int64_t term = mul_q30(diffuse_[c], ndl) + spec;
      sums.coloured[c] += fx::round_shift_right(term * l.color[c].raw(), 16);
    }
  }

  // The least N·H (Q1.30) whose power (N·H)^n is not 0: power's roundings are monotone in N·H,
  // so a bisection finds it; kept until the exponent changes. spec_margin2_: t²/2^30 (rounded
  // down) for t = spec_zero_below_ − 8, specular_cosine's bound; 0 where there is none.
  void update_spec_zero(const MaterialCmd& m) {
    if (m.n == spec_zero_n_) return;
    spec_zero_n_ = m.n;
    power_fn_ = unrolled_power(m.n);
    const auto pw = [&](std::int64_t x) {
      return power(q1_30::from_raw(static_cast<std::int32_t>(x)), m.n).raw();
    };
    std::int64_t lo = 0, hi = std::int64_t{1} << 30;  // pw(lo) == 0 < pw(hi), or none is
    spec_margin2_ = 0;
    if (pw(lo) != 0) {  // n = 0: the power is 1 everywhere
      spec_zero_below_ = 0;
      return;
    }
    while (hi - lo > 1) {
      const std::int64_t mid = lo + (hi - lo) / 2;
      (pw(mid) == 0 ? lo : hi) = mid;
    }
    spec_zero_below_ = hi;
    const std::int64_t t = spec_zero_below_ - 8;
    if (t > 0) spec_margin2_ = (t * t) >> 30;
  }

  // The edge functions k_i are exact linear functions of the subpixel position, so every
  // Σ k_i w_i is too: k at the centre of pixel (0, 0), and its changes per pixel in x and per row
  // (16 subpixels).
  struct PlaneBasis {
    std::int64_t k[3][3];  // [origin, per pixel in x, per row][vertex]
  };
  static PlaneBasis plane_basis(const Triangle& tri) {
    const Lambdas origin = lambdas_at(tri, 8, 8);
    const Lambdas dx = lambdas_step_x(tri);
    return PlaneBasis{{{origin.l[0], origin.l[1], origin.l[2]},
                       {dx.l[0], dx.l[1], dx.l[2]},
                       {16 * (std::int64_t{tri.v[2].sx} - tri.v[1].sx),
                        16 * (std::int64_t{tri.v[0].sx} - tri.v[2].sx),
                        16 * (std::int64_t{tri.v[1].sx} - tri.v[0].sx)}}};
  }
  // The plane Σ k_i w_i over the screen of weights w (per vertex, per component): [0] at the
  // centre of pixel (0, 0), [1] per pixel in x, [2] per row, modulo 2^64.
  static void plane_of(const PlaneBasis& b, const std::int64_t w[3][3], std::uint64_t out[3][3]) {
    for (int a = 0; a < 3; ++a)
      for (int j = 0; j < 3; ++j) {
        std::uint64_t sum = 0;
        for (int i = 0; i < 3; ++i)
          sum += static_cast<std::uint64_t>(b.k[a][i]) * static_cast<std::uint64_t>(w[i][j]);
        out[a][j] = sum;
      }
  }

  // Weights are cut to 28 bits so that weight × r (Q1.30) stays below 2^59.
  static int shift_for(std::int64_t bits) {
    const int w = fx::bit_width(static_cast<std::uint64_t>(bits));
    return w > 28 ? w - 28 : 0;
  }
  // Q.30 radiance -> level in Q.14, NOT clamped to [0, 255]: the output clamps per pixel, so
  // that a quadratic fitted to these samples meets no kink where the colour saturates, and the
  // unclamped diffuse of kb-adaptive's terminators may take it below 0. Kept in [−2040, 2040]
  // levels (|g| < 2^25, the bound kb_quadratic.hpp's products assume); past +2040 the output
  // is saturated either way, and kb-adaptive keeps its terminators above −1785 levels.
  // The clamp is counted (Counters::saturations, once per channel of a sample, or of a pixel of
  // a triangle too large to step, where it fires): a saturation, not a proven range.
  std::int32_t level_of(std::int64_t i_q30) const {
    constexpr std::int64_t lo = -(std::int64_t{8} << 30), hi = std::int64_t{8} << 30;
    const std::int64_t v = fx::clamp(i_q30, lo, hi);
    if (v != i_q30) ++ctx_->counters->saturations;
    return static_cast<std::int32_t>(fx::round_shift_right(v * 255, 30 - kFrac));
  }

  // level_of(i) rounded half up to an integer and clamped to [0, 255]: 0 for i <= 0 (a level
  // <= 0), 255 for i >= 2^30 (>= 255), and between them level_of's symmetric rounding is the
  // plain half-up one of a positive value, whose result needs no clamp.
  static std::uint8_t output_level(std::int64_t i_q30) {
    if (i_q30 <= 0) return 0;
    if (i_q30 >= (std::int64_t{1} << 30)) return 255;
    const std::int64_t q14 = (i_q30 * 255 + (std::int64_t{1} << (29 - kFrac))) >> (30 - kFrac);
    return static_cast<std::uint8_t>((q14 + (std::int64_t{1} << (kFrac - 1))) >> kFrac);
  }

  const Triangle* tri_ = nullptr;
  const ShadeContext* ctx_ = nullptr;
  bool skipping_ = true;
  bool steppable_ = false;
  // The stepped path's state, formed on the first span_stepper of a triangle (prepare_planes).
  mutable bool planes_ready_ = false;
  // The planes of n and p over the screen: [0] at the centre of pixel (0, 0), [1] per pixel in
  // x, [2] per row, modulo 2^64; the x steps again as signed values.
  mutable std::uint64_t normal_plane_[3][3] = {}, eye_plane_[3][3] = {};
  mutable std::int64_t normal_step_[3] = {0, 0, 0}, eye_step_[3] = {0, 0, 0};
  mutable int normal_cut_ = 0, eye_cut_ = 0;
  mutable std::int64_t normal_bias_ = 0, eye_bias_ = 0;       // cut_bias of the two cuts
  mutable std::uint64_t light_plane_[kMaxLights][3][3] = {};  // point lights' v (light_[] index)
  mutable std::int64_t light_step_[kMaxLights][3] = {};
  // The point lights' v along the current run: a member, not a local, because its 384 bytes
  // would be the largest frame of a draw on a small part's stack (docs/TARGET.md, "Stack").
  mutable LightStepper light_stepper_{};
  std::int64_t r_[3] = {0, 0, 0};  // w_min / w_i, Q1.30
  std::int64_t ambient_[3] = {0, 0, 0};
  std::int64_t diffuse_[3] = {0, 0, 0};  // kd·O_c, Q1.30
  const LightState* light_[kMaxLights] = {};
  bool fixed_h_[kMaxLights] = {};
  bool grey_[kMaxLights] = {};   // the same intensity in every channel
  bool white_[kMaxLights] = {};  // intensity exactly 1 in every channel
  static constexpr std::int32_t kUnitIntensity = std::int32_t{1} << 16;  // q15_16 one
  std::int64_t spec_zero_below_ = 0;                                     // update_spec_zero
  std::int64_t spec_margin2_ = 0;
  // The context, revision and skipping the lights' part was prepared for (prepare_lights).
  const ShadeContext* lights_ctx_ = nullptr;
  std::uint64_t lights_revision_ = 0;
  bool lights_skipping_ = true;
  PowerFn power_fn_ = nullptr;  // power(·, n) unrolled for this exponent (unrolled_power)
  std::int64_t margin2_ = 0;    // spec_margin2_ where skipping_, else 0 (specular_cosine)
  std::uint32_t spec_zero_n_ = ~std::uint32_t{0};  // the exponent it was found for (none yet)
  Vec3u h_[kMaxLights];
  Vec3u direction_[kMaxLights];  // light_[i]->direction, beside the other per-light values
  int lights_ = 0;
  bool point_lights_ = false;  // some light_[] is a point light
  bool few_grey_ = true;       // the grey lights' intensities add up to at most 2 (totals)
};

}  // namespace tp::fw
