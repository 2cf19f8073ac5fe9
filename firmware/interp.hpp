// Interpolation helpers shared by the methods: screen-linear planes (what the 1980s methods
// assume, docs/CONVENTIONS.md) and perspective-correct (hyperbolic) barycentrics (what the double
// reference uses). Both are exact-integer at their core: the edge functions are exact, and each
// result is rounded once.
#pragma once

#include <cstdint>

#include "firmware/method.hpp"
#include "fixedpoint/arith.hpp"
#include "fixedpoint/divide.hpp"
#include "fixedpoint/q.hpp"
#include "fixedpoint/wide.hpp"

namespace tp::fw {

// Shift that brings a non-negative magnitude below 2^bits.
constexpr int shift_to_fit(std::uint64_t mag, int bits) {
  const int w = fx::bit_width(mag);
  return w > bits ? w - bits : 0;
}

// Edge-function weights of the three vertices at subpixel (px, py): lambda_i * area2, exact.
struct Lambdas {
  std::int64_t l[3];
};
constexpr Lambdas lambdas_at(const Triangle& t, std::int64_t px, std::int64_t py) {
  return Lambdas{{edge_function(t.v[1], t.v[2], px, py), edge_function(t.v[2], t.v[0], px, py),
                  edge_function(t.v[0], t.v[1], px, py)}};
}
// Their exact change per pixel step in x (+16 subpixels): dE_ab/dpx = -(b.sy - a.sy).
constexpr Lambdas lambdas_step_x(const Triangle& t) {
  return Lambdas{{16 * (std::int64_t{t.v[1].sy} - t.v[2].sy),
                  16 * (std::int64_t{t.v[2].sy} - t.v[0].sy),
                  16 * (std::int64_t{t.v[0].sy} - t.v[1].sy)}};
}

// A value given at the three vertices, interpolated linearly in screen space.
// Values: any fixed-point format with |v| <= 2^33. at() is exact to 2^-27 of the largest
// vertex difference (lambdas are cut to 27 bits so the products stay below 2^62) for points
// inside the triangle. step_x() is the per-pixel x increment with 16 extra fraction bits,
// saturated to |g| <= 2^48: a span of n >= 2 pixels inside the triangle has |g| (n - 1) <= the
// vertex range, so saturation only touches one-pixel spans, where the step is never used, and
// an accumulator start (<= 2^49) plus 4096 steps stays below 2^61.
class ScreenPlane {
 public:
  static constexpr int kStepFrac = 16;
  using Step = fx::Q<32, kStepFrac, std::int64_t>;

  void setup(const Triangle& t, std::int64_t v0, std::int64_t v1, std::int64_t v2) {
    v0_ = v0;
    d1_ = v1 - v0;
    d2_ = v2 - v0;
    shift_ = shift_to_fit(static_cast<std::uint64_t>(t.area2), 27);
    area_ = t.area2 >> shift_;
    // dv/dpx = (d1 (y2 - y0) + d2 (y0 - y1)) / area2, times 16 subpixels per pixel.
    const std::int64_t num =
        d1_ * (std::int64_t{t.v[2].sy} - t.v[0].sy) + d2_ * (std::int64_t{t.v[0].sy} - t.v[1].sy);
    step_ = fx::div<Step>(fx::int_q::from_raw(num), fx::Q<58, 4, std::int64_t>::from_raw(t.area2))
                .raw();
  }
  std::int64_t at(const Lambdas& lam) const {
    const std::int64_t l1 = clamp27(lam.l[1] >> shift_), l2 = clamp27(lam.l[2] >> shift_);
    const std::int64_t num = l1 * d1_ + l2 * d2_;
    // fx::div<int_q> for a positive denominator: round half away from zero, one division.
    const auto [q, r] = fx::idivmod(num, area_);
    const std::int64_t ar = r < 0 ? -r : r;
    return v0_ + (ar >= area_ - ar ? (num < 0 ? q - 1 : q + 1) : q);
  }
  std::int64_t step_x() const { return step_; }
  // The per-row increment, as step_x() (same format and saturation), computed on demand: only
  // the methods that step from row to row need it. dv/dpy = (d1 (x0 - x2) + d2 (x1 - x0)) / area2.
  std::int64_t step_y(const Triangle& t) const {
    const std::int64_t num =
        d1_ * (std::int64_t{t.v[0].sx} - t.v[2].sx) + d2_ * (std::int64_t{t.v[1].sx} - t.v[0].sx);
    return fx::div<Step>(fx::int_q::from_raw(num), fx::Q<58, 4, std::int64_t>::from_raw(t.area2))
        .raw();
  }
  // Whether a step is below the saturation limit with room to spare (2^47 against 2^48).
  static constexpr bool step_exact(std::int64_t g) {
    constexpr std::int64_t lim = std::int64_t{1} << 47;
    return g > -lim && g < lim;
  }

