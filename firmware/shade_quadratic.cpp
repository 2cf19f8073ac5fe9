// Vlasic's quadratic shading (methods.hpp, 8): setup lights the six points and solves eq. 4.2 per
// channel; the pixel loop evaluates eq. 4.1, forward-differenced where (s, t) are affine in x.
#include "firmware/methods.hpp"
#include "firmware/six_points.hpp"

namespace tp::fw {
namespace {

constexpr int kF = QuadraticMethod::kForwardFrac;

// A forward-differenced value's output level: round(255 r) clamped, from Q.52 (|r| < 2^5).
std::uint8_t forward_level(std::int64_t r) {
  const std::int64_t q = r >> (kF - 32);  // Q.32
  if (q <= 0) return 0;
  if (q >= std::int64_t{1} << 32) return 255;
  return static_cast<std::uint8_t>((255 * q + (std::int64_t{1} << 31)) >> 32);
}

}  // namespace

QuadraticMethod::Coefficients QuadraticMethod::coefficients(const std::int64_t r[6]) {
  return Coefficients{{
      r[0],                                       // Vlasic eq. 4.2
      -3 * r[0] + 4 * r[1] - r[2],                //
      -3 * r[0] - r[4] + 4 * r[5],                //
      2 * r[0] - 4 * r[1] + 2 * r[2],             //
      4 * r[0] - 4 * r[1] + 4 * r[3] - 4 * r[5],  //
      2 * r[0] + 2 * r[4] - 4 * r[5],             //
  }};
}

// Vlasic eq. 4.1 as C0 + s (C1 + C3 s + C4 t) + t (C2 + C5 t), s and t at 28 fraction bits:
// |C| <= 2^33, so C3 s + C4 t < 2^62, the brackets below 2^34 and 2^33, and their products with
// s and t sum below 2^63.
std::int64_t QuadraticMethod::evaluate(const Coefficients& q, std::int64_t s, std::int64_t t) {
  const std::int64_t s28 = s >> 2, t28 = t >> 2;
  const std::int64_t u = q.c[1] + ((q.c[3] * s28 + q.c[4] * t28) >> 28);
  const std::int64_t v = q.c[2] + ((q.c[5] * t28) >> 28);
  return q.c[0] + ((u * s28 + v * t28) >> 28);
}

bool QuadraticMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  VertexLevels lit[6];
  six_levels(tri, ctx, lit);
  for (int ch = 0; ch < 3; ++ch) {
    std::int64_t r[6];
    for (int k = 0; k < 6; ++k) r[k] = lit[kEq42Order[k]].c[ch];
    coef_[ch] = coefficients(r);
  }
  bary_.setup(tri, screen_linear_);
  forward_ = can_forward(bary_);
  if (forward_)
    for (int ch = 0; ch < 3; ++ch) d2_[ch] = second_difference(coef_[ch], bary_);
  return true;
}

void QuadraticMethod::shade_span(const Span& s, Rgb8* out) {
  bary_.start(s.x0, s.y);
  const int length = s.x1 - s.x0;
  if (forward_) {
    for (int ch = 0; ch < 3; ++ch) {
      const Forward f = forward_start(coef_[ch], bary_, d2_[ch]);
      r_[ch] = f.r;
      d1_[ch] = f.d1;
    }
    for (int x = 0; x < length; ++x) {
      out[x] = Rgb8{forward_level(r_[0]), forward_level(r_[1]), forward_level(r_[2])};
      for (int ch = 0; ch < 3; ++ch) {  // two additions per channel
        r_[ch] += d1_[ch];
        d1_[ch] += d2_[ch];
      }
    }
    return;
  }
  for (int x = 0; x < length; ++x) {
    std::int64_t b[3];
    bary_.next(b);  // (s, t) = (b1, b2): vertex 1 at (1, 0), vertex 2 at (0, 1)
    out[x] =
        Rgb8{to_level(evaluate(coef_[0], b[1], b[2])), to_level(evaluate(coef_[1], b[1], b[2])),
             to_level(evaluate(coef_[2], b[1], b[2]))};
  }
}

}  // namespace tp::fw
