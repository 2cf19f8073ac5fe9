// kb-adaptive (docs/KUIJK-BLAKE.md "kb-adaptive"): Kuijk-Blake shading that chooses, per
// triangle and under an error budget, how to evaluate:
//   constant / linear / quadratic — one screen-space quadratic per channel through exact samples
//     at the vertices and edge midpoints, every light summed into it (two additions per channel
//     per pixel, no per-span trigonometry), when its error estimate is within the budget;
//   subdivision — where the quadratic misses, the cells that miss are split into four, down to
//     4^4, with exact L, H and N at every new sample point, so that near point lights converge
//     toward per-pixel Phong instead of failing as angular interpolation of L does;
//   exact — per pixel, on triangles under 64 pixels (their samples would cost more), on
//     triangles with fewer pixels than refining would take samples, and on deepest-level cells
//     that still miss.
// The exact evaluation (firmware/point_shader.hpp) is Blinn-Phong at the perspective-correct point,
// and the budget bounds the difference from it: every pixel of a cheap path within
// ShadeContext::budget_levels output levels of it.
//
// The error estimate (docs/KUIJK-BLAKE.md): the quadratic is compared with exact values at the
// nine other points of the quarter lattice (the children's samples, so refining reuses them), and
// a highlight guard makes the samples dense enough, in angle, for any specular peak that may lie
// on the cell (peak_level).
#pragma once

#include <cstddef>
#include <cstdint>

#include "firmware/kb/kb_quadratic.hpp"
#include "firmware/method.hpp"
#include "firmware/point_shader.hpp"

namespace tp::fw::kb {

// The error budget: every pixel of a cheap path within B output levels of the exact per-pixel
// evaluation, B = ShadeContext::budget_levels (1 unless set_budget changed it). The estimate (check
// points) must stay below it with a margin for what lies between the check points: 0.375·B level
// keeps every pixel of 300,000 random triangles within the budget at B = 1, 0.61 does not
// (tests/kb/test_kb_adaptive.cpp, which also measures B = 2, 4 and 16).
inline constexpr std::int32_t kEstimatePerLevel = (1 << kSampleFrac) * 3 / 8;  // 0.375 level, Q.14
inline constexpr int kMaxLevel = 4;  // deepest subdivision: 4^4 = 256 sub-triangles
// A cell of level kMaxLevel − 1 whose estimate is within this (times B) makes its children leaves
// unchecked (refine): under the h³ law their error is an eighth of it, 0.094·B level.
inline constexpr std::int32_t kTrustedMissPerLevel = 2 * kEstimatePerLevel;  // 0.75 level, Q.14
inline constexpr int kLatticeRes = 4 << kMaxLevel;  // quarter lattice of the deepest level
inline constexpr int kLatticePoints = (kLatticeRes + 1) * (kLatticeRes + 2) / 2;
// Lights per triangle whose terminator (N·L = 0, the kink of max(0, N·L)) is handled exactly:
// their diffuse is sampled unclamped and max(0, ·) applied per pixel where a cell crosses it.
inline constexpr int kMaxTerminators = 8;
// Triangles below 64 pixels (area2 counts 512 per pixel) go straight to per-pixel evaluation:
// their samples and check would cost more (docs/KUIJK-BLAKE.md, "kb-adaptive").
inline constexpr std::int64_t kDirectExactArea2 = std::int64_t{64} * 512;
inline constexpr int kChannels = 3 + kMaxTerminators;  // colours (Q.14 levels), then N·L (Q.24)

// kAdaptive: the method. kNoSkip: the same choices, but constant triangles are stepped and every
// light is evaluated everywhere (the image must not change: tested). kExactOnly: every pixel
// exact — the reference the budget is measured against (tests, docs).
enum class AdaptiveMode : std::uint8_t { kAdaptive, kNoSkip, kExactOnly };

// How a light's N·L behaves over a cell of the subdivision: positive (lit) or negative (dark) all
// over it, or neither (its terminator crosses the cell: clamped per pixel).
enum class TerminatorSign : std::uint8_t { kLit, kDark, kCrossing };

class KbAdaptiveMethod final : public ShadingMethod {
 public:
  enum class Path : std::uint8_t { kConstant, kLinear, kQuadratic, kSubdivided, kExact };
  // What identifies a vertex for the boundary samples' memo.
  struct VertexKey {
    std::int32_t sx = 0, sy = 0;
    std::int64_t z = 0;
    std::int32_t nx = 0, ny = 0, nz = 0;
    std::int32_t w = 0, ex = 0, ey = 0, ez = 0;  // clip w and the eye-space position
    friend bool operator==(const VertexKey&, const VertexKey&) = default;
  };
  explicit KbAdaptiveMethod(AdaptiveMode mode = AdaptiveMode::kAdaptive) : mode_(mode) {}
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
  void shade_span(const Span& s, Rgb8* out) override;
  static constexpr bool kSkipsHiddenPixels = true;