 private:
  static constexpr std::int64_t clamp27(std::int64_t v) {
    constexpr std::int64_t lim = std::int64_t{1} << 27;
    return v < -lim ? -lim : (v > lim ? lim : v);
  }
  std::int64_t v0_ = 0, d1_ = 0, d2_ = 0, area_ = 1, step_ = 0;
  int shift_ = 0;
};

// Perspective-correct barycentrics: b_i = (lambda_i / w_i) / sum_j (lambda_j / w_j), Q1.30.
// Per triangle: r_i = w_min / w_i in (0, 1] (Q1.30). Per point: mu_i = lambda_i' r_i with the
// lambdas cut to 28 bits (mu_i < 2^58), then each b_i rounded once by fx::div.
class PerspectiveBary {
 public:
  void setup(const Triangle& t) {
    q15_16 wmin = t.v[0].w;
    for (const auto& v : t.v) wmin = v.w < wmin ? v.w : wmin;
    for (int i = 0; i < 3; ++i) r_[i] = fx::div<q1_30>(wmin, t.v[i].w).raw();
    shift_ = shift_to_fit(static_cast<std::uint64_t>(t.area2), 28);
  }
  // Weights of the three vertices at a point with edge weights lam (all >= 0 inside).
  void at(const Lambdas& lam, q1_30 b[3]) const {
    std::int64_t mu[3];
    std::int64_t sum = 0;
    for (int i = 0; i < 3; ++i) {
      const std::int64_t l = lam.l[i] < 0 ? 0 : (lam.l[i] >> shift_);
      mu[i] = (l > kLim ? kLim : l) * r_[i];
      sum += mu[i];
    }
    if (sum == 0) {  // cannot happen inside a triangle of positive area; stay defined anyway
      b[0] = q1_30::one();
      b[1] = b[2] = q1_30::zero();
      return;
    }
    for (int i = 0; i < 3; ++i)
      b[i] = fx::div<q1_30>(fx::int_q::from_raw(mu[i]), fx::int_q::from_raw(sum));
  }

 private:
  static constexpr std::int64_t kLim = std::int64_t{1} << 28;
  std::int64_t r_[3] = {0, 0, 0};
  int shift_ = 0;
};

// Perspective-correct barycentrics stepped along a span, with one reciprocal per pixel (none
// where the three w are equal): b_i = m_i / Σ m_j (Brown eq. 9) with m_i = λ_i w_min / w_i, λ
// the screen barycentrics; m_i at the span's first pixel by one division each, then stepped by
// its exact-to-2^-40 change per pixel. screen_linear: take b = λ whatever the w (what the
// screen-linear variants interpolate).
class SteppedBarycentrics {
 public:
  using Q40 = fx::Q<22, 40, std::int64_t>;

  void setup(const Triangle& t, bool screen_linear = false) {
    tri_ = &t;
    const q15_16 w0 = t.v[0].w, w1 = t.v[1].w, w2 = t.v[2].w;
    affine_ = screen_linear || (w0.raw() == w1.raw() && w0.raw() == w2.raw());
    q15_16 wmin = w0 < w1 ? w0 : w1;
    wmin = w2 < wmin ? w2 : wmin;
    const Lambdas step = lambdas_step_x(t);
    for (int i = 0; i < 3; ++i) {
      rho_[i] = affine_ ? kOne : fx::div<q1_30>(wmin, t.v[i].w).raw();
      dm_[i] = fx::mul_shift_right(to_q40(step.l[i]), rho_[i], 30);
    }
  }
  // Whether b is affine in screen space (then b = m, and m steps by dm exactly as b).
  bool affine() const { return affine_; }
  // Starts a span at pixel (x, y).
  void start(std::int32_t x, std::int32_t y) {
    const Lambdas lam = lambdas_at(*tri_, 16 * std::int64_t{x} + 8, 16 * std::int64_t{y} + 8);
    for (int i = 0; i < 3; ++i) m_[i] = fx::mul_shift_right(to_q40(lam.l[i]), rho_[i], 30);
  }
  // m at the current pixel and its step per pixel, Q.40 (for an affine triangle: b itself).
  const std::int64_t* m() const { return m_; }
  const std::int64_t* dm() const { return dm_; }
  // The current pixel's barycentrics, Q.30 clamped to [0, 1]; then steps to the next pixel.
  void next(std::int64_t b[3]) {
    if (affine_) {
      for (int i = 0; i < 3; ++i) b[i] = fx::round_shift_right(m_[i], 10);
    } else {
      const std::int64_t sum = fx::round_shift_right(m_[0] + m_[1] + m_[2], 10);  // Q.30, > 0
      const std::int64_t inv = fx::idiv((std::int64_t{1} << 60) + sum / 2, sum > 0 ? sum : 1);
      for (int i = 0; i < 3; ++i) b[i] = fx::mul_shift_right(m_[i] >> 10, inv, 30);
    }
    for (int i = 0; i < 3; ++i) {
      b[i] = b[i] < 0 ? 0 : (b[i] > kOne ? kOne : b[i]);
      m_[i] += dm_[i];
    }
  }

 private:
  static constexpr std::int64_t kOne = std::int64_t{1} << 30;
  std::int64_t to_q40(std::int64_t lambda) const {
    return fx::div<Q40>(fx::int_q::from_raw(lambda), fx::int_q::from_raw(tri_->area2)).raw();
  }
  const Triangle* tri_ = nullptr;
  bool affine_ = true;
  std::int64_t rho_[3] = {0, 0, 0};  // w_min / w_i, Q.30
  std::int64_t dm_[3] = {0, 0, 0};   // Q.40
  std::int64_t m_[3] = {0, 0, 0};    // Q.40
};

}  // namespace tp::fw
