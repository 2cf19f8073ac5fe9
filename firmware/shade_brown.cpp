// Brown's Bézier-triangle highlights (methods.hpp, 7): setup builds each light's Bézier triangle
// of N·H and culls it by its convex hull; the pixel loop adds Gouraud's diffuse-and-ambient
// colour and, per light left, the smoothstep of the Bézier triangle at the pixel's
// perspective-correct barycentrics.
#include "firmware/methods.hpp"
#include "firmware/six_points.hpp"

namespace tp::fw {
namespace {

using Q40 = fx::Q<22, 40, std::int64_t>;
constexpr std::int64_t kOne30 = std::int64_t{1} << 30;

std::int64_t dot30(const Vec3u& a, const Vec3u& b) { return fx::dot<q1_30>(a, b).raw(); }

// The smoothstep's range for exponent n (docs/DECISIONS.md, "Brown"): the least-squares fit
// of s((c − c_lo) / (c_hi − c_lo)) to cos^n over 0..90°, tracked by
//   c_lo = 1 − k_lo(n) / n,  k_lo(n) = 2.2690 − 1.5814 / (n + 0.4243)
//   c_hi = 1 + k_hi(n) / n,  k_hi(n) = 0.5800 − 0.6483 / (n + 0.5240)
// Each gap k / n = (A m − B) / (10^4 n m) with m = 10^4 n + C in integers (the numerators below
// 2^42, the denominators below 2^54 for n <= 10,000), divided once to Q.40.
std::int64_t gap(std::uint32_t exponent, std::int64_t a, std::int64_t b, std::int64_t c) {
  const std::int64_t n = exponent == 0 ? 1 : exponent;
  const std::int64_t m = 10000 * n + c;
  return fx::div<Q40>(fx::int_q::from_raw(a * m - b), fx::int_q::from_raw(10000 * n * m)).raw();
}
std::int64_t lower_gap(std::uint32_t n) { return gap(n, 22690, 158140000, 4243); }
std::int64_t upper_gap(std::uint32_t n) { return gap(n, 5800, 64830000, 5240); }

}  // namespace

BrownMethod::Bezier BrownMethod::control_points(const std::int64_t c[6]) {
  // Brown eq. 12, doubled: 2 C011 = 4 c011 − C020 − C002.
  return Bezier{
      c[0], c[1], c[2], 4 * c[3] - c[0] - c[1], 4 * c[4] - c[1] - c[2], 4 * c[5] - c[2] - c[0]};
}

// Brown eq. 18: (C200 b0 + 2 C110 b1) b0 + (C020 b1 + 2 C011 b2) b1 + (C002 b2 + 2 C101 b0) b2.
// The inner sums are exact in 64 bits (|C| <= 2^31 and |2 C| <= 2^33 for cosines in [-1, 1]:
// below 2^63 with b <= 2^30); the outer products are summed in 128 bits and rounded once.
std::int64_t BrownMethod::evaluate(const Bezier& z, const std::int64_t b[3]) {
  fx::Sum128 sum;
  sum.add_product(z.c200 * b[0] + z.d110 * b[1], b[0]);
  sum.add_product(z.c020 * b[1] + z.d011 * b[2], b[1]);
  sum.add_product(z.c002 * b[2] + z.d101 * b[0], b[2]);
  bool over = false;
  return sum.shifted(60, over);  // |result| <= 3 · 2^30: never over
}

std::int64_t BrownMethod::lower_cosine(std::uint32_t n) {
  return kOne30 - fx::round_shift_right(lower_gap(n), 10);
}
std::int64_t BrownMethod::upper_cosine(std::uint32_t n) {
  return kOne30 + fx::round_shift_right(upper_gap(n), 10);
}

// The material's smoothstep range, and the shading state without the specular term for the
// Gouraud part, when the state changes.
void BrownMethod::refresh_material(const ShadeContext& ctx) {
  if (ctx.revision != 0 && &ctx == ctx_ && ctx.revision == revision_) return;
  ctx_ = &ctx;
  revision_ = ctx.revision;
  diffuse_ctx_ = ctx;
  diffuse_ctx_.material.ks = q1_30::zero();
  const std::uint32_t n = ctx.material.n;
  c_lo_ = lower_cosine(n);
  const std::int64_t range = lower_gap(n) + upper_gap(n);  // c_hi − c_lo, Q.40
  inv_range_ = fx::div<Q40>(Q40::one(), Q40::from_raw(range)).raw();
}

bool BrownMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  refresh_material(ctx);
  diffuse_ctx_.counters = ctx.counters;
  counters_ = ctx.counters;
  gouraud_.setup(tri, diffuse_ctx_);

  bary_.setup(tri);  // Brown eq. 9: perspective-correct barycentrics

