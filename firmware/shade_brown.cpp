// Brown's Bézier-triangle highlights (methods.hpp, 7): setup builds each light's Bézier triangle
// of N·H and culls it by its convex hull; the pixel loop adds Gouraud's diffuse-and-ambient
// colour and, per light left, the smoothstep of the Bézier triangle at the pixel's
// perspective-correct barycentrics.
#include "firmware/methods.hpp"

namespace tp::fw {
namespace {

using Q40 = fx::Q<22, 40, std::int64_t>;
constexpr std::int64_t kOne30 = std::int64_t{1} << 30;

std::int64_t dot30(const Vec3u& a, const Vec3u& b) { return fx::dot<q1_30>(a, b).raw(); }

Vec3u unit_sum(const Vec3u& a, const Vec3u& b) {  // normalize(a + b); zero if they cancel
  return fx::normalize_fast(std::int64_t{a.x.raw()} + b.x.raw(),
                            std::int64_t{a.y.raw()} + b.y.raw(),
                            std::int64_t{a.z.raw()} + b.z.raw());
}

Vec3q16 midpoint(const Vec3q16& a, const Vec3q16& b) {  // rounded toward -inf: any one rule
  const auto mid = [](q15_16 p, q15_16 q) {
    return q15_16::from_raw(
        static_cast<std::int32_t>((std::int64_t{p.raw()} + std::int64_t{q.raw()}) >> 1));
  };
  return Vec3q16{mid(a.x, b.x), mid(a.y, b.y), mid(a.z, b.z)};
}

// The six points of the Bézier triangle: vertices 0, 1, 2, then the midpoints of edges 0-1, 1-2
// and 2-0 (Brown's N110, N011, N101 and their eye-space positions).
constexpr int kEdge[3][2] = {{0, 1}, {1, 2}, {2, 0}};

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
  tri_ = &tri;
  gouraud_.setup(tri, diffuse_ctx_);

  // Perspective-correct barycentrics (Brown eq. 9): b_i ∝ λ_i / w_i.
  const q15_16 w0 = tri.v[0].w, w1 = tri.v[1].w, w2 = tri.v[2].w;
  affine_ = w0.raw() == w1.raw() && w0.raw() == w2.raw();
  q15_16 wmin = w0 < w1 ? w0 : w1;
  wmin = w2 < wmin ? w2 : wmin;
  const Lambdas step = lambdas_step_x(tri);
  for (int i = 0; i < 3; ++i) {
    rho_[i] = affine_ ? kOne30 : fx::div<q1_30>(wmin, tri.v[i].w).raw();
    const std::int64_t dl =
        fx::div<Q40>(fx::int_q::from_raw(step.l[i]), fx::int_q::from_raw(tri.area2)).raw();
    dm_[i] = fx::mul_shift_right(dl, rho_[i], 30);
  }

  lights_ = 0;
  if (ctx.material.ks.raw() == 0) return true;
  // The six normals: the vertices', and the edge midpoints' (Brown eq. 10).
  Vec3u normal[6];
  Vec3q16 point[6];
  for (int i = 0; i < 3; ++i) {
    normal[i] = tri.v[i].normal;
    point[i] = tri.v[i].eye;
  }
  for (int e = 0; e < 3; ++e) {
    const ShadeVertex& a = tri.v[kEdge[e][0]];
    const ShadeVertex& b = tri.v[kEdge[e][1]];
    normal[3 + e] = unit_sum(a.normal, b.normal);
    point[3 + e] = midpoint(a.eye, b.eye);
  }
  counters_->normalizations += 3;
  // The eye direction at the six points (one for an eye at infinity).
  Vec3u eye[6];
  for (int k = 0; k < 6; ++k) eye[k] = eye_direction(ctx, point[k]);
  if (ctx.eye == EyeMode::kFinite) counters_->normalizations += 6;

  for (const LightState& l : ctx.lights) {
    if (l.type == LightType::kOff) continue;
    if (l.color[0].raw() == 0 && l.color[1].raw() == 0 && l.color[2].raw() == 0) continue;
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
  // m_i = λ_i ρ_i at the span's first pixel, Q.40.
  const Lambdas lam = lambdas_at(*tri_, 16 * std::int64_t{s.x0} + 8, 16 * std::int64_t{s.y} + 8);
  std::int64_t m[3];
  for (int i = 0; i < 3; ++i) {
    const std::int64_t l =
        fx::div<Q40>(fx::int_q::from_raw(lam.l[i]), fx::int_q::from_raw(tri_->area2)).raw();
    m[i] = fx::mul_shift_right(l, rho_[i], 30);
  }
  constexpr std::int64_t kTop = std::int64_t{255} << k;
  for (int x = 0; x < length; ++x) {
    // The pixel's barycentrics b_i = m_i / Σ m_j (Brown eq. 9), Q.30 in [0, 1].
    std::int64_t b[3];
    if (affine_) {
      for (int i = 0; i < 3; ++i) b[i] = fx::round_shift_right(m[i], 10);
    } else {
      const std::int64_t sum = fx::round_shift_right(m[0] + m[1] + m[2], 10);  // Q.30, > 0
      const std::int64_t inv = ((std::int64_t{1} << 60) + sum / 2) / (sum > 0 ? sum : 1);
      for (int i = 0; i < 3; ++i) b[i] = fx::mul_shift_right(m[i] >> 10, inv, 30);
    }
    for (std::int64_t& v : b) v = v < 0 ? 0 : (v > kOne30 ? kOne30 : v);
    for (int i = 0; i < 3; ++i) m[i] += dm_[i];
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
