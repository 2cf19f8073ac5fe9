// Vlasic's quadratic shading (methods.hpp, 8): setup lights the six points and solves eq. 4.2 per
// channel; the pixel loop evaluates eq. 4.1, forward-differenced where (s, t) are affine in x.
#include "firmware/methods.hpp"
#include "firmware/six_points.hpp"

namespace tp::fw {
namespace {

constexpr std::int64_t kOne40 = std::int64_t{1} << 40;
constexpr int kF = QuadraticMethod::kForwardFrac;

std::int64_t magnitude(std::int64_t v) { return v < 0 ? -v : v; }

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
  // Forward differencing where s and t are affine in x and move at most 1 per pixel (a sliver's
  // spans are a pixel or two long: eq. 4.1 directly there).
  const std::int64_t ds = bary_.dm()[1], dt = bary_.dm()[2];  // Q.40
  forward_ = bary_.affine() && magnitude(ds) <= kOne40 && magnitude(dt) <= kOne40;
  if (forward_) {
    // The second difference per pixel, 2 (C3 ds² + C4 ds dt + C5 dt²), Q.52: each product
    // through Q.50 (|C ds| <= 2^53), so that its error, which adds up k²/2 times over k pixels,
    // stays below 2^-28 of a colour unit over 4096.
    const auto term = [](std::int64_t c, std::int64_t a, std::int64_t b) {
      return fx::mul_shift_right(fx::mul_shift_right(c, a, 20), b, 90 - kF);
    };
    for (int ch = 0; ch < 3; ++ch) {
      const std::int64_t* c = coef_[ch].c;
      d2_[ch] = 2 * (term(c[3], ds, ds) + term(c[4], ds, dt) + term(c[5], dt, dt));
    }
  }
  return true;
}

// The span's first pixel: r by eq. 4.1, and its first difference
// r(s + ds, t + dt) − r(s, t) = (∂r/∂s) ds + (∂r/∂t) dt + d2 / 2, the gradient at Q.40.
void QuadraticMethod::start_forward() {
  const std::int64_t s0 = bary_.m()[1], t0 = bary_.m()[2];  // Q.40
  const std::int64_t ds = bary_.dm()[1], dt = bary_.dm()[2];
  for (int ch = 0; ch < 3; ++ch) {
    const std::int64_t* c = coef_[ch].c;
    const std::int64_t gs =
        (c[1] << 10) + 2 * fx::mul_shift_right(c[3], s0, 30) + fx::mul_shift_right(c[4], t0, 30);
    const std::int64_t gt =
        (c[2] << 10) + fx::mul_shift_right(c[4], s0, 30) + 2 * fx::mul_shift_right(c[5], t0, 30);
    r_[ch] = evaluate(coef_[ch], fx::round_shift_right(s0, 10), fx::round_shift_right(t0, 10))
             << (kF - 30);
    d1_[ch] =
        fx::mul_shift_right(gs, ds, 80 - kF) + fx::mul_shift_right(gt, dt, 80 - kF) + d2_[ch] / 2;
  }
}

void QuadraticMethod::shade_span(const Span& s, Rgb8* out) {
  bary_.start(s.x0, s.y);
  const int length = s.x1 - s.x0;
  if (forward_) {
    start_forward();
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
