#include "firmware/methods.hpp"

namespace tp::fw {

bool PhongMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  point_.setup(tri, ctx);
  counters_ = ctx.counters;
  return true;
}

void PhongMethod::shade_span(const Span& s, Rgb8* out) {
  // Every pixel's value is its own (the row's steps are exact): the visible ones alone.
  const std::int32_t n = s.last - s.first;
  point_.shade_pixels(s.y, s.first, n, out + (s.first - s.x0));  // Blinn-Phong at every pixel
  counters_->lighting_evaluations += static_cast<std::uint64_t>(n);
  counters_->specular_evaluations +=
      static_cast<std::uint64_t>(n) * static_cast<std::uint64_t>(point_.lights());
}

}  // namespace tp::fw
