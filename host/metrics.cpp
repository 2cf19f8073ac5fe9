#include "host/metrics.hpp"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>

namespace tp::host {

namespace {
void check_same(const Image8& a, const Mask& ma, const Image8& b, const Mask& mb) {
  const auto n = static_cast<std::size_t>(a.width) * static_cast<std::size_t>(a.height);
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument("images differ in size");
  if (ma.size() != n || mb.size() != n) throw std::invalid_argument("mask size does not match");
}
}  // namespace

Comparison compare(const Image8& ref, const Mask& mref, const Image8& ev, const Mask& mev) {
  check_same(ref, mref, ev, mev);
  Comparison c;
  long long sum_abs = 0;
  double sum_sq = 0;
  for (std::size_t p = 0; p < mref.size(); ++p) {
    if (mref[p] && !mev[p]) ++c.only_reference;
    if (!mref[p] && mev[p]) ++c.only_evaluated;
    if (!mref[p] || !mev[p]) continue;
    ++c.covered_both;
    for (std::size_t k = 0; k < 3; ++k) {
      const int d = std::abs(int{ref.rgb[3 * p + k]} - int{ev.rgb[3 * p + k]});
      sum_abs += d;
      sum_sq += double(d) * d;
      c.max_abs = std::max(c.max_abs, d);
    }
  }
  if (c.covered_both == 0) {
    c.psnr_db = std::numeric_limits<double>::infinity();
    return c;
  }
  const double samples = 3.0 * static_cast<double>(c.covered_both);
  c.color_correctness = 1 - static_cast<double>(sum_abs) / (255.0 * samples);  // eq. 6.1
  c.mean_abs = static_cast<double>(sum_abs) / samples;
  const double mse = sum_sq / samples;
  c.psnr_db =
      mse > 0 ? 10 * std::log10(255.0 * 255.0 / mse) : std::numeric_limits<double>::infinity();
  return c;
}

Mask mask_from_background(const Image8& im, glm::u8vec3 bg) {
  Mask m(static_cast<std::size_t>(im.width) * static_cast<std::size_t>(im.height), 0);
  for (std::size_t p = 0; p < m.size(); ++p)
    m[p] = !(im.rgb[3 * p] == bg.r && im.rgb[3 * p + 1] == bg.g && im.rgb[3 * p + 2] == bg.b);
  return m;
}

Image8 difference_image(const Image8& ref, const Mask& mref, const Image8& ev, const Mask& mev) {
  check_same(ref, mref, ev, mev);
  Image8 out(ref.width, ref.height);
  for (std::size_t p = 0; p < mref.size(); ++p) {
    if (!mref[p] || !mev[p]) continue;
    for (std::size_t k = 0; k < 3; ++k) {
      const int d = std::abs(int{ref.rgb[3 * p + k]} - int{ev.rgb[3 * p + k]});
      // Vlasic eq. 6.2: gamma 1/10 makes one-level differences visible (255·(1/255)^0.1 ≈ 146.5).
      out.rgb[3 * p + k] = static_cast<std::uint8_t>(std::lround(255 * std::pow(d / 255.0, 0.1)));
    }
  }
  return out;
}

std::vector<std::optional<double>> scanline_curve(const Image8& im, const Mask& m, int y) {
  if (y < 0 || y >= im.height) throw std::out_of_range("scanline row outside the image");
  std::vector<std::optional<double>> out(static_cast<std::size_t>(im.width));
  for (int x = 0; x < im.width; ++x) {
    const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(im.width) +
                          static_cast<std::size_t>(x);
    if (!m[p]) continue;
    const std::uint8_t* c = im.at(x, y);
    out[static_cast<std::size_t>(x)] = (c[0] + c[1] + c[2]) / (3.0 * 255.0);  // eq. 6.3
  }
  return out;
}

}  // namespace tp::host
