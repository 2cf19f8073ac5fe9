// Bishop & Weimer's fast Phong (methods.hpp, 5): the second-order Taylor expansions of Duff's
// N·L/|N| and N·H/|N| about the triangle's centre, forward-differenced along each span, the
// power by table lookup.
#include <bit>

#include "firmware/cosn_bw.hpp"
#include "firmware/methods.hpp"
#include "fixedpoint/divide.hpp"
#include "fixedpoint/sqrt.hpp"

namespace tp::fw {
namespace {

constexpr int kF = BishopWeimerMethod::kCoeffFrac;
constexpr int kS = BishopWeimerMethod::kStateFrac;
using Coeff = fx::Q<22, kF, std::int64_t>;
// Q.30 to Q.kF, by a multiplication (the values may be negative).
constexpr std::int64_t kQ30ToCoeff = std::int64_t{1} << (kF - 30);

std::int64_t clamp_to(std::int64_t v, std::int64_t limit, bool& saturated) {
  if (v > limit || v < -limit) saturated = true;
  return v > limit ? limit : (v < -limit ? -limit : v);
}
// |v| in unsigned arithmetic (defined for every v).
std::uint64_t mag(std::int64_t v) {
  const auto u = static_cast<std::uint64_t>(v);
  return v < 0 ? 0 - u : u;
}

// Products of the coefficients, Q.kF, saturated to ±2^61 (and `saturated` set) where they would
// not fit: a sliver's steps can be huge (the fuzzed command streams make them), and with every
// product within 2^61 the sums of three or four in expand() stay inside 64 bits. Not inlined:
// expand() takes some forty of these 128-bit products per vector and triangle, and each inlined
// copy is ~100 bytes of Cortex-M code (the 64x64-bit product from 32-bit limbs).
[[gnu::noinline]] std::int64_t mul(std::int64_t a, std::int64_t b, bool& saturated) {
  constexpr std::int64_t kLimit = std::int64_t{1} << 61;
  // |a b| >= 2^(width(a) + width(b) - 2): above 2^(63 + kF) the result is at least 2^62, so
  // saturating it is right; below, it is exact in 64 bits and clamped.
  if (std::bit_width(mag(a)) + std::bit_width(mag(b)) > 63 + kF) {
    saturated = true;
    return (a < 0) != (b < 0) ? -kLimit : kLimit;
  }
  return clamp_to(fx::mul_shift_right(a, b, kF), kLimit, saturated);
}
// A dot product of Q.kF vectors, within ±2^61 like the products (three of them sum below
// 2^63; the callers double some).
std::int64_t dot(const std::int64_t a[3], const std::int64_t b[3], bool& saturated) {
  const std::int64_t sum =
      mul(a[0], b[0], saturated) + mul(a[1], b[1], saturated) + mul(a[2], b[2], saturated);
  return clamp_to(sum, std::int64_t{1} << 61, saturated);
}
// |N| at the centre at least 1/4: below, the expansion is meaningless (normals more than 150°
// apart on one triangle) and 1/|N|^5 would leave the coefficients' range.
constexpr std::int64_t kMinCentreSquare = std::int64_t{1} << (kF - 4);
// The coefficients' ranges (Q.kF): the constant and first-order terms up to 2^12 (per pixel),
// the second-order ones up to 2^8 per pixel² (a sub-pixel triangle whose normals turn by a
// radian within it has about 1) — beyond any triangle whose expansion means anything, and small
// enough for the products in expand() and start() to stay inside 64 bits.
constexpr std::int64_t kMaxLinear = std::int64_t{1} << (kF + 12);
constexpr std::int64_t kMaxQuadratic = std::int64_t{1} << (kF + 8);

// c·k for an integer k, saturated to ±2^61 (the span start's terms; |k| < 2^40).
std::int64_t scaled(std::int64_t c, std::int64_t k, bool& saturated) {
  if (std::bit_width(mag(c)) + std::bit_width(mag(k)) > 61) {
    saturated = true;
    return (c < 0) != (k < 0) ? -(std::int64_t{1} << 61) : (std::int64_t{1} << 61);
  }
  return c * k;
}
// a + b for |a|, |b| <= 2^61, kept inside ±2^61.
std::int64_t add_sat(std::int64_t a, std::int64_t b, bool& saturated) {
  return clamp_to(a + b, std::int64_t{1} << 61, saturated);
}

// A light that faces away from all three vertex normals adds nothing anywhere on the triangle:
// N(x, y) is a convex combination of them.
bool faces_away(const Triangle& tri, const Vec3u& d) {
  for (const ShadeVertex& v : tri.v)
    if (fx::dot<q1_30>(v.normal, d).raw() > -BishopWeimerMethod::kAwayMargin) return false;
  return true;
}
// ... and one that lights all three by at least as much lights every point of it.
bool faces_towards(const Triangle& tri, const Vec3u& d) {
  for (const ShadeVertex& v : tri.v)
    if (fx::dot<q1_30>(v.normal, d).raw() < BishopWeimerMethod::kAwayMargin) return false;
  return true;
}

}  // namespace

// Bishop & Weimer's expansion of f = p / sqrt(q), with p = dir·N = p0 + p1 u + p2 v and
// q = |N|² = q0 + q1 u + q2 v + q11 u² + q12 u v + q22 v² (their a..i), derived by
// differentiating f at (0, 0): with r = q0^(-1/2),
//   f     = p0 r
//   f_u   = p1 r − ½ p0 q1 r³
//   f_uu  = −p1 q1 r³ + p0 (¾ q1² r⁵ − q11 r³)
//   f_uv  = −½ (p1 q2 + p2 q1) r³ + p0 (¾ q1 q2 r⁵ − ½ q12 r³)
// and f_v, f_vv by symmetry; T = f + f_u u + f_v v + ½ f_uu u² + f_uv u v + ½ f_vv v². (The
// seed's printed T5 reads "3ig²" where the derivative gives 3cg²: the numerator must scale with
// (a, b, c). tests/firmware/bishop_weimer_test.cpp checks every coefficient against a numerical
// expansion of the exact function.)
BishopWeimerMethod::Taylor BishopWeimerMethod::expand(const VectorField& n,
                                                      const std::int64_t dir[3], bool quadratic,
                                                      bool& saturated) {
  const auto m = [&saturated](std::int64_t a, std::int64_t b) { return mul(a, b, saturated); };
  const std::int64_t p0 = dot(dir, n.c, saturated), p1 = dot(dir, n.a, saturated),
                     p2 = dot(dir, n.b, saturated);
  std::int64_t q0 = dot(n.c, n.c, saturated);
  const std::int64_t q1 = 2 * dot(n.c, n.a, saturated), q2 = 2 * dot(n.c, n.b, saturated);
  const std::int64_t q11 = quadratic ? dot(n.a, n.a, saturated) : 0,
                     q12 = quadratic ? 2 * dot(n.a, n.b, saturated) : 0,
                     q22 = quadratic ? dot(n.b, n.b, saturated) : 0;
  if (q0 < kMinCentreSquare) {
    q0 = kMinCentreSquare;
    saturated = true;
  }
  const std::int64_t r = fx::rsqrt<Coeff>(Coeff::from_raw(q0)).raw();
  const std::int64_t r2 = m(r, r);
  const std::int64_t r3 = m(r2, r);
  const std::int64_t r5 = m(r3, r2);
  Taylor t;
  t.c0 = p0 == 0 ? 0 : m(p0, r);
  t.c1 = m(p1, r) - m(m(p0, q1), r3) / 2;
  t.c2 = m(p2, r) - m(m(p0, q2), r3) / 2;
  t.c0 = clamp_to(t.c0, kMaxLinear, saturated);
  t.c1 = clamp_to(t.c1, kMaxLinear, saturated);
  t.c2 = clamp_to(t.c2, kMaxLinear, saturated);
  if (!quadratic) return t;  // first order only (a steep triangle, setup())
  const std::int64_t f_uu = -m(m(p1, q1), r3) + 3 * m(m(p0, m(q1, q1)), r5) / 4 - m(m(p0, q11), r3);
  const std::int64_t f_vv = -m(m(p2, q2), r3) + 3 * m(m(p0, m(q2, q2)), r5) / 4 - m(m(p0, q22), r3);
  const std::int64_t f_uv = -(m(m(p1, q2), r3) + m(m(p2, q1), r3)) / 2 +
                            3 * m(m(p0, m(q1, q2)), r5) / 4 - m(m(p0, q12), r3) / 2;
  t.c11 = clamp_to(f_uu / 2, kMaxQuadratic, saturated);
  t.c12 = clamp_to(f_uv, kMaxQuadratic, saturated);
  t.c22 = clamp_to(f_vv / 2, kMaxQuadratic, saturated);
  return t;
}

// The same for f = P / sqrt(Q R) with two screen-linear vectors N and D: P = N·D, Q = |N|²,
// R = |D|², each quadratic in (u, v) (the paper's finite-eye a..r, with m = D·D, n = 2 D·E,
// o = E·E as its list must read). Both fields are first scaled to unit length at the centre,
// which leaves f unchanged and makes Q(0, 0) = R(0, 0) = 1; then with S = Q R and w = S^(-1/2):
//   S_u = q1 + r1,  S_uu = 2 (q11 + q1 r1 + r11),  S_uv = q12 + q1 r2 + q2 r1 + r12
//   f = p0,  f_u = p1 − ½ p0 S_u
//   f_uu = 2 p11 − p1 S_u + p0 (¾ S_u² − ½ S_uu)
//   f_uv = p12 − ½ (p1 S_v + p2 S_u) + p0 (¾ S_u S_v − ½ S_uv)
// (and f_v, f_vv by symmetry). With D constant this is expand()'s expansion.
BishopWeimerMethod::Taylor BishopWeimerMethod::expand_pair(const VectorField& n_in,
                                                           const VectorField& d_in, bool quadratic,
                                                           bool& saturated) {
  const auto m = [&saturated](std::int64_t a, std::int64_t b) { return mul(a, b, saturated); };
  const auto d3 = [&saturated](const std::int64_t a[3], const std::int64_t b[3]) {
    return dot(a, b, saturated);
  };
  // A centre shorter than 1/4 (normals more than 150° apart, or a point light nearer the
  // centre than a quarter of the vertices' distance, where no expansion about the centre
  // describes the spot) is taken as 1/4 long, and counted.
  const auto unit = [&](const VectorField& f) {
    std::int64_t q0 = d3(f.c, f.c);
    if (q0 < kMinCentreSquare) {
      q0 = kMinCentreSquare;
      saturated = true;
    }
    const std::int64_t r = fx::rsqrt<Coeff>(Coeff::from_raw(q0)).raw();
    // Components up to 2^8 (a step of 256 centre lengths per pixel; first order only beyond
    // one): the dot products below stay under 2^58 and the sums of the products under 2^63.
    constexpr std::int64_t kLimit = std::int64_t{1} << (kF + 8);
    VectorField u{};
    for (int c = 0; c < 3; ++c) {
      u.c[c] = clamp_to(m(f.c[c], r), kLimit, saturated);
      u.a[c] = clamp_to(m(f.a[c], r), kLimit, saturated);
      u.b[c] = clamp_to(m(f.b[c], r), kLimit, saturated);
    }
    return u;
  };
  const VectorField n = unit(n_in), d = unit(d_in);
  quadratic = quadratic && !steep(d);
  const std::int64_t p0 = d3(n.c, d.c), p1 = d3(n.c, d.a) + d3(n.a, d.c),
                     p2 = d3(n.c, d.b) + d3(n.b, d.c);
  const std::int64_t q1 = 2 * d3(n.c, n.a), q2 = 2 * d3(n.c, n.b);
  const std::int64_t r1 = 2 * d3(d.c, d.a), r2 = 2 * d3(d.c, d.b);
  const std::int64_t su = q1 + r1, sv = q2 + r2;
  Taylor t;
  t.c0 = clamp_to(p0, kMaxLinear, saturated);
  t.c1 = clamp_to(p1 - m(p0, su) / 2, kMaxLinear, saturated);
  t.c2 = clamp_to(p2 - m(p0, sv) / 2, kMaxLinear, saturated);
  if (!quadratic) return t;
  const std::int64_t p11 = d3(n.a, d.a), p12 = d3(n.a, d.b) + d3(n.b, d.a), p22 = d3(n.b, d.b);
  const std::int64_t s_uu = 2 * (d3(n.a, n.a) + m(q1, r1) + d3(d.a, d.a));
  const std::int64_t s_uv = 2 * d3(n.a, n.b) + m(q1, r2) + m(q2, r1) + 2 * d3(d.a, d.b);
  const std::int64_t s_vv = 2 * (d3(n.b, n.b) + m(q2, r2) + d3(d.b, d.b));
  const std::int64_t f_uu = 2 * p11 - m(p1, su) + m(p0, 3 * m(su, su) / 4 - s_uu / 2);
  const std::int64_t f_uv = p12 - (m(p1, sv) + m(p2, su)) / 2 + m(p0, 3 * m(su, sv) / 4 - s_uv / 2);
  const std::int64_t f_vv = 2 * p22 - m(p2, sv) + m(p0, 3 * m(sv, sv) / 4 - s_vv / 2);
  t.c11 = clamp_to(f_uu / 2, kMaxQuadratic, saturated);
  t.c12 = clamp_to(f_uv, kMaxQuadratic, saturated);
  t.c22 = clamp_to(f_vv / 2, kMaxQuadratic, saturated);
  return t;
}

// The exponent table for the material's n (Bishop & Weimer: 1 KiB up to n = 20, 8 KiB up to
// n = 164), filled when the material changes; above 164 there is none (power() per pixel).
void BishopWeimerMethod::refresh_material(const ShadeContext& ctx) {
  if (ctx.revision != 0 && &ctx == ctx_ && ctx.revision == revision_) return;
  ctx_ = &ctx;
  revision_ = ctx.revision;
  const std::uint32_t n = ctx.material.n;
  const int size = n <= cosn::kBwMaxN1K   ? cosn::kBwSize1K
                   : n <= cosn::kBwMaxN8K ? cosn::kBwSize8K
                                          : 0;
  if (n != exponent_ || size != table_size_) {
    exponent_ = n;
    table_size_ = size;
    if (size != 0) cosn::bw_fill(static_cast<int>(n), table_, size);
  }
}

bool BishopWeimerMethod::steep(const VectorField& f) {
  bool steep = false;
  for (int c = 0; c < 3; ++c)
    steep =
        steep || mag(f.a[c]) > (std::uint64_t{1} << kF) || mag(f.b[c]) > (std::uint64_t{1} << kF);
  return steep;
}

BishopWeimerMethod::VectorField BishopWeimerMethod::screen_field(const Triangle& tri,
                                                                 const Lambdas& lam,
                                                                 const std::int64_t v[3][3]) {
  VectorField field{};
  ScreenPlane plane;
  for (int c = 0; c < 3; ++c) {
    plane.setup(tri, v[0][c], v[1][c], v[2][c]);
    constexpr int kStep = ScreenPlane::kStepFrac + 30 - kF;  // Q.46 -> Q.kF
    field.c[c] = plane.at(lam) * kQ30ToCoeff;
    field.a[c] = fx::round_shift_right(plane.step_x(), kStep);
    field.b[c] = fx::round_shift_right(plane.step_y(tri), kStep);
  }
  return field;
}

void BishopWeimerMethod::begin(const Triangle& tri, const ShadeContext& ctx, VectorField& normal,
                               bool& steep_normal, Lambdas& lam) {
  counters_ = ctx.counters;
  refresh_material(ctx);
  const MaterialCmd& m = ctx.material;

  // The expansion pixel: the pixel whose centre is nearest the screen centroid.
  const std::int64_t sx = std::int64_t{tri.v[0].sx} + tri.v[1].sx + tri.v[2].sx;  // 48 × x
  const std::int64_t sy = std::int64_t{tri.v[0].sy} + tri.v[1].sy + tri.v[2].sy;
  xr_ = fx::idiv(sx < 0 ? sx - 47 : sx, 48);  // floor(centroid / 16 px)
  yr_ = fx::idiv(sy < 0 ? sy - 47 : sy, 48);
  // The screen-linear normal there, and its steps per pixel (Q.kF).
  lam = lambdas_at(tri, 16 * xr_ + 8, 16 * yr_ + 8);
  std::int64_t n[3][3];
  for (int i = 0; i < 3; ++i) {
    n[i][0] = tri.v[i].normal.x.raw();
    n[i][1] = tri.v[i].normal.y.raw();
    n[i][2] = tri.v[i].normal.z.raw();
  }
  normal = screen_field(tri, lam, n);
  // A triangle whose normal turns by more than a unit per pixel is less than a pixel across in
  // that direction: its second-order terms would extrapolate the steepest curvature over its
  // pixels (and their products leave 64 bits). It is shaded by the first-order expansion.
  steep_normal = steep(normal);

  for (int c = 0; c < 3; ++c) {
    const std::int64_t a = fx::mul_sat<q1_30>(m.ka, m.color[c]).raw();
    ambient_[c] = a * (std::int64_t{1} << (kS - 30));
    diffuse_[c] = Taylor{};
    diffuse_[c].c0 = a * kQ30ToCoeff;
  }
  lights_ = 0;
  terminators_ = 0;
}

void BishopWeimerMethod::add_diffuse(const Taylor& t, const LightState& l, const MaterialCmd& m,
                                     bool whole) {
  std::int64_t w[3];  // kd O_c Il_c, Q.30 × Q.16
  for (int c = 0; c < 3; ++c)
    w[c] = fx::mul_shift_right(fx::mul_sat<q1_30>(m.kd, m.color[c]).raw(), l.color[c].raw(), 16);
  if (!whole) {  // its own polynomial, clamped at zero per pixel
    terminator_[terminators_] = t;
    for (int c = 0; c < 3; ++c) terminator_weight_[terminators_][c] = w[c];
    ++terminators_;
    return;
  }
  for (int c = 0; c < 3; ++c) {  // into the channels' sum
    Taylor& s = diffuse_[c];
    s.c0 += fx::mul_shift_right(t.c0, w[c], 30);
    s.c1 += fx::mul_shift_right(t.c1, w[c], 30);
    s.c2 += fx::mul_shift_right(t.c2, w[c], 30);
    s.c11 += fx::mul_shift_right(t.c11, w[c], 30);
    s.c12 += fx::mul_shift_right(t.c12, w[c], 30);
    s.c22 += fx::mul_shift_right(t.c22, w[c], 30);
  }
}

void BishopWeimerMethod::add_specular(const Taylor& t, const LightState& l, const MaterialCmd& m) {
  specular_[lights_] = t;
  for (int c = 0; c < 3; ++c) {
    // ks Il_c per unit of what the pixel loop multiplies it by: a table entry (255 for 1.0) in
    // Q.36, or a power in Q.24 with the weight in Q.30.
    const std::int64_t k36 = fx::mul_shift_right(m.ks.raw(), l.color[c].raw(), 10);
    spec_weight_[lights_][c] = table_size_ != 0 ? fx::idiv(k36 + 127, 255) : k36 >> 6;
  }
  ++lights_;
}

void BishopWeimerMethod::finish(bool saturated) {
  // Sixteen lights of intensity up to 16 add into a channel's coefficients: keep the sums in
  // the coefficients' range.
  for (Taylor& s : diffuse_) {
    s.c0 = clamp_to(s.c0, kMaxLinear, saturated);
    s.c1 = clamp_to(s.c1, kMaxLinear, saturated);
    s.c2 = clamp_to(s.c2, kMaxLinear, saturated);
    s.c11 = clamp_to(s.c11, kMaxQuadratic, saturated);
    s.c12 = clamp_to(s.c12, kMaxQuadratic, saturated);
    s.c22 = clamp_to(s.c22, kMaxQuadratic, saturated);
  }
  if (saturated) ++counters_->saturations;
}

bool BishopWeimerMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  VectorField field;
  bool steep_normal = false;
  Lambdas lam;
  begin(tri, ctx, field, steep_normal, lam);
  const MaterialCmd& m = ctx.material;

