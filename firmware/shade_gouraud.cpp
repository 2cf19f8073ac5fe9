#include "firmware/methods.hpp"

namespace tp::fw {

namespace {

// The vertex's colour, clamped to [0, 1] in Q.30: lit once per draw for a vertex of the vertex
// buffer (the cache), every time for a vertex that clipping made.
VertexLevels vertex_colour(const Triangle& tri, int i, const ShadeContext& ctx) {
  const ShadeVertex& v = tri.v[i];
  VertexLevels* cached = v.id >= 0 && tri.levels != nullptr ? &tri.levels[v.id] : nullptr;
  if (cached != nullptr && cached->c[0] >= 0) return *cached;
  constexpr std::int64_t one = std::int64_t{1} << 30;
  const Radiance r = blinn_phong(ctx, v.eye, v.normal);
  VertexLevels c;
  for (int ch = 0; ch < 3; ++ch) c.c[ch] = static_cast<std::int32_t>(fx::clamp(r.c[ch], 0, one));
  if (cached != nullptr) *cached = c;
  return c;
}

}  // namespace

bool GouraudMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  std::int64_t c[3][3];  // [vertex][channel], clamped to [0, 1] in Q.30
  bool positive = true;
  for (int i = 0; i < 3; ++i) {
    const VertexLevels v = vertex_colour(tri, i, ctx);
    for (int ch = 0; ch < 3; ++ch) {
      c[i][ch] = v.c[ch];
      positive = positive && v.c[ch] > 0;
    }
  }
  // A span's colours are the exact interpolation (a convex combination of the vertices', also
  // with the lambdas cut to 27 bits: the cut weights still sum to at most 1) off by at most half
  // a unit from at()'s rounding and 4096 · 2^-17 from the steps' (ScreenPlane): so inside
  // [min − 1, max] of the vertex values, [0, 1] wherever every vertex channel is above 0.
  in_range_ = positive;
  for (int ch = 0; ch < 3; ++ch) plane_[ch].setup(tri, c[0][ch], c[1][ch], c[2][ch]);
  tri_ = &tri;
  return true;
}

void GouraudMethod::shade_span(const Span& s, Rgb8* out) {
  const Lambdas lam = lambdas_at(*tri_, 16 * std::int64_t{s.x0} + 8, 16 * std::int64_t{s.y} + 8);
  constexpr int f = ScreenPlane::kStepFrac;
  std::int64_t r = plane_[0].at(lam) << f, g = plane_[1].at(lam) << f, b = plane_[2].at(lam) << f;
  const std::int64_t dr = plane_[0].step_x(), dg = plane_[1].step_x(), db = plane_[2].step_x();
  const std::int32_t n = s.x1 - s.x0;
  // The colours are exactly linear along the span (a start plus k steps): inside [0, 1] at both
  // ends means inside at every pixel, and the pixel loop needs no clamp. (The vertices' colours
  // are clamped, but the planes' rounding may still step a span's end a few units outside.)
  const auto in_range = [&](std::int64_t v, std::int64_t dv) {
    constexpr std::int64_t one = std::int64_t{1} << 30;
    const std::int64_t first = v >> f, last = (v + dv * (n - 1)) >> f;
    return first >= 0 && first <= one && last >= 0 && last <= one;
  };
  if (in_range_ || (in_range(r, dr) && in_range(g, dg) && in_range(b, db))) {
    for (std::int32_t x = 0; x < n; ++x) {
      out[x] =
          Rgb8{to_level_in_range(r >> f), to_level_in_range(g >> f), to_level_in_range(b >> f)};
      r += dr;  // Gouraud: one addition per channel per pixel
      g += dg;
      b += db;
    }
    return;
  }
  for (std::int32_t x = 0; x < n; ++x) {
    out[x] = Rgb8{to_level(r >> f), to_level(g >> f), to_level(b >> f)};
    r += dr;
    g += dg;
    b += db;
  }
}

}  // namespace tp::fw
