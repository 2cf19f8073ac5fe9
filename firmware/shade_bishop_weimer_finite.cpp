// Bishop & Weimer's finite-eye extension (methods.hpp, 5b): the specular term
// N·H / (|N| |H|) with H varying across the triangle, and a point light's diffuse term
// N·L / (|N| |L|) with L varying, each replaced by its second-order Taylor expansion about the
// triangle's centre (BishopWeimerMethod::expand_pair); the rest, and the pixel loop, are
// bishop-weimer's.

#include "firmware/methods.hpp"
#include "fixedpoint/q.hpp"

namespace tp::fw {
namespace {

constexpr int kF = BishopWeimerMethod::kCoeffFrac;
constexpr std::int64_t kQ30ToCoeff = std::int64_t{1} << (kF - 30);
constexpr std::int64_t kMargin = BishopWeimerMethod::kAwayMargin;

// N(x, y)·D(x, y) = Σ_ij λ_i λ_j N_i·D_j with λ >= 0 inside the triangle (both fields
// interpolate their vertex values with the same weights, D's possibly scaled per vertex by a
// positive length): when every one of the nine products is at most -margin the term is
// negative everywhere on the triangle; when every one is at least +margin, positive everywhere.
// (With D the same at all three vertices: bishop-weimer's test, to the bit.)
bool all_products_below(const Triangle& tri, const Vec3u d[3], std::int64_t bound) {
  for (const ShadeVertex& v : tri.v)
    for (int j = 0; j < 3; ++j)
      if (fx::dot<q1_30>(v.normal, d[j]).raw() > bound) return false;
  return true;
}
bool all_products_above(const Triangle& tri, const Vec3u d[3], std::int64_t bound) {
  for (const ShadeVertex& v : tri.v)
    for (int j = 0; j < 3; ++j)
      if (fx::dot<q1_30>(v.normal, d[j]).raw() < bound) return false;
  return true;
}

bool same(const Vec3u& a, const Vec3u& b) {
  return a.x.raw() == b.x.raw() && a.y.raw() == b.y.raw() && a.z.raw() == b.z.raw();
}

// A unit vector in Q.kF.
void to_coeff(const Vec3u& v, std::int64_t out[3]) {
  out[0] = v.x.raw() * kQ30ToCoeff;
  out[1] = v.y.raw() * kQ30ToCoeff;
  out[2] = v.z.raw() * kQ30ToCoeff;
}

// P_light − P_i at the three vertices, all scaled by one power of two so that the largest
// component has 30 bits (the quotient N·L / (|N| |L|) does not depend on L's scale; the
// vertices' relative lengths are kept, which is what makes the interpolated L point at the
// light).
void light_vectors(const Triangle& tri, const LightState& l, std::int64_t v[3][3]) {
  std::uint64_t largest = 0;
  for (int i = 0; i < 3; ++i) {
    v[i][0] = std::int64_t{l.position.x.raw()} - tri.v[i].eye.x.raw();
    v[i][1] = std::int64_t{l.position.y.raw()} - tri.v[i].eye.y.raw();
    v[i][2] = std::int64_t{l.position.z.raw()} - tri.v[i].eye.z.raw();
    for (int c = 0; c < 3; ++c) {
      const std::uint64_t m = v[i][c] < 0 ? 0 - static_cast<std::uint64_t>(v[i][c])
                                          : static_cast<std::uint64_t>(v[i][c]);
      largest = m > largest ? m : largest;
    }
  }
  // |v| < 2^32 (coordinates below 2^30 raw); the light at a vertex gives a zero vector there.
  const int width = fx::bit_width(largest);
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 3; ++c)
      v[i][c] = width > 30 ? v[i][c] >> (width - 30) : v[i][c] * (std::int64_t{1} << (30 - width));
}

}  // namespace

bool BishopWeimerFiniteMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  VectorField normal;
  bool steep_normal = false;
  Lambdas lam;
  begin(tri, ctx, normal, steep_normal, lam);
  const MaterialCmd& m = ctx.material;
  Counters& counters = *this->counters();

  // The eye vector at each vertex (the paper's E, interpolated through H below).
  Vec3u eye[3];
  for (int i = 0; i < 3; ++i) eye[i] = eye_direction(ctx, tri.v[i].eye);
  if (ctx.eye == EyeMode::kFinite) counters.normalizations += 3;
  bool saturated = false;
  // A term's expansion: of N·D / (|N| |D|) with D interpolated from the vertex vectors v where
  // D varies, else of N·D / |N| with bishop-weimer's constant D (the vertex vectors, all three
  // the same). A triangle on which either field turns by more than a unit per pixel (less than a
  // pixel across, or a sliver whose expansion pixel lies well outside it, where the extrapolated
  // D can shrink to nothing) takes D constant too, in the direction of the vertex vectors' mean
  // (for L, P_light minus the centroid; for H, the mean of the unit vectors): bishop-weimer's
  // approximation, on triangles too small to show another.
  const auto term = [&](bool varies, const std::int64_t v[3][3], const Vec3u& first) {
    if (varies) {
      const VectorField d = screen_field(tri, lam, v);
      if (!steep_normal && !steep(d)) return expand_pair(normal, d, true, saturated);
      ++counters.normalizations;
      const Vec3u mean = fx::normalize_fast(
          v[0][0] + v[1][0] + v[2][0], v[0][1] + v[1][1] + v[2][1], v[0][2] + v[1][2] + v[2][2]);
      std::int64_t dir[3];
      to_coeff(mean, dir);
      return expand(normal, dir, !steep_normal, saturated);
    }
    std::int64_t dir[3];
    to_coeff(first, dir);
    return expand(normal, dir, !steep_normal, saturated);
  };
  for (const LightState& l : ctx.lights) {
    if (!contributes(l)) continue;
    Vec3u lv[3], h[3];
    for (int i = 0; i < 3; ++i) {
      lv[i] = light_direction(l, tri.v[i].eye);
      h[i] = halfway(lv[i], eye[i]);
    }
    counters.normalizations += l.type == LightType::kPoint ? 6u : 3u;
    // Each term (diffuse, specular) left out is counted, as in the Kuijk-Blake methods.
    const bool diffuse_away = all_products_below(tri, lv, -kMargin),
               specular_away = all_products_below(tri, h, -kMargin);
    counters.lights_skipped_triangle += (diffuse_away ? 1u : 0u) + (specular_away ? 1u : 0u);
    if (!diffuse_away) {
      std::int64_t v[3][3];
      if (l.type == LightType::kPoint) light_vectors(tri, l, v);
      add_diffuse(term(l.type == LightType::kPoint, v, lv[0]), l, m,
                  all_products_above(tri, lv, kMargin));
    }
    if (!specular_away && m.ks.raw() != 0) {
      std::int64_t v[3][3];
      for (int i = 0; i < 3; ++i) {
        v[i][0] = h[i].x.raw();
        v[i][1] = h[i].y.raw();
        v[i][2] = h[i].z.raw();
      }
      add_specular(term(!(same(h[0], h[1]) && same(h[0], h[2])), v, h[0]), l, m);
    }
  }
  finish(saturated);
  return true;
}

}  // namespace tp::fw
