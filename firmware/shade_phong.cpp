#include "firmware/methods.hpp"

namespace tp::fw {

bool PhongMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  point_.setup(tri, ctx);
  counters_ = ctx.counters;
  return true;
}

void PhongMethod::shade_span(const Span& s, Rgb8* out) {
  const std::int32_t n = s.x1 - s.x0;
  point_.shade_pixels(s.y, s.x0, n, out);  // Blinn-Phong at every pixel
  counters_->lighting_evaluations += static_cast<std::uint64_t>(n);
}

}  // namespace tp::fw
