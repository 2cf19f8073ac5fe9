// Duff's shading (methods.hpp, 4): Phong's screen-linear normal, the lighting forward-differenced
// as numerators over the root of a quadratic radicand (Bishop & Weimer's statement of Duff 1979).
#include "firmware/methods.hpp"
#include "fixedpoint/divide.hpp"
#include "fixedpoint/sqrt.hpp"

namespace tp::fw {
namespace {

constexpr int kF = DuffMethod::kNormalFrac;
// A light whose numerators are at most this (Q1.30) at all three vertices adds nothing to any
// pixel: N(x, y) is a convex combination of the vertex normals, so N·L and N·H are convex
// combinations of their vertex values, and the stepped normal is off from the exact one by at
// most 2^-17 per component (rounding to kF bits, 4096 steps), far less than this margin.
constexpr std::int64_t kDarkMargin = std::int64_t{1} << 18;  // 2^-12

std::int64_t dot30(const Vec3u& n, const std::int32_t v[3]) {
  return (std::int64_t{n.x.raw()} * v[0] + std::int64_t{n.y.raw()} * v[1] +
          std::int64_t{n.z.raw()} * v[2]) >>
         30;
}
// n·v for the normal or its step n (kF fraction bits) and a light's L or H (Q1.30): a numerator
// or its step, at kF + 30 fraction bits.
std::int64_t numerator(const std::int64_t n[3], const std::int32_t v[3]) {
  return n[0] * v[0] + n[1] * v[1] + n[2] * v[2];
}

}  // namespace

bool DuffMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  tri_ = &tri;
  counters_ = ctx.counters;
  const MaterialCmd& m = ctx.material;
  for (int c = 0; c < 3; ++c) {
    ambient_[c] = fx::mul_sat<q1_30>(m.ka, m.color[c]).raw();
    diffuse_[c] = fx::mul_sat<q1_30>(m.kd, m.color[c]).raw();
  }
  ks_ = m.ks.raw();
  exponent_ = m.n;
  power_ = unrolled_power(m.n);
  normal_[0].setup(tri, tri.v[0].normal.x.raw(), tri.v[1].normal.x.raw(), tri.v[2].normal.x.raw());
  normal_[1].setup(tri, tri.v[0].normal.y.raw(), tri.v[1].normal.y.raw(), tri.v[2].normal.y.raw());
  normal_[2].setup(tri, tri.v[0].normal.z.raw(), tri.v[1].normal.z.raw(), tri.v[2].normal.z.raw());

  // Duff's constants: L and H per triangle, at the eye-space centroid.
  const Vec3q16 p = eye_centroid(tri);
  const Vec3u v = eye_direction(ctx, p);
  if (ctx.eye == EyeMode::kFinite) ++counters_->normalizations;
  lights_ = 0;
  for (const LightState& l : ctx.lights) {
    if (!contributes(l)) continue;
    const auto [lv, h] = light_and_halfway(l, p, v, *counters_);
    LightTerm& t = light_[lights_];
    t.l[0] = lv.x.raw(), t.l[1] = lv.y.raw(), t.l[2] = lv.z.raw();
    t.h[0] = h.x.raw(), t.h[1] = h.y.raw(), t.h[2] = h.z.raw();
    bool dark = true;  // facing away from L and from H at every vertex
    for (const ShadeVertex& sv : tri.v)
      dark = dark && dot30(sv.normal, t.l) <= -kDarkMargin && dot30(sv.normal, t.h) <= -kDarkMargin;
    if (dark) {
      ++counters_->lights_skipped_triangle;
      continue;
    }
    for (int c = 0; c < 3; ++c) t.colour[c] = l.color[c].raw();
    ++lights_;
  }
  return true;
}