  Path path() const { return path_; }
  int level() const { return level_; }
  // The exact evaluation at pixel (x, y) of the current triangle: what the per-pixel path
  // writes and what the cheap paths are held to (tests).
  Rgb8 exact_at(std::int32_t x, std::int32_t y) const;

  // A cell of the subdivision: level L has 4^L cells, "up" (i, j) with i + j <= 2^L − 1 and
  // "down" (i, j) with i + j <= 2^L − 2, in units of 2^-L of the barycentrics (λ1, λ2).
  struct Cell {
    int level = 0, i = 0, j = 0;
    bool up = true;
  };

 private:
  static constexpr Cell kWhole{0, 0, 0, true};
  // A terminator's N·L quadratic over a cell, fitted through its six samples, and its sign there.
  struct TerminatorFit {
    LocalQuadratic nl;
    TerminatorSign sign = TerminatorSign::kLit;
  };
  // A leaf of the subdivision: its cell and quadratics, or exact (over budget at the deepest
  // level: evaluated per pixel).
  struct Leaf {
    Cell cell;
    SteppedQuadratic q[3];
    bool exact = false;
    bool in_range = false;  // the quadratics stay inside [0, 255]: no clamp per pixel
    // Terminators crossing the cell: crossings_[first .. first + crossing).
    std::uint8_t crossing = 0;
    std::uint16_t first = 0;
  };
  static constexpr int kMaxLeaves = 1 << (2 * kMaxLevel);
  // A terminator crossing a cell: N·L's quadratic and the weight per channel (levels Q.14 per
  // unit N·L) of max(0, −N·L), the diffuse the unclamped samples left out. Crossed cells are
  // few (they lie along the terminator curves); a cell that finds the pool full is evaluated
  // per pixel instead.
  struct Crossing {
    SteppedQuadratic nl;
    std::int64_t weight[3] = {0, 0, 0};
  };
  static constexpr int kMaxCrossings = 256;
  struct Lattice {
    std::int32_t value[kLatticePoints][kChannels] = {};  // see kChannels
    std::uint32_t stamp[kLatticePoints] = {};  // == generation: evaluated for this triangle
    std::uint32_t generation = 0;
  };
  static constexpr int index(int a, int b) { return b * (kLatticeRes + 1) - b * (b - 1) / 2 + a; }
  // Lattice coordinates of quarter point (qu, qv) of cell c: kLatticeRes / (4·2^level) lattice
  // steps per quarter, from the cell's A vertex (an "up" cell (i, j) has A = (i, j), B = A + (1,
  // 0), C = A + (0, 1) in units of its level; a "down" cell A = (i + 1, j + 1), B = A − (1, 0), C =
  // A − (0, 1)).
  static void cell_point(const Cell& c, int qu, int qv, int& la, int& lb) {
    const int st = kLatticeRes >> (c.level + 2);
    la = c.up ? (4 * c.i + qu) * st : (4 * (c.i + 1) - qu) * st;
    lb = c.up ? (4 * c.j + qv) * st : (4 * (c.j + 1) - qv) * st;
  }
  const std::int32_t* lattice_at(int la, int lb);
  void edge_sample(int la, int lb, int lc, std::int32_t out[]);
  void prepare_edge_keys(const Triangle& tri);
  void find_terminators(const Triangle& tri);
  void cell_points(const Cell& c, const std::int32_t* v[15]);
  void shade_crossing(const Leaf& leaf, std::int64_t u, std::int64_t v, std::int32_t n,
                      Rgb8* out) const;
  TP_PIXEL_INLINE static inline void shade_terms(const SteppedQuadratic q[3], int crossings,
                                                 const Crossing* crossing, std::int64_t u,
                                                 std::int64_t v, std::int32_t n, Rgb8* out);
  template <std::size_t K>
  static void shade_crossings(const QuadStep st[], const Crossing* crossing, std::int32_t n,
                              Rgb8* out);
  Samples6 samples_of(const Cell& c, int ch) const;
  std::int64_t check_error(const Cell& c, std::int64_t nl_error[]);
  void refine(const Cell& c, bool guarded, std::uint32_t peaks);
  bool settle(const Cell& c, bool guarded);
  void mark(const Cell& c, std::uint16_t leaf);
  void choose_cheap_path(std::int64_t err0);
  int peak_level(const Cell& c, std::uint32_t& peaks);
  void add_leaf(const Cell& c, bool quadratic, const std::int64_t nl_error[], bool checked);
  Cell finest_cell(std::int64_t s, std::int64_t t) const;
  std::int64_t pixels_in(const Cell& c, std::int64_t s, std::int64_t t, std::int64_t ds,
                         std::int64_t dt) const;
  void shade_exact(std::int32_t y, std::int32_t xa, std::int32_t n, Rgb8* out) const;
  // n exact evaluations (pixels or samples), counted as counters.hpp defines them.
  void count_exact(std::int64_t n) const {
    counters_->lighting_evaluations += static_cast<std::uint64_t>(n);
    counters_->specular_evaluations +=
        static_cast<std::uint64_t>(n) * static_cast<std::uint64_t>(point_.lights());
  }
  void shade_cell(const Leaf& leaf, std::int64_t s, std::int64_t t, std::int32_t n,
                  Rgb8* out) const;
  void shade_pieces(const Span& s, std::int64_t e1, std::int64_t e2, Rgb8* out) const;
  void fill_quadratic(const SteppedQuadratic q[3], bool in_range, std::int64_t u, std::int64_t v,
                      std::int32_t n, Rgb8* out) const;

