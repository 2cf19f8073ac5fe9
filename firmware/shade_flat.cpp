#include "firmware/methods.hpp"
#include "fixedpoint/normalize_fast.hpp"

namespace tp::fw {

bool FlatMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  const Vec3q16 p = eye_centroid(tri);
  const auto nsum = [&](auto get) {
    return std::int64_t{get(tri.v[0]).raw()} + get(tri.v[1]).raw() + get(tri.v[2]).raw();
  };
  const Vec3u n = fx::normalize_fast(nsum([](const ShadeVertex& v) { return v.normal.x; }),
                                     nsum([](const ShadeVertex& v) { return v.normal.y; }),
                                     nsum([](const ShadeVertex& v) { return v.normal.z; }));
  ++ctx.counters->normalizations;
  colour_ = to_rgb8(blinn_phong(ctx, p, n));
  return true;
}

void FlatMethod::shade_span(const Span& s, Rgb8* out) {
  for (std::int32_t x = s.x0; x < s.x1; ++x) *out++ = colour_;
}

LinearColours FlatMethod::linear_span(const Span& s) {
  static_cast<void>(s);
  constexpr int k = LinearColours::kShift;
  return LinearColours{
      {std::int64_t{colour_.r} << k, std::int64_t{colour_.g} << k, std::int64_t{colour_.b} << k},
      {0, 0, 0}};
}

}  // namespace tp::fw
