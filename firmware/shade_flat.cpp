#include "firmware/methods.hpp"
#include "fixedpoint/normalize_fast.hpp"

namespace tp::fw {

bool FlatMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  // Centroid of the eye-space triangle; each coordinate sum of three Q15.16 values fits 64 bits.
  const auto mean = [&](auto get) {
    const std::int64_t sum =
        std::int64_t{get(tri.v[0]).raw()} + get(tri.v[1]).raw() + get(tri.v[2]).raw();
    return q15_16::from_raw(static_cast<std::int32_t>(
        fx::div<fx::int_q>(fx::int_q::from_raw(sum), fx::int_q::from_raw(3)).raw()));
  };
  const Vec3q16 p{mean([](const ShadeVertex& v) { return v.eye.x; }),
                  mean([](const ShadeVertex& v) { return v.eye.y; }),
                  mean([](const ShadeVertex& v) { return v.eye.z; })};
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
