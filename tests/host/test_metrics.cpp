// Metrics on hand-computed 2×1 and 2×2 images.
#include <gtest/gtest.h>

#include <cmath>

#include "host/metrics.hpp"

using namespace tp::host;

namespace {
Image8 img(int w, int h, std::vector<std::uint8_t> rgb) {
  Image8 im(w, h);
  im.rgb = std::move(rgb);
  return im;
}
}  // namespace

TEST(Metrics, HandComputedPair) {
  // Pixel 0: Δ = (10, 0, 5); pixel 1: Δ = (0, 3, 0); pixel 2 covered only in the reference,
  // pixel 3 only in the evaluated image (both excluded).
  const Image8 ref = img(2, 2, {100, 100, 100, 50, 60, 70, 9, 9, 9, 0, 0, 0});
  const Image8 ev = img(2, 2, {110, 100, 95, 50, 63, 70, 0, 0, 0, 7, 7, 7});
  const Mask mr = {1, 1, 1, 0}, me = {1, 1, 0, 1};
  const Comparison c = compare(ref, mr, ev, me);
  EXPECT_EQ(c.covered_both, 2);
  EXPECT_EQ(c.only_reference, 1);
  EXPECT_EQ(c.only_evaluated, 1);
  // eq. 6.1: 1 − (10 + 0 + 5 + 0 + 3 + 0)/(3·255·2) = 1 − 18/1530.
  EXPECT_DOUBLE_EQ(c.color_correctness, 1 - 18.0 / 1530.0);
  EXPECT_DOUBLE_EQ(c.mean_abs, 18.0 / 6.0);
  EXPECT_EQ(c.max_abs, 10);
  // MSE = (100 + 25 + 9)/6; PSNR = 10·log10(255²/MSE).
  EXPECT_NEAR(c.psnr_db, 10 * std::log10(255.0 * 255.0 * 6.0 / 134.0), 1e-12);
}

TEST(Metrics, IdenticalImagesArePerfect) {
  const Image8 a = img(2, 1, {1, 2, 3, 4, 5, 6});
  const Comparison c = compare(a, {1, 1}, a, {1, 1});
  EXPECT_EQ(c.color_correctness, 1.0);
  EXPECT_TRUE(std::isinf(c.psnr_db));
  EXPECT_EQ(c.max_abs, 0);
}

TEST(Metrics, GammaEnhancedDifferenceEq62) {
  const Image8 ref = img(2, 1, {0, 255, 100, 10, 10, 10});
  const Image8 ev = img(2, 1, {1, 0, 100, 0, 0, 0});
  const Image8 d = difference_image(ref, {1, 1}, ev, {1, 0});
  // 255·(1/255)^0.1 = 255·e^(−0.1·ln 255) = 146.52 -> 147; 255·1^0.1 = 255; Δ = 0 -> 0.
  EXPECT_EQ(d.rgb[0], 147);
  EXPECT_EQ(d.rgb[1], 255);
  EXPECT_EQ(d.rgb[2], 0);
  EXPECT_EQ(d.rgb[3], 0);  // not covered in both
}

TEST(Metrics, ScanlineCurveEq63) {
  const Image8 im = img(3, 1, {255, 255, 255, 30, 60, 90, 1, 1, 1});
  const auto curve = scanline_curve(im, {1, 1, 0}, 0);
  ASSERT_EQ(curve.size(), 3u);
  EXPECT_DOUBLE_EQ(*curve[0], 1.0);
  EXPECT_DOUBLE_EQ(*curve[1], 180.0 / 765.0);
  EXPECT_FALSE(curve[2].has_value());
  EXPECT_THROW(scanline_curve(im, {1, 1, 0}, 1), std::out_of_range);
}

TEST(Metrics, MaskFromBackground) {
  const Image8 im = img(3, 1, {0, 0, 0, 0, 0, 1, 5, 5, 5});
  EXPECT_EQ(mask_from_background(im), (Mask{0, 1, 1}));
  EXPECT_EQ(mask_from_background(im, {5, 5, 5}), (Mask{1, 1, 0}));
}

TEST(Metrics, SizeMismatchIsRejected) {
  EXPECT_THROW(compare(Image8(2, 1), {1, 1}, Image8(1, 2), {1, 1}), std::invalid_argument);
}
