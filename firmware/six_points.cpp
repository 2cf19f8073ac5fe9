#include "firmware/six_points.hpp"

#include "fixedpoint/normalize_fast.hpp"

namespace tp::fw {
namespace {

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

}  // namespace

SixPoints six_points(const Triangle& tri) {
  SixPoints p;
  for (int i = 0; i < 3; ++i) {
    p.normal[i] = tri.v[i].normal;
    p.point[i] = tri.v[i].eye;
  }
  for (int e = 0; e < 3; ++e) {
    const ShadeVertex& a = tri.v[kSixEdge[e][0]];
    const ShadeVertex& b = tri.v[kSixEdge[e][1]];
    p.normal[3 + e] = unit_sum(a.normal, b.normal);
    p.point[3 + e] = midpoint(a.eye, b.eye);
  }
  return p;
}

VertexLevels lit_levels(const ShadeContext& ctx, const Vec3q16& point, const Vec3u& normal) {
  constexpr std::int64_t one = std::int64_t{1} << 30;
  const Radiance r = blinn_phong(ctx, point, normal);
  VertexLevels c;
  for (int ch = 0; ch < 3; ++ch) c.c[ch] = static_cast<std::int32_t>(fx::clamp(r.c[ch], 0, one));
  return c;
}

VertexLevels vertex_levels(const Triangle& tri, int i, const ShadeContext& ctx) {
  const ShadeVertex& v = tri.v[i];
  VertexLevels* cached = v.id >= 0 && tri.levels != nullptr ? &tri.levels[v.id] : nullptr;
  if (cached != nullptr && cached->c[0] >= 0) return *cached;
  const VertexLevels c = lit_levels(ctx, v.eye, v.normal);
  if (cached != nullptr) *cached = c;
  return c;
}

void six_levels(const Triangle& tri, const ShadeContext& ctx, VertexLevels out[6]) {
  for (int i = 0; i < 3; ++i) out[i] = vertex_levels(tri, i, ctx);
  const SixPoints p = six_points(tri);
  ctx.counters->normalizations += 3;
  for (int k = 3; k < 6; ++k) out[k] = lit_levels(ctx, p.point[k], p.normal[k]);
}

}  // namespace tp::fw