// The span's state at its first visible pixel: the normal and its step from the planes at the
// span's start (kF bits), advanced to s.first by exact integer arithmetic — so a pixel's value is
// the same whether its span starts there or further left (early depth).
void DuffMethod::start_span(const Span& s) {
  const Lambdas lam = lambdas_at(*tri_, 16 * std::int64_t{s.x0} + 8, 16 * std::int64_t{s.y} + 8);
  const std::int64_t k = s.first - s.x0;
  std::int64_t n[3], st[3];
  for (int c = 0; c < 3; ++c) {
    st[c] = fx::round_shift_right(normal_[c].step_x(), ScreenPlane::kStepFrac + 30 - kF);
    n[c] = fx::round_shift_right(normal_[c].at(lam), 30 - kF) + k * st[c];
  }
  // The radicand (Duff's dx² + exy + fy² + gx + hy + i along the row) and its differences.
  m_ = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
  dm_ = 0;
  ddm_ = 0;
  for (int c = 0; c < 3; ++c) {
    dm_ += (2 * n[c] + st[c]) * st[c];
    ddm_ += 2 * st[c] * st[c];
  }
  // The numerators (Duff's ax + by + c) of every light, and their steps.
  for (int j = 0; j < lights_; ++j) {
    const LightTerm& t = light_[j];
    Numerators& u = num_[j];
    u.d = numerator(n, t.l);
    u.dd = numerator(st, t.l);
    u.h = numerator(n, t.h);
    u.dh = numerator(st, t.h);
  }
}

void DuffMethod::shade_span(const Span& s, Rgb8* out) {
  start_span(s);
  constexpr std::int64_t one = std::int64_t{1} << 30;
  // A cosine from a numerator (Q.kF+30) and 1/|N| (Q.30): in [0, 1], Q.30. |numerator| <= |N|,
  // so the product stays near 2^60 whatever |N| is.
  const auto cosine = [](std::int64_t numerator, std::int64_t inverse) {
    const std::int64_t c =
        fx::round_shift_right(fx::round_shift_right(numerator, kF) * inverse, 30);
    return c < 0 ? 0 : (c > one ? one : c);
  };
  for (std::int32_t x = s.first;;) {
    // Duff's one square root and one division per pixel: 1/|N| in Q.30 (0 for N = 0, where every
    // numerator is 0 too).
    const std::uint64_t root = fx::isqrt_floor(static_cast<std::uint64_t>(m_));  // |N|, Q.kF
    const std::int64_t inverse =
        root == 0 ? 0 : static_cast<std::int64_t>(fx::udiv(std::uint64_t{1} << (kF + 30), root));
    std::int64_t acc[3] = {ambient_[0], ambient_[1], ambient_[2]};
    for (int j = 0; j < lights_; ++j) {
      const Numerators& u = num_[j];
      const std::int64_t ndl = cosine(u.d, inverse);
      const std::int64_t ndh = cosine(u.h, inverse);
      const std::int64_t spec = fx::round_shift_right(
          ks_ * (power_ != nullptr
                     ? power_(ndh)
                     : power(q1_30::from_raw(static_cast<std::int32_t>(ndh)), exponent_).raw()),
          30);
      for (int c = 0; c < 3; ++c) {
        const std::int64_t term = fx::round_shift_right(diffuse_[c] * ndl, 30) + spec;
        acc[c] += fx::round_shift_right(term * light_[j].colour[c], 16);
      }
    }
    out[x - s.x0] = Rgb8{to_level(acc[0]), to_level(acc[1]), to_level(acc[2])};
    // To the next pixel, if any (past the span's end the differences could leave their range):
    // two additions for the radicand, one per numerator.
    if (++x == s.last) break;
    m_ += dm_;
    dm_ += ddm_;
    for (int j = 0; j < lights_; ++j) {
      num_[j].d += num_[j].dd;
      num_[j].h += num_[j].dh;
    }
  }
  const auto n = static_cast<std::uint64_t>(s.last - s.first);
  counters_->lighting_evaluations += n;
  counters_->specular_evaluations += n * static_cast<std::uint64_t>(lights_);
}

}  // namespace tp::fw
