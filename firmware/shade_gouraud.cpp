#include "firmware/methods.hpp"

namespace tp::fw {

bool GouraudMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  constexpr std::int64_t one = std::int64_t{1} << 30;
  std::int64_t c[3][3];  // [vertex][channel], clamped to [0, 1] in Q.30
  for (int i = 0; i < 3; ++i) {
    const Radiance r = blinn_phong(ctx, tri.v[i].eye, tri.v[i].normal);
    for (int ch = 0; ch < 3; ++ch) c[i][ch] = fx::clamp(r.c[ch], 0, one);
  }
  for (int ch = 0; ch < 3; ++ch) plane_[ch].setup(tri, c[0][ch], c[1][ch], c[2][ch]);
  tri_ = &tri;
  return true;
}

void GouraudMethod::shade_span(const Span& s, Rgb8* out) {
  const Lambdas lam = lambdas_at(*tri_, 16 * std::int64_t{s.x0} + 8, 16 * std::int64_t{s.y} + 8);
  constexpr int f = ScreenPlane::kStepFrac;
  std::int64_t r = plane_[0].at(lam) << f, g = plane_[1].at(lam) << f, b = plane_[2].at(lam) << f;
  const std::int64_t dr = plane_[0].step_x(), dg = plane_[1].step_x(), db = plane_[2].step_x();
  for (std::int32_t x = s.x0; x < s.x1; ++x) {
    *out++ = Rgb8{to_level(r >> f), to_level(g >> f), to_level(b >> f)};
    r += dr;  // Gouraud: one addition per channel per pixel
    g += dg;
    b += db;
  }
}

}  // namespace tp::fw