  AdaptiveMode mode_;
  PointShader point_;
  const Triangle* tri_ = nullptr;
  const ShadeContext* ctx_ = nullptr;
  Counters* counters_ = nullptr;
  Path path_ = Path::kConstant;
  int level_ = 0;
  Rgb8 constant_{0, 0, 0};
  SteppedQuadratic whole_[3];  // level 0: the triangle's quadratic per channel
  bool whole_in_range_ = false;
  std::int64_t du_ = 0, dv_ = 0;    // per pixel: dλ1/dx, dλ2/dx in Q.30
  std::int64_t de1_ = 0, de2_ = 0;  // per pixel: dE1, dE2 (exact edge-function steps)
  // ⌊2^60 / area2⌋: num / area2 in Q.30 as one product per span piece instead of a division;
  // relative error below area2·2^-60. num (an edge function at a pixel centre of the triangle,
  // within [0, area2]) is kept within [−area2, 2·area2] so that |num·recip| < 2^62 whatever
  // the caller passes; where that clamp fires it is counted (Counters::saturations, per piece).
  std::int64_t area_recip_ = 0;
  std::int64_t local_of(std::int64_t num) const {
    const std::int64_t area = tri_->area2;
    const std::int64_t kept = fx::clamp(num, -area, 2 * area);
    if (kept != num) ++counters_->saturations;
    num = kept;
    return (num * area_recip_ + (std::int64_t{1} << 29)) >> 30;
  }
  // The leaves of the subdivision, and the leaf holding each deepest-level cell.
  Leaf leaves_[kMaxLeaves];
  int leaf_count_ = 0;
  Crossing crossings_[kMaxCrossings];
  int crossing_count_ = 0;
  int terminators_ = 0;           // lights with their terminator handled
  bool every_terminator_ = true;  // no light's terminator left as a kink in the samples
  // The samples have no kink (every terminator handled, and no specular kink at N·H = 0, which
  // max(0, N·H)^n has for n = 1): the h³ law holds for refine's unchecked children.
  bool smooth_ = true;
  std::int64_t estimate_budget_ = kEstimatePerLevel;   // the check's threshold for this budget
  std::int64_t trusted_miss_ = kTrustedMissPerLevel;   // refine's, for unchecked children
  std::uint32_t terminator_mask_ = 0;                  // those lights (PointShader's light numbers)
  std::int64_t term_weight_[kMaxTerminators][3] = {};  // kd·O_c·Il_c, levels Q.14 per unit N·L
  std::int64_t term_worst_[kMaxTerminators] = {};      // max over c of term_weight_
  // Each terminator's fit over the cell classified last. add_leaf of the cell check_error has just
  // classified reuses it instead of fitting and classifying again. Here, not on the stack: 448
  // bytes on the Cortex-M (docs/DECISIONS.md, "kb-adaptive's leaves reuse their check's fits").
  TerminatorFit fits_[kMaxTerminators];
  std::uint16_t leaf_up_[1 << kMaxLevel][1 << kMaxLevel] = {};
  std::uint16_t leaf_down_[1 << kMaxLevel][1 << kMaxLevel] = {};
  std::uint32_t omega_n_ = 0;  // the exponent omega_ was made for
  std::int64_t omega_ = 0;     // 0.6/√n in Q.30 rad (peak_level)
  Lattice lattice_;
  // Samples on triangle edges, shared with the neighbours: keyed on the edge's vertices (in a
  // canonical order) and the position along it, in units of 1/kMemoScale.
  static constexpr std::int32_t kMemoScale = 1 << 16;
  static constexpr std::uint32_t kEdgeMemo = 256;
  struct EdgeMemo {
    VertexKey a, b;
    std::int32_t share = 0;
    std::uint32_t terminators = 0;  // the terminator mask the values were taken with
    std::int32_t value[kChannels] = {};
    bool valid = false;
  };
  EdgeMemo edge_memo_[kEdgeMemo];
  struct EdgeKeys {
    VertexKey key[3];
    bool swapped[3] = {false, false, false};
    std::uint32_t hash_first[3] = {0, 0, 0}, hash_second[3] = {0, 0, 0};
  };
  EdgeKeys edge_;  // the current triangle's (prepare_edge_keys)
  // The shading state the memo's values belong to: its revision (ShadeContext::revision).
  struct MemoContext {
    std::uint64_t revision = 0;
    bool valid = false;
    bool same(const ShadeContext& c) const { return valid && c.revision == revision; }
    void take(const ShadeContext& c) {
      revision = c.revision;
      valid = true;
    }
  };
  MemoContext memo_context_;
};

}  // namespace tp::fw::kb
