#include "firmware/methods.hpp"
#include "firmware/six_points.hpp"

namespace tp::fw {

bool GouraudMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  std::int64_t c[3][3];  // [vertex][channel], clamped to [0, 1] in Q.30
  for (int i = 0; i < 3; ++i) {
    const VertexLevels v = vertex_levels(tri, i, ctx);
    for (int ch = 0; ch < 3; ++ch) c[i][ch] = v.c[ch];
  }
  steps_exact_ = true;
  for (int ch = 0; ch < 3; ++ch) {
    plane_[ch].setup(tri, c[0][ch], c[1][ch], c[2][ch]);
    step_x_[ch] = plane_[ch].step_x();
    step_y_[ch] = plane_[ch].step_y(tri);
    steps_exact_ = steps_exact_ && ScreenPlane::step_exact(step_x_[ch]) &&
                   ScreenPlane::step_exact(step_y_[ch]);
  }
  tri_ = &tri;
  stepping_ = false;
  return true;
}

// The span's colours as level accumulators: level = round(255 v), ties up, is
// (255 v' + 2^45) >> 46 for v' = v in Q.30 with the planes' 16 more fraction bits.
//
// Why no clamp is needed: every vertex channel is inside [0, 1]. The triangle's first span
// starts at the exact interpolation (a convex combination of the vertices', also with at()'s
// lambdas cut to 27 bits), rounded to half a unit; the next spans' starts are stepped from it,
// one row step per row and one x step per pixel the start moves (an unsaturated step is off by at
// most 2^-17 of a unit), and so are the pixels along a span. A triangle's path has fewer than
// 2^15 steps (at most 4096 rows, at most 3 · 4096 pixels of start movement along its two left
// edges and the viewport's edge, 4096 along a span): every pixel's value is within a quarter unit
// more of the exact one, inside [-2, 2^30 + 1] in Q.30 units, so 255 v' + 2^45 is inside
// [0, 2^54) and the level inside [0, 255]. With a saturated step (a sliver, where the steps are
// not the true gradient) every span starts exactly instead.
LinearColours GouraudMethod::linear_span(const Span& s) {
  constexpr int f = ScreenPlane::kStepFrac;
  if (stepping_) {
    const std::int64_t dx = std::int64_t{s.x0} - x_, dy = std::int64_t{s.y} - y_;
    for (int ch = 0; ch < 3; ++ch) start_[ch] += step_y_[ch] * dy + step_x_[ch] * dx;
  } else {
    const Lambdas lam = lambdas_at(*tri_, 16 * std::int64_t{s.x0} + 8, 16 * std::int64_t{s.y} + 8);
    for (int ch = 0; ch < 3; ++ch) start_[ch] = plane_[ch].at(lam) << f;
    stepping_ = steps_exact_;
  }
  x_ = s.x0;
  y_ = s.y;
  constexpr std::int64_t half = std::int64_t{1} << (LinearColours::kShift - 1);
  LinearColours out;
  for (int ch = 0; ch < 3; ++ch) {
    out.c[ch] = 255 * start_[ch] + half;
    out.dc[ch] = 255 * step_x_[ch];
  }
  return out;
}

void GouraudMethod::shade_span(const Span& s, Rgb8* out) {
  LinearColours c = linear_span(s);
  constexpr int k = LinearColours::kShift;
  for (std::int32_t x = s.x0; x < s.x1; ++x) {
    *out++ = Rgb8{static_cast<std::uint8_t>(c.c[0] >> k), static_cast<std::uint8_t>(c.c[1] >> k),
                  static_cast<std::uint8_t>(c.c[2] >> k)};
    for (int ch = 0; ch < 3; ++ch) c.c[ch] += c.dc[ch];  // Gouraud: one addition per channel
  }
}

}  // namespace tp::fw
