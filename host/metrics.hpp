// Error measures between a reference image and an evaluated one (Vlasic's thesis, ch. 6: colour
// correctness, eq. 6.1; docs/RESULTS.md). All are taken over the pixels covered in both images;
// background pixels are excluded.
#pragma once

#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "host/image.hpp"

namespace tp::host {

struct Comparison {
  long long covered_both = 0;    // N of eq. 6.1
  long long only_reference = 0;  // covered in the reference, not in the evaluated image
  long long only_evaluated = 0;
  double color_correctness = 1;  // Vlasic eq. 6.1: 1 − Σ(|ΔR|+|ΔG|+|ΔB|)/(3·255·N)
  double psnr_db = 0;            // 10·log10(255²/MSE), MSE over channels; +inf if identical
  double mean_abs = 0;           // mean |Δ| per channel, 8-bit levels
  int max_abs = 0;               // max |Δ| over channels, 8-bit levels

  // Without a pixel covered in both images the measures have nothing to measure: the fields
  // above keep their initial values, which are not a result (a printer says "none" instead).
  bool measured() const { return covered_both > 0; }
};

// Precondition: same size; masks have one entry per pixel (nonzero = covered).
Comparison compare(const Image8& reference, const Mask& reference_mask, const Image8& evaluated,
                   const Mask& evaluated_mask);

// Coverage of an image read back from a file: every pixel that is not exactly the background.
Mask mask_from_background(const Image8& image, glm::u8vec3 background = {0, 0, 0});

// Vlasic eq. 6.2: per channel 255·(|Δ|/255)^(1/10), rounded; pixels not covered in both are 0.
Image8 difference_image(const Image8& reference, const Mask& reference_mask,
                        const Image8& evaluated, const Mask& evaluated_mask);

// Vlasic eq. 6.3: (R+G+B)/(3·255) along row y; nullopt where the pixel is not covered.
std::vector<std::optional<double>> scanline_curve(const Image8& image, const Mask& mask, int y);

}  // namespace tp::host