  // The lights' constant vectors, at the eye-space centroid (Duff's, methods.hpp).
  const Vec3q16 p = eye_centroid(tri);
  const Vec3u eye = eye_direction(ctx, p);
  if (ctx.eye == EyeMode::kFinite) ++counters_->normalizations;
  bool saturated = false;
  for (const LightState& l : ctx.lights) {
    if (!contributes(l)) continue;
    const auto [lv, h] = light_and_halfway(l, p, eye, *counters_);
    // Each term (diffuse, specular) left out is counted, as in the Kuijk-Blake methods.
    const bool diffuse_away = faces_away(tri, lv), specular_away = faces_away(tri, h);
    counters_->lights_skipped_triangle += (diffuse_away ? 1u : 0u) + (specular_away ? 1u : 0u);
    if (!diffuse_away) {
      const std::int64_t d[3] = {lv.x.raw() * kQ30ToCoeff, lv.y.raw() * kQ30ToCoeff,
                                 lv.z.raw() * kQ30ToCoeff};
      add_diffuse(expand(field, d, !steep_normal, saturated), l, m, faces_towards(tri, lv));
    }
    if (!specular_away && m.ks.raw() != 0) {
      const std::int64_t d[3] = {h.x.raw() * kQ30ToCoeff, h.y.raw() * kQ30ToCoeff,
                                 h.z.raw() * kQ30ToCoeff};
      add_specular(expand(field, d, !steep_normal, saturated), l, m);
    }
  }
  finish(saturated);
  return true;
}

