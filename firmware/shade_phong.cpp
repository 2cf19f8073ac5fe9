#include "firmware/methods.hpp"
#include "firmware/vecmath.hpp"

namespace tp::fw {

bool PhongMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  tri_ = &tri;
  ctx_ = &ctx;
  bary_.setup(tri);
  step_ = lambdas_step_x(tri);
  return true;
}

void PhongMethod::shade_span(const Span& s, Rgb8* out) {
  const Triangle& t = *tri_;
  Lambdas lam = lambdas_at(t, 16 * std::int64_t{s.x0} + 8, 16 * std::int64_t{s.y} + 8);
  for (std::int32_t x = s.x0; x < s.x1; ++x) {
    q1_30 b[3];
    bary_.at(lam, b);
    // Interpolated normal (unnormalised, Q.60) and position (Q.46), then Phong's renormalise.
    std::int64_t n[3] = {0, 0, 0}, p[3] = {0, 0, 0};
    for (int i = 0; i < 3; ++i) {
      const std::int64_t w = b[i].raw();
      n[0] += w * t.v[i].normal.x.raw();
      n[1] += w * t.v[i].normal.y.raw();
      n[2] += w * t.v[i].normal.z.raw();
      p[0] += w * t.v[i].eye.x.raw();
      p[1] += w * t.v[i].eye.y.raw();
      p[2] += w * t.v[i].eye.z.raw();
    }
    const Vec3u normal = normalize_wide(n[0], n[1], n[2]);
    ++ctx_->counters->normalizations;
    const auto pos = [](std::int64_t v) {
      return q15_16::from_raw(static_cast<std::int32_t>(fx::round_shift_right(v, 30)));
    };
    *out++ = to_rgb8(blinn_phong(*ctx_, Vec3q16{pos(p[0]), pos(p[1]), pos(p[2])}, normal));
    for (int i = 0; i < 3; ++i) lam.l[i] += step_.l[i];
  }
}

}  // namespace tp::fw
