#include "firmware/texture.hpp"

#include "firmware/lighting.hpp"
#include "fixedpoint/normalize_fast.hpp"
#include "fixedpoint/sqrt.hpp"

namespace tp::fw {
namespace {

constexpr std::int64_t kOne30 = std::int64_t{1} << 30;

// A Q.30 value in [0, 1] as a sample, rounded.
std::uint16_t to_texel(std::int64_t v) {
  v = v < 0 ? 0 : (v > kOne30 ? kOne30 : v);
  return static_cast<std::uint16_t>((v + (std::int64_t{1} << 14)) >> 15);
}

template <class F>
void fill(std::uint16_t* tex, int log2_cells, int stride, F value) {
  const int side = texture_side(log2_cells);
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i)
      value(grid_coordinate(i, log2_cells), grid_coordinate(j, log2_cells),
            tex + (j * side + i) * stride);
}

// A texture of the hemisphere's height h(x, y) alone, value(h) Q.30: one eighth of the samples
// computed (0 <= j <= i <= cells / 2), the rest by the square's eight symmetries.
template <class F>
void fill_radial(std::uint16_t* tex, int log2_cells, F value) {
  const int cells = 1 << log2_cells, side = cells + 1;
  for (int j = 0; j <= cells / 2; ++j)
    for (int i = j; i <= cells / 2; ++i) {
      const std::uint16_t t = to_texel(
          value(disk_height(grid_coordinate(i, log2_cells), grid_coordinate(j, log2_cells))));
      for (const int a : {i, cells - i})
        for (const int b : {j, cells - j}) {
          tex[b * side + a] = t;
          tex[a * side + b] = t;
        }
    }
}

}  // namespace

// sqrt(1 - x² - y²) by the sample-grade reciprocal root (relative error < 2^-28, far below a
// sample's 2^-15): x · (1/sqrt(x)) with x = 1 - x² - y² cut to Q.30.
std::int64_t disk_height(std::int64_t x, std::int64_t y) {
  const std::int64_t rest = ((std::int64_t{1} << 58) - x * x - y * y) >> 28;  // Q.30
  if (rest <= 0) return 0;
  const fx::RsqrtFast inv = fx::rsqrt_fast(static_cast<std::uint64_t>(rest));
  // (rest · r) >> shift is rest / sqrt(rest) in Q1.30 (rest an integer): sqrt(rest) 2^30; the
  // root of the Q.30 value is sqrt(rest) 2^15 (rest · r < 2^62).
  return fx::round_shift_right(rest * inv.r, inv.shift + 15);
}

void build_blinn_diffuse(std::uint16_t* tex, int log2_cells) {
  fill_radial(tex, log2_cells, [](std::int64_t h) { return h; });  // Vlasic eq. 5.4
}

void build_blinn_specular(std::uint16_t* tex, int log2_cells, std::uint32_t n) {
  // Vlasic eq. 5.5, (1 - x² - y²)^(n/2) = (N·H)^n with N·H the hemisphere's height.
  fill_radial(tex, log2_cells, [n](std::int64_t h) {
    return h == 0 ? 0 : power(q1_30::from_raw(static_cast<std::int32_t>(h)), n).raw();
  });
}

Vec3u sphere_map_direction(std::int64_t x, std::int64_t y) {
  const std::int64_t z = disk_height(x, y);  // Q.30
  if (z == 0) return Vec3u{q1_30::zero(), q1_30::zero(), q1_30::from_raw(-(std::int32_t{1} << 30))};
  const auto q30 = [](std::int64_t v) { return q1_30::from_raw(static_cast<std::int32_t>(v)); };
  // 2 z x: Q.30 × Q.29 = Q.59, times 2, to Q.30 (|2 z x| <= 1).
  return Vec3u{q30(fx::round_shift_right(z * x, 28)), q30(fx::round_shift_right(z * y, 28)),
               q30(fx::round_shift_right(2 * z * z, 30) - kOne30)};
}

std::int64_t sphere_map_highlight(const Vec3u& w, const Vec3u& l, std::uint32_t n) {
  const std::int64_t d = fx::dot<q1_30>(w, l).raw();
  std::int64_t half = (kOne30 + d) / 2;  // (1 + W·L) / 2 = cos² of half the angle from R to V
  half = half < 0 ? 0 : (half > kOne30 ? kOne30 : half);
  const q1_30 h = q1_30::from_raw(static_cast<std::int32_t>(half));
  if (n % 2 == 0) return power(h, n / 2).raw();  // no root for an even n
  const q1_30 c = fx::sqrt<q1_30>(h);
  return power(c > q1_30::one() ? q1_30::one() : c, n).raw();
}

void build_sphere_map(std::uint16_t* tex, int log2_cells, const ShadeContext& ctx,
                      const Vec3q16& centre) {
  Vec3u direction[kMaxLights];
  std::int64_t weight[kMaxLights][3];  // ks Il_c, Q.30
  int lights = 0;
  for (const LightState& l : ctx.lights) {
    if (!contributes(l)) continue;
    direction[lights] = light_direction(l, centre);
    for (int ch = 0; ch < 3; ++ch)
      weight[lights][ch] = fx::mul_shift_right(ctx.material.ks.raw(), l.color[ch].raw(), 16);
    ++lights;
  }
  // The map is the method's table of the summed highlight: its specular factors are evaluated
  // here, one per sample and light (firmware/counters.hpp), and none per pixel.
  ctx.counters->specular_evaluations +=
      static_cast<std::uint64_t>(texture_texels(log2_cells)) * static_cast<std::uint64_t>(lights);
  const std::uint32_t n = ctx.material.n;
  fill(tex, log2_cells, 3, [&](std::int64_t x, std::int64_t y, std::uint16_t* out) {
    const Vec3u w = sphere_map_direction(x, y);
    std::int64_t sum[3] = {0, 0, 0};
    for (int k = 0; k < lights; ++k) {
      const std::int64_t s = sphere_map_highlight(w, direction[k], n);
      for (int ch = 0; ch < 3; ++ch) sum[ch] += fx::mul_shift_right(weight[k][ch], s, 30);
    }
    for (int ch = 0; ch < 3; ++ch) out[ch] = to_texel(sum[ch]);
  });
}

}  // namespace tp::fw