// A polynomial at pixel offset (u, v) and its forward differences along x, Q.kS:
// value T(u, v), delta T(u + 1, v) − T(u, v), delta2 the constant second difference 2 c11.
// Bounds for a span of n <= 4096 pixels: |value| <= 2^52 and |delta|, |delta2| at most 2^52
// and such that n |delta| <= 2^58 and n² |delta2| <= 2^59: then every stepped value stays
// below 2^52 + 2^58 + 2^59 < 2^60 and every delta below 2^52 + 2^59 / n.
BishopWeimerMethod::Stepper BishopWeimerMethod::start(const Taylor& t, std::int64_t u,
                                                      std::int64_t v, std::int64_t n,
                                                      bool& saturated) const {
  constexpr int kDown = kF - kS;
  std::int64_t value = t.c0;
  value = add_sat(value, scaled(t.c1, u, saturated), saturated);
  value = add_sat(value, scaled(t.c2, v, saturated), saturated);
  value = add_sat(value, scaled(t.c11, u * u, saturated), saturated);
  value = add_sat(value, scaled(t.c12, u * v, saturated), saturated);
  value = add_sat(value, scaled(t.c22, v * v, saturated), saturated);
  std::int64_t delta = t.c1;
  delta = add_sat(delta, scaled(t.c12, v, saturated), saturated);
  delta = add_sat(delta, scaled(t.c11, 2 * u + 1, saturated), saturated);
  const int bits = static_cast<int>(std::bit_width(static_cast<std::uint64_t>(n)));  // n < 2^bits
  Stepper s;
  s.value = clamp_to(fx::round_shift_right(value, kDown), std::int64_t{1} << 52, saturated);
  const auto limit = [](int e) { return std::int64_t{1} << (e < 52 ? e : 52); };
  s.delta = clamp_to(fx::round_shift_right(delta, kDown), limit(58 - bits), saturated);
  s.delta2 = clamp_to(fx::round_shift_right(2 * t.c11, kDown), limit(59 - 2 * bits), saturated);
  return s;
}