  lights_ = 0;
  if (ctx.material.ks.raw() == 0) return true;
  // The six normals: the vertices', and the edge midpoints' (Brown eq. 10).
  const SixPoints six = six_points(tri);
  const Vec3u* normal = six.normal;
  const Vec3q16* point = six.point;
  counters_->normalizations += 3;
  // The eye direction at the six points (one for an eye at infinity).
  Vec3u eye[6];
  for (int k = 0; k < 6; ++k) eye[k] = eye_direction(ctx, point[k]);
  if (ctx.eye == EyeMode::kFinite) counters_->normalizations += 6;

  for (const LightState& l : ctx.lights) {
    if (!contributes(l)) continue;
    // The six cosines N·H, H at each point (Brown: one H where light and eye are at infinity).
    std::int64_t c[6];
    const bool constant = l.type == LightType::kDirectional && ctx.eye == EyeMode::kInfinite;
    const Vec3u h0 = constant ? halfway(l.direction, eye[0]) : Vec3u{};
    for (int k = 0; k < 6; ++k)
      c[k] = dot30(normal[k], constant ? h0 : halfway(light_direction(l, point[k]), eye[k]));
    counters_->normalizations += constant ? 1u : (l.type == LightType::kPoint ? 12u : 6u);
    const Bezier z = control_points(c);
    // Convex-hull culling: the surface lies inside the hull of its control points, so if they
    // are all below c_lo no pixel's cosine reaches it.
    const std::int64_t lo = c_lo_;
    if (cull_ && z.c200 < lo && z.c020 < lo && z.c002 < lo && z.d110 < 2 * lo && z.d011 < 2 * lo &&
        z.d101 < 2 * lo) {
      ++counters_->lights_skipped_triangle;
      continue;
    }
    Highlight& hl = highlight_[lights_++];
    hl.bezier = z;
    for (int ch = 0; ch < 3; ++ch)  // ks Il_c: Q1.30 × Q15.16 -> Q.30 (at most 16)
      hl.weight[ch] = fx::mul_shift_right(ctx.material.ks.raw(), l.color[ch].raw(), 16);
  }
  return true;
}

void BrownMethod::shade_span(const Span& s, Rgb8* out) {
  LinearColours g = gouraud_.linear_span(s);  // diffuse and ambient, as Gouraud
  constexpr int k = LinearColours::kShift;
  const int length = s.x1 - s.x0;
  if (lights_ == 0) {
    for (int x = 0; x < length; ++x) {
      out[x] = Rgb8{static_cast<std::uint8_t>(g.c[0] >> k), static_cast<std::uint8_t>(g.c[1] >> k),
                    static_cast<std::uint8_t>(g.c[2] >> k)};
      for (int ch = 0; ch < 3; ++ch) g.c[ch] += g.dc[ch];
    }
    return;
  }
  bary_.start(s.x0, s.y);
  constexpr std::int64_t kTop = std::int64_t{255} << k;
  for (int x = 0; x < length; ++x) {
    std::int64_t b[3];  // the pixel's barycentrics (Brown eq. 9), Q.30 in [0, 1]
    bary_.next(b);
    std::int64_t acc[3] = {g.c[0], g.c[1], g.c[2]};
    for (int ch = 0; ch < 3; ++ch) g.c[ch] += g.dc[ch];
    for (int j = 0; j < lights_; ++j) {
      const Highlight& hl = highlight_[j];
      const std::int64_t c = evaluate(hl.bezier, b);  // Brown eq. 18
      if (c <= c_lo_) continue;
      // Brown eqs. 13 and 14: t = (c − c_lo) / (c_hi − c_lo), s = t² (3 − 2t).
      std::int64_t t = fx::mul_shift_right(c - c_lo_, inv_range_, 40);  // Q.30
      t = t > kOne30 ? kOne30 : t;
      const std::int64_t t2 = (t * t) >> 30;
      const std::int64_t sm = (t2 * (3 * kOne30 - 2 * t)) >> 36;  // Q.24
      // Brown eq. 15 with g_s = g_da + ks Il: g = g_da + s ks Il, in the colours' units.
      for (int ch = 0; ch < 3; ++ch) acc[ch] += 255 * ((sm * hl.weight[ch]) >> (54 - k));
    }
    out[x] = Rgb8{static_cast<std::uint8_t>((acc[0] > kTop ? kTop : acc[0]) >> k),
                  static_cast<std::uint8_t>((acc[1] > kTop ? kTop : acc[1]) >> k),
                  static_cast<std::uint8_t>((acc[2] > kTop ? kTop : acc[2]) >> k)};
  }
  counters_->specular_evaluations +=
      static_cast<std::uint64_t>(length) * static_cast<std::uint64_t>(lights_);
}

}  // namespace tp::fw
