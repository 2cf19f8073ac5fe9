// The textures of Vlasic's texture-mapping methods (envmap, blinn-map, quadratic-blinn-map): a
// square grid of 16-bit samples over the coordinate square [-1, 1]², corner-aligned — sample
// (i, j) sits at u = -1 + 2 i / cells, v = -1 + 2 j / cells — so the disk's centre and rim fall
// on samples. The device builds them in the method's region of its memory block from the
// material and the lights (integer-only), and samples them with an integer bilinear filter.
// Their size and filter are chosen by measurement against the exact functions
// (tests/firmware/texture_test.cpp; docs/DECISIONS.md, "Vlasic's texture methods").
#pragma once

#include <cstdint>

#include "firmware/build.hpp"
#include "firmware/interp.hpp"
#include "firmware/method.hpp"

namespace tp::fw {

// Texture coordinates: Q.29 (raw 2^29 = 1), |c| <= 2 (blinn-map places a normal that faces away
// from the plane's vector outside the unit disk, up to radius 2).
inline constexpr int kCoordFrac = 29;
inline constexpr std::int64_t kCoordOne = std::int64_t{1} << kCoordFrac;
// Samples: Q1.15 (32768 = 1).
inline constexpr int kTexelFrac = 15;
inline constexpr std::int32_t kTexelOne = std::int32_t{1} << kTexelFrac;

// The methods' textures: 64 cells (65 samples) a side — the measured choice.
inline constexpr int kTextureLog2Cells = 6;
constexpr int texture_side(int log2_cells) { return (1 << log2_cells) + 1; }
constexpr int texture_texels(int log2_cells) {
  return texture_side(log2_cells) * texture_side(log2_cells);
}

// Sample i's coordinate, -1 + 2 i / cells, Q.29.
TP_SIZE_OUTLINE constexpr std::int64_t grid_coordinate(int i, int log2_cells) {
  return (std::int64_t{i} << (kCoordFrac + 1 - log2_cells)) - kCoordOne;
}

// Where a coordinate pair falls, clamped to the square: the cell's first sample (i along u, j
// along v, each below cells) and the fractions across the cell, Q.15.
struct TexelPosition {
  std::int32_t i = 0, j = 0;
  std::int32_t fu = 0, fv = 0;
};
inline TexelPosition texel_position(std::int64_t u, std::int64_t v, int log2_cells) {
  const int shift = kCoordFrac + 1 - log2_cells;
  const auto axis = [&](std::int64_t c, std::int32_t& cell, std::int32_t& frac) {
    c = c < -kCoordOne ? -kCoordOne : (c >= kCoordOne ? kCoordOne - 1 : c);
    const std::int64_t t = c + kCoordOne;  // [0, 2^30)
    cell = static_cast<std::int32_t>(t >> shift);
    frac = static_cast<std::int32_t>((t >> (shift - kTexelFrac)) & (kTexelOne - 1));
  };
  TexelPosition p;
  axis(u, p.i, p.fu);
  axis(v, p.j, p.fv);
  return p;
}

// The bilinear sample (Q1.15) of a texture whose texels are `stride` values apart (an RGB
// texture's channel: stride 3, the texture pointer at its first value).
inline std::int32_t sample_bilinear(const std::uint16_t* tex, int log2_cells, int stride,
                                    const TexelPosition& p) {
  const int side = texture_side(log2_cells);
  const std::uint16_t* t = tex + (p.j * side + p.i) * stride;
  const std::int32_t a = t[0], b = t[stride], c = t[side * stride], d = t[(side + 1) * stride];
  constexpr std::int32_t half = kTexelOne / 2;
  const std::int32_t top = a + (((b - a) * p.fu + half) >> kTexelFrac);
  const std::int32_t bottom = c + (((d - c) * p.fu + half) >> kTexelFrac);
  return top + (((bottom - top) * p.fv + half) >> kTexelFrac);
}

// The nearest sample (Q1.15): measured against the bilinear one, not taken by a method.
inline std::int32_t sample_nearest(const std::uint16_t* tex, int log2_cells, int stride,
                                   const TexelPosition& p) {
  const int side = texture_side(log2_cells);
  const std::int32_t i = p.i + (p.fu >= kTexelOne / 2 ? 1 : 0);
  const std::int32_t j = p.j + (p.fv >= kTexelOne / 2 ? 1 : 0);
  return tex[(j * side + i) * stride];
}

// A texture coordinate interpolated in screen space (envmap, blinn-map) from its values at the
// three vertices (Q.29, |c| <= 2), Q.40: its step per pixel once per triangle, from the
// barycentrics' exact steps; its value at a span's first pixel from their Q.30 part (within
// 2^-27 of the exact, a 2^-22 part of a texture cell), three 64-bit products.
struct LinearCoordinate {
  std::int64_t vertex[3] = {0, 0, 0};
  std::int64_t step = 0;
  void setup(const SteppedBarycentrics& b) {
    step = 0;
    for (int i = 0; i < 3; ++i) step += fx::mul_shift_right(b.dm()[i], vertex[i], kCoordFrac);
  }
  std::int64_t start(const SteppedBarycentrics& b) const {
    std::int64_t sum = 0;  // Q.59, each product below 2^61
    for (int i = 0; i < 3; ++i) sum += (b.m()[i] >> 10) * vertex[i];
    return sum >> (kCoordFrac + 30 - 40);
  }
};

// The height of the unit hemisphere over (x, y), sqrt(1 - x² - y²), Q.30; 0 outside the disk.
std::int64_t disk_height(std::int64_t x, std::int64_t y);

// Blinn's textures (Vlasic eqs. 5.4 and 5.5) over the shading parameter plane: diffuse
// sqrt(1 - x² - y²), specular (1 - x² - y²)^(n/2); 0 outside the unit disk.
void build_blinn_diffuse(std::uint16_t* tex, int log2_cells);
void build_blinn_specular(std::uint16_t* tex, int log2_cells, std::uint32_t n);

// The sphere map's reflected view vector W at texture point (x, y) (Vlasic eqs. 5.1-5.3
// inverted): the mirror sphere's normal there is (x, y, z), z = sqrt(1 - x² - y²), and
// W = (2 z x, 2 z y, 2 z² - 1), Q.30; (0, 0, -1) on and outside the rim.
Vec3u sphere_map_direction(std::int64_t x, std::int64_t y);

// Blinn's highlight as a function of W alone (docs/DECISIONS.md, "Vlasic's texture methods"):
// ((1 + W·L) / 2)^(n/2), which is (N·H)^n wherever N lies in the plane of L and the view, Q.30.
std::int64_t sphere_map_highlight(const Vec3u& w, const Vec3u& l, std::uint32_t n);

// The envmap's RGB texture (three values per texel): at each sample, the sum over the lights of
// ks Il_c sphere_map_highlight(W, L_l), clamped to 1, with L_l the light's direction or, for a
// point light, the direction to it from `centre`.
void build_sphere_map(std::uint16_t* tex, int log2_cells, const ShadeContext& ctx,
                      const Vec3q16& centre);

}  // namespace tp::fw