void BishopWeimerMethod::shade_span(const Span& s, Rgb8* out) {
  const std::int64_t u = s.x0 - xr_, v = s.y - yr_, n = s.x1 - s.x0;
  bool saturated = false;
  // The channels' state in locals (the loop stores bytes, which could alias any member).
  Stepper d[3];
  for (int c = 0; c < 3; ++c) d[c] = start(diffuse_[c], u, v, n, saturated);
  for (int j = 0; j < terminators_; ++j)
    terminator_step_[j] = start(terminator_[j], u, v, n, saturated);
  for (int j = 0; j < lights_; ++j) specular_step_[j] = start(specular_[j], u, v, n, saturated);
  if (saturated) ++counters_->saturations;
  constexpr std::int64_t kOne = std::int64_t{1} << kS;
  const std::int64_t a0 = ambient_[0], a1 = ambient_[1], a2 = ambient_[2];
  const std::int64_t last = table_size_ - 1;
  const bool table = table_size_ != 0;
  const int length = s.x1 - s.x0;
  for (int x = 0; x < length; ++x) {
    // The diffuse sum and the ambient (its floor: no light takes light away), two additions
    // per channel.
    std::int64_t acc[3] = {d[0].value < a0 ? a0 : d[0].value, d[1].value < a1 ? a1 : d[1].value,
                           d[2].value < a2 ? a2 : d[2].value};
    for (Stepper& st : d) {
      st.value += st.delta;
      st.delta += st.delta2;
    }
    for (int j = 0; j < terminators_; ++j) {  // max(0, N·L) of the lights crossing the triangle
      Stepper& t = terminator_step_[j];
      if (t.value > 0) {
        // Q.30 weight (<= 16) × N·L in Q.24: below 2^58, then to Q.kS.
        const std::int64_t ndl = (t.value > kOne ? kOne : t.value) >> (kS - 24);
        for (int c = 0; c < 3; ++c) acc[c] += (terminator_weight_[j][c] * ndl) >> (54 - kS);
      }
      t.value += t.delta;
      t.delta += t.delta2;
    }
    for (int j = 0; j < lights_; ++j) {
      Stepper& h = specular_step_[j];
      const std::int64_t ndh = h.value < 0 ? 0 : (h.value > kOne ? kOne : h.value);
      h.value += h.delta;  // two additions per light
      h.delta += h.delta2;
      if (table) {  // Bishop & Weimer's lookup, addressed by N·H scaled to the table
        const std::int64_t entry = table_[(ndh * last + (kOne >> 1)) >> kS];
        for (int c = 0; c < 3; ++c) acc[c] += spec_weight_[j][c] * entry;
      } else {  // above the table's range: the power by repeated squaring, in Q.24
        const std::int64_t p =
            power(q1_30::from_raw(static_cast<std::int32_t>(ndh >> (kS - 30))), exponent_).raw() >>
            6;
        for (int c = 0; c < 3; ++c) acc[c] += (spec_weight_[j][c] * p) >> (54 - kS);
      }
    }
    out[x] = Rgb8{to_level(acc[0] >> (kS - 30)), to_level(acc[1] >> (kS - 30)),
                  to_level(acc[2] >> (kS - 30))};
  }
  counters_->specular_evaluations +=
      static_cast<std::uint64_t>(length) * static_cast<std::uint64_t>(lights_);
}

}  // namespace tp::fw
