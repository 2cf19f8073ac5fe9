// kb-adaptive's geometric tests on the caps of directions over a cell (kb_adaptive.hpp): the
// highlight guard (peak_level) and the terminators (find_terminators). Both bound the normal
// and the light or halfway direction over a cell by the caps of their values at its vertices.
#include "firmware/kb/kb_adaptive.hpp"
#include "fixedpoint/divide.hpp"
#include "fixedpoint/q.hpp"
#include "fixedpoint/sqrt.hpp"

#include <algorithm>
#include <limits>

namespace tp::fw::kb {
namespace {

std::int64_t abs64(std::int64_t v) { return v < 0 ? -v : v; }

// Whether point light l is nearer a cell (vertices at[v], eye space Q15.16) than 17/12 of its
// longest edge, from the nearest vertex (peak_level): 144 d² < 289 D², the differences cut to 26
// bits together so that the products stay within 64 bits.
// size_inf: the longest edge in the max norm, for a first test that settles most lights: with
// |v|∞ <= |v| <= √3 |v|∞, a light 2.5 D∞ from every vertex in the max norm is not near.
bool light_near_cell(const LightState& l, const std::int64_t at[3][3], std::int64_t size_inf) {
  const std::int64_t x[3] = {l.position.x.raw(), l.position.y.raw(), l.position.z.raw()};
  std::int64_t d_inf = std::numeric_limits<std::int64_t>::max();
  for (int v = 0; v < 3; ++v)
    d_inf = std::min(
        d_inf, std::max({abs64(x[0] - at[v][0]), abs64(x[1] - at[v][1]), abs64(x[2] - at[v][2])}));
  if (2 * d_inf >= 5 * size_inf) return false;
  std::int64_t to_light[3][3], edge[3][3], largest = 0;
  for (int v = 0; v < 3; ++v)
    for (int k = 0; k < 3; ++k) {
      to_light[v][k] = x[k] - at[v][k];
      edge[v][k] = at[(v + 1) % 3][k] - at[v][k];
      largest = std::max({largest, abs64(to_light[v][k]), abs64(edge[v][k])});
    }
  const int cut = std::max(0, fx::bit_width(static_cast<std::uint64_t>(largest)) - 26);
  const auto length2 = [cut](const std::int64_t w[3]) {
    const std::int64_t a = w[0] >> cut, b = w[1] >> cut, c = w[2] >> cut;
    return a * a + b * b + c * c;  // < 3·2^52
  };
  std::int64_t d2 = std::numeric_limits<std::int64_t>::max(), size2 = 0;
  for (int v = 0; v < 3; ++v) {
    d2 = std::min(d2, length2(to_light[v]));
    size2 = std::max(size2, length2(edge[v]));
  }
  return 144 * d2 < 289 * size2;
}

// The angle (Q.30 rad) of a cosine c (Q1.30), from t = 1 − c: acos c = √(2t)·(1 + t/12 +
// 3t²/160 + …), the series cut after three terms (low by 0.8 % at 90°, by 21 % at 180°).
std::int64_t angle_of(std::int64_t c) {
  constexpr std::int64_t one = std::int64_t{1} << 30;
  const std::int64_t t = one - (c > one ? one : (c < -one ? -one : c));  // [0, 2], Q.30
  using Q60 = fx::Q<2, 60, std::int64_t>;
  const std::int64_t two_t = 2 * t < 4 * one ? 2 * t : 4 * one - 1;
  const std::int64_t root = fx::sqrt<q1_30>(Q60::from_raw(two_t << 30)).raw();  // √(2t), Q.30
  const std::int64_t series = one + fx::idiv(t, 12) + fx::idiv(3 * ((t * t) >> 30), 160);
  return (root * series) >> 30;
}

// Cap of three unit vectors: its centre and the cosine of its radius (the largest angle from
// the centre to one of them).
struct Cap {
  Vec3u centre;
  std::int64_t cos_radius = 0;
};
Cap cap_of(const Vec3u v[3]) {
  Cap c;
  c.centre = fx::normalize_fast(std::int64_t{v[0].x.raw()} + v[1].x.raw() + v[2].x.raw(),
                                std::int64_t{v[0].y.raw()} + v[1].y.raw() + v[2].y.raw(),
                                std::int64_t{v[0].z.raw()} + v[1].z.raw() + v[2].z.raw());
  c.cos_radius = std::int64_t{1} << 30;
  for (int i = 0; i < 3; ++i) {
    const std::int64_t d = fx::dot<q1_30>(c.centre, v[i]).raw();
    if (d < c.cos_radius) c.cos_radius = d;
  }
  return c;
}

}  // namespace

// The lights whose terminator may cross the triangle: N over it stays in the cap of the vertex
// normals and L in the cap of the vertex L (as in peak_level), so N·L keeps its sign unless the
// caps' centres are within r_N + r_L of 90° (margins for the angle series). Their diffuse is
// sampled unclamped and clamped per pixel (add_leaf); beyond kMaxTerminators, the rest keep the
// clamp in the samples (and the kink: refinement or per-pixel evaluation handles them), and
// every_terminator_ says whether any was left so.
void KbAdaptiveMethod::find_terminators(const Triangle& tri) {
  terminators_ = 0;
  every_terminator_ = true;
  std::uint32_t mask = 0;
  std::int64_t total = 0;
  const MaterialCmd& m = ctx_->material;
  if (m.kd.raw() != 0) {
    const Vec3u normals[3] = {tri.v[0].normal, tri.v[1].normal, tri.v[2].normal};
    const Cap n_cap = cap_of(normals);
    const std::int64_t r_n = angle_of(n_cap.cos_radius);
    for (int li = 0; li < point_.lights(); ++li) {
      const LightState& l = point_.light(li);
      Vec3u lv[3];
      for (int v = 0; v < 3; ++v) {
        const Vec3q16& p = tri.v[v].eye;
        lv[v] = l.type == LightType::kDirectional
                    ? l.direction
                    : fx::normalize_fast(std::int64_t{l.position.x.raw()} - p.x.raw(),
                                         std::int64_t{l.position.y.raw()} - p.y.raw(),
                                         std::int64_t{l.position.z.raw()} - p.z.raw());
      }
      const Cap l_cap = cap_of(lv);
      const std::int64_t spread = (r_n + angle_of(l_cap.cos_radius)) * 17 / 16;
      const std::int64_t d = angle_of(fx::dot<q1_30>(n_cap.centre, l_cap.centre).raw());
      constexpr std::int64_t kLit = 1599875000, kDark = 1771674908;  // 1.49 and 1.65 rad, Q.30
      if (d * 17 / 16 + spread <= kLit || d * 15 / 16 - spread >= kDark) continue;
      if (terminators_ == kMaxTerminators) {  // its kink stays in the samples
        every_terminator_ = false;
        break;
      }
      // Weight of a unit of N·L in channel c: kd·O_c·Il_c, in levels Q.14 (as shade() sums it).
      std::int64_t worst = 0;
      for (int c = 0; c < 3; ++c) {
        const std::int64_t kdo = fx::mul_sat<q1_30>(m.kd, m.color[c]).raw();
        const std::int64_t w = ((kdo * l.color[c].raw()) >> 16) * 255 >> (30 - kSampleFrac);
        term_weight_[terminators_][c] = w;
        worst = w > worst ? w : worst;
      }
      // The unclamped diffuse may take the sampled colour below 0 by the terminators' weights
      // together: they stay within 1785 levels, inside the samples' range
      // (firmware/point_shader.hpp), so that no sample is cut and the per-pixel clamp restores the
      // exact sum.
      if (worst == 0) continue;  // no diffuse: no kink
      if (total + worst > (std::int64_t{1785} << kSampleFrac)) {
        every_terminator_ = false;
        continue;
      }
      total += worst;
      term_worst_[terminators_] = worst;
      mask |= std::uint32_t{1} << li;
      ++terminators_;
    }
  }
  terminator_mask_ = mask;
}

// The level that cell c's descendants must reach for their samples to see every highlight peak
// that may lie on c (c.level itself when none can). N over the cell stays in the cap of the
// normals at its vertices (radius r_N) and H in the cap of its vertices' H (r_H; the central
// projection of a planar patch from a point light or the eye keeps L and E in the caps of their
// vertex values). A specular peak, where N = H, can lie on the cell only if the caps' centres
// are less than r_N + r_H apart; then the sample spacing, about (r_N + r_H) / 2^k in angle, must
// stay within ω = 0.6/√n, where cos^n has fallen to 0.83 of its peak, so that the check points
// see the peak's curvature instead of it passing between samples (docs/KUIJK-BLAKE.md).
// `peaks` (in and out): the lights to test — those whose peak may lie on a cell containing c —
// narrowed to those whose peak may lie on c; the others cannot have one on c's descendants.
//
// The same for a point light's L, whose diffuse N·L = cos θ is the exponent 1 (ω = 0.6): near the
// light L turns fast, |dL/dP| <= 1/|X − P| for the light at X, so between neighbouring samples of
// a cell (a quarter of its size D apart) L turns by at most (D/4) / dist(X, cell), and
// dist(X, cell) >= d − D for d the light's distance to the nearest vertex and D the cell's longest
// edge. That is within ω when d >= (17/12) D. A cell nearer the light is refined, down to
// per-pixel evaluation at the deepest level; a light that is not near c drops out of `peaks`, as
// it need not be tested on c's descendants: there L turns by at most (D/8)/(d − D) <= 0.3 between
// samples. (Without this, a light at 1 % of a perspective triangle's size from its near vertex,
// whose vertex L lie in a small cap, turned L by 30° within a pixel of the vertex: 2 levels off
// the exact evaluation there, one of 300,000 random triangles.)
int KbAdaptiveMethod::peak_level(const Cell& c, std::uint32_t& peaks) {
  const MaterialCmd& m = ctx_->material;
  const bool near_lights = m.kd.raw() != 0 && point_.point_lights();
  if ((m.ks.raw() == 0 && !near_lights) || point_.lights() == 0 || peaks == 0) {
    peaks = 0;
    return c.level;
  }
  if (omega_n_ != m.n) {
    // ω = 0.6 / √n in Q.30: 0.6·2^45 / (√n·2^15).
    omega_n_ = m.n;
    const std::uint64_t root = fx::isqrt_floor(std::uint64_t{m.n} << 30);
    omega_ = static_cast<std::int64_t>(fx::udiv(21110623253299ULL, root == 0 ? 1 : root));
  }
  PointShader::Point pt[3];
  Vec3u normals[3];
  const int corner[3][2] = {{0, 0}, {4, 0}, {0, 4}};
  for (int v = 0; v < 3; ++v) {
    int la = 0, lb = 0;
    cell_point(c, corner[v][0], corner[v][1], la, lb);
    pt[v] = point_.point(kLatticeRes - la - lb, la, lb);
    normals[v] = pt[v].normal;
  }
  const Cap n_cap = cap_of(normals);
  const std::int64_t r_n = angle_of(n_cap.cos_radius);
  int level = c.level;
  std::uint32_t may_peak = 0;
  // The cell's vertices in eye space (Q15.16), its longest edge in the max norm.
  std::int64_t at[3][3] = {};
  std::int64_t size_inf = 0;
  if (near_lights) {
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k) at[v][k] = pt[v].s > 0 ? fx::idiv(pt[v].p[k], pt[v].s) : 0;
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k)
        size_inf = std::max(size_inf, abs64(at[(v + 1) % 3][k] - at[v][k]));
  }
  for (int li = 0; li < point_.lights(); ++li) {
    if (((peaks >> li) & 1u) == 0) continue;
    const LightState& l = point_.light(li);
    if (!contributes(l)) continue;  // (the shader's lights are all on)
    if (near_lights && l.type == LightType::kPoint && light_near_cell(l, at, size_inf)) {
      may_peak |= std::uint32_t{1} << li;  // refine once more, and test again there
      level = std::max(level, c.level + 1);
    }
    if (m.ks.raw() == 0) continue;
    Vec3u h[3];
    for (int v = 0; v < 3; ++v) h[v] = point_.halfway(pt[v], li, point_.light_direction(pt[v], li));
    const Cap h_cap = cap_of(h);
    // Radii over-estimated by 1/16, the centre distance under-estimated by 1/16 (the series).
    const std::int64_t reach = (r_n + angle_of(h_cap.cos_radius)) * 17 / 16;
    const std::int64_t apart = angle_of(fx::dot<q1_30>(n_cap.centre, h_cap.centre).raw()) * 15 / 16;
    if (apart - reach >= omega_) continue;  // no peak on the cell
    may_peak |= std::uint32_t{1} << li;
    int k = c.level;
    while (k <= kMaxLevel && (reach >> (k - c.level)) > omega_) ++k;
    if (k > level) level = k;
  }
  peaks = may_peak;
  return level;
}

}  // namespace tp::fw::kb
