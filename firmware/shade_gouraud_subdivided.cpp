// Gouraud on the triangle cut into four at its edge midpoints (methods.hpp, 9): setup lights the
// six points and sets up the four sub-triangles' planes; the pixel loop picks each pixel's
// sub-triangle by the inner edges and steps its colour as Gouraud does.
#include "firmware/methods.hpp"
#include "firmware/six_points.hpp"
#include "fixedpoint/divide.hpp"

namespace tp::fw {
namespace {

// The sub-triangles' corners among the six points (0-2 vertices, 3-5 midpoints of 0-1, 1-2,
// 2-0), each in the triangle's own orientation.
constexpr int kPartPoints[4][3] = {{0, 3, 5}, {3, 1, 4}, {5, 4, 2}, {3, 4, 5}};

// Where the eye-space midpoint of edge a-b lands on screen: its clip coordinates are the mean of
// a's and b's, so its screen position is (w_a S_a + w_b S_b) / (w_a + w_b), rounded to 1/16 pixel.
std::int32_t screen_midpoint(std::int32_t sa, q15_16 wa, std::int32_t sb, q15_16 wb) {
  const std::int64_t num = std::int64_t{sa} * wa.raw() + std::int64_t{sb} * wb.raw();
  const std::int64_t den = std::int64_t{wa.raw()} + wb.raw();  // > 0 after clipping
  return static_cast<std::int32_t>(
      fx::div<fx::int_q>(fx::int_q::from_raw(num), fx::int_q::from_raw(den)).raw());
}

}  // namespace

bool GouraudSubdividedMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  VertexLevels lit[6];
  six_levels(tri, ctx, lit);
  ShadeVertex point[6];
  for (int i = 0; i < 3; ++i) point[i] = tri.v[i];
  for (int e = 0; e < 3; ++e) {
    const ShadeVertex& a = tri.v[kSixEdge[e][0]];
    const ShadeVertex& b = tri.v[kSixEdge[e][1]];
    point[3 + e].sx = screen_midpoint(a.sx, a.w, b.sx, b.w);
    point[3 + e].sy = screen_midpoint(a.sy, a.w, b.sy, b.w);
  }
  for (int k = 0; k < 4; ++k) {
    Part& p = part_[k];
    const int* corner = kPartPoints[k];
    for (int j = 0; j < 3; ++j) p.tri.v[j] = point[corner[j]];
    p.tri.area2 = edge_function(p.tri.v[1], p.tri.v[2], p.tri.v[0].sx, p.tri.v[0].sy);
    p.degenerate = p.tri.area2 <= 0;  // a sub-triangle that rounding flattened: its mean colour
    p.stepped = !p.degenerate;
    for (int ch = 0; ch < 3; ++ch) {
      const std::int64_t c0 = lit[corner[0]].c[ch], c1 = lit[corner[1]].c[ch],
                         c2 = lit[corner[2]].c[ch];
      const std::int64_t low = c0 < c1 ? c0 : c1, high = c0 < c1 ? c1 : c0;
      const std::int64_t lowest = c2 < low ? c2 : low, highest = c2 > high ? c2 : high;
      p.lowest[ch] = lowest << ScreenPlane::kStepFrac;
      p.range[ch] = static_cast<std::uint64_t>(highest - lowest) << ScreenPlane::kStepFrac;
      if (p.degenerate) {
        p.constant[ch] = fx::idiv(c0 + c1 + c2, 3);
        continue;
      }
      p.plane[ch].setup(p.tri, c0, c1, c2);
      p.step[ch] = p.plane[ch].step_x();
      p.stepped = p.stepped && ScreenPlane::step_exact(p.step[ch]);
    }
  }
  return true;
}

// The three channels of part k at pixel (x, y), exactly, with ScreenPlane::kStepFrac more
// fraction bits.
void GouraudSubdividedMethod::part_start(int k, std::int32_t x, std::int32_t y,
                                         std::int64_t c[3]) const {
  const Part& p = part_[k];
  if (p.degenerate) {
    for (int ch = 0; ch < 3; ++ch) c[ch] = p.constant[ch] << ScreenPlane::kStepFrac;
    return;
  }
  const Lambdas lam = lambdas_at(p.tri, 16 * std::int64_t{x} + 8, 16 * std::int64_t{y} + 8);
  for (int ch = 0; ch < 3; ++ch) c[ch] = p.plane[ch].at(lam) << ScreenPlane::kStepFrac;
}

void GouraudSubdividedMethod::shade_span(const Span& s, Rgb8* out) {
  constexpr int f = 30 + ScreenPlane::kStepFrac;
  constexpr std::int64_t kHalf = std::int64_t{1} << (f - 1);
  const ShadeVertex* m = part_[3].tri.v;  // m01, m12, m20
  const std::int64_t px = 16 * std::int64_t{s.x0} + 8, py = 16 * std::int64_t{s.y} + 8;
  std::int64_t e[3], de[3];  // the inner edges' functions at the pixel and their steps in x
  for (int i = 0; i < 3; ++i) {
    const ShadeVertex& a = m[i];
    const ShadeVertex& b = m[(i + 1) % 3];
    e[i] = edge_function(a, b, px, py);
    de[i] = -16 * (std::int64_t{b.sy} - a.sy);
  }
  int current = -1;
  std::int64_t c[3] = {0, 0, 0};
  std::int64_t lowest[3] = {0, 0, 0};  // the current part's (Part::lowest, Part::range)
  std::uint64_t range[3] = {0, 0, 0};
  for (std::int32_t x = s.x0; x < s.x1; ++x) {
    // Beyond m01→m12 lies corner 1, beyond m12→m20 corner 2, beyond m20→m01 corner 0.
    const int k = e[0] < 0 ? 1 : (e[1] < 0 ? 2 : (e[2] < 0 ? 0 : 3));
    if (k == current && part_[k].stepped) {
      for (int ch = 0; ch < 3; ++ch) c[ch] += part_[k].step[ch];  // Gouraud: one addition
    } else {
      part_start(k, x, s.y, c);
      current = k;
      for (int ch = 0; ch < 3; ++ch) {
        lowest[ch] = part_[k].lowest[ch];
        range[ch] = part_[k].range[ch];
      }
    }
    const auto level = [&](int ch) {
      // Held within the corners' colours, so within [0, 1]: one unsigned comparison where it is
      // (the difference taken modulo 2^64, below the lowest it is above any range).
      std::int64_t v = c[ch];
      if (static_cast<std::uint64_t>(v) - static_cast<std::uint64_t>(lowest[ch]) > range[ch])
        v = v < lowest[ch] ? lowest[ch] : lowest[ch] + static_cast<std::int64_t>(range[ch]);
      return static_cast<std::uint8_t>((255 * v + kHalf) >> f);
    };
    *out++ = Rgb8{level(0), level(1), level(2)};
    for (int i = 0; i < 3; ++i) e[i] += de[i];
  }
}

}  // namespace tp::fw
