// kb-adaptive: per triangle, the cheapest evaluation that stays within the error budget
// (kb_adaptive.hpp; the derivation and the measurements are in docs/KUIJK-BLAKE.md,
// "kb-adaptive").
//
// Setup: a triangle under 64 pixels is evaluated per pixel at once; else the highlight guard and
// the terminators (kb_adaptive_caps.cpp), exact samples on the triangle's quarter lattice (the
// six points of the quadratic and the nine check points), then
//   1. the quadratic passes its check → constant, linear or quadratic, the simplest whose added
//      error keeps the estimate within the budget;
//   2. else, a small triangle (fewer pixels than the samples refining would take) → per pixel;
//   3. else subdivision: each cell that fails its check is split into four, down to 4^4 cells,
//      reusing its check points as the children's samples; a deepest cell that still fails is
//      evaluated per pixel.
// Terminators crossing a triangle are sampled unclamped and clamped per pixel (add_leaf).
// Span: the pieces of the span in each leaf cell, each seeded once and forward-differenced.
#include "firmware/kb/kb_adaptive.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <utility>

#include "firmware/build.hpp"
#include "firmware/interp.hpp"
#include "firmware/lighting.hpp"
#include "firmware/raster.hpp"
#include "firmware/vecmath.hpp"
#include "fixedpoint/divide.hpp"

namespace tp::fw::kb {
namespace {

std::int64_t abs64(std::int64_t v) { return v < 0 ? -v : v; }

// Pixels until q (now in [lo, hi)) leaves that interval when it moves by dq per pixel.
TP_PIXEL_INLINE inline std::int64_t steps_inside(std::int64_t q, std::int64_t dq, std::int64_t lo,
                                                 std::int64_t hi) {
  constexpr std::int64_t kForever = std::int64_t{1} << 40;
  if (dq > 0) return ceil_div(hi - q, dq);
  if (dq < 0) return floor_div(q - lo, -dq) + 1;
  return kForever;
}

// A quadratic's largest departure from its value at A over the triangle (u, v >= 0,
// u + v <= 1): |c_u| + |c_v| + |c_uu| + |c_vv| + |c_uv| bounds it.
std::int64_t spread_bound(const LocalQuadratic& q) {
  return abs64(q.cu) + abs64(q.cv) + abs64(q.cuu) + abs64(q.cvv) + abs64(q.cuv);
}

// The linear interpolant through the vertices differs from the quadratic by
// c_uu (u² − u) + c_vv (v² − v) + c_uv u v, at most (|c_uu| + |c_vv| + |c_uv|) / 4.
std::int64_t curvature_bound(const LocalQuadratic& q) {
  return (abs64(q.cuu) + abs64(q.cvv) + abs64(q.cuv) + 3) / 4;
}

// Whether a quadratic stays inside [0, 255.5) levels over its cell — then the pixel loop needs
// no clamp: it lies within (|c_uu| + |c_vv| + |c_uv|) / 4 of the plane through its vertex values
// (curvature_bound), plus a level of margin for the stepping's rounding. Size builds have one
// pixel loop, which clamps (fill_quadratic), and leave the test out.
bool inside_levels(const LocalQuadratic& q) {
  if constexpr (kSizeBuild) return false;
  const std::int64_t a = q.c0, b = q.c0 + q.cu + q.cuu, c = q.c0 + q.cv + q.cvv;  // q at A, B, C
  const std::int64_t lo = a < b ? (a < c ? a : c) : (b < c ? b : c);
  const std::int64_t hi = a > b ? (a > c ? a : c) : (b > c ? b : c);
  const std::int64_t slack = curvature_bound(q) + (std::int64_t{1} << kSampleFrac);
  return lo - slack >= 0 && hi + slack < (std::int64_t{255} << kSampleFrac);
}

LocalQuadratic linear_of(const LocalQuadratic& q) {
  return LocalQuadratic{q.c0, q.cu + q.cuu, q.cv + q.cvv, 0, 0, 0};
}

// Samples of the quarter lattice of level k: (4·2^k + 1)(4·2^k + 2) / 2.
std::int64_t lattice_samples_at(int k) {
  const std::int64_t r = std::int64_t{4} << k;
  return (r + 1) * (r + 2) / 2;
}

}  // namespace

// The value at lattice point (la, lb) of the deepest quarter lattice, evaluated on first use in
// this triangle (every cell's points lie on it; neighbouring cells share theirs).
const std::int32_t* KbAdaptiveMethod::lattice_at(int la, int lb) {
  const int i = index(la, lb);
  if (lattice_.stamp[i] != lattice_.generation) {
    const int lc = kLatticeRes - la - lb;
    if (la == 0 || lb == 0 || lc == 0)
      edge_sample(la, lb, lc, lattice_.value[i]);
    else {
      point_.shade(point_.point(lc, la, lb), lattice_.value[i], terminator_mask_);
      ++counters_->lattice_samples;
      count_exact(1);
    }
    lattice_.stamp[i] = lattice_.generation;
  }
  return lattice_.value[i];
}

namespace {
KbAdaptiveMethod::VertexKey key_of(const ShadeVertex& v) {
  return {
      v.sx,      v.sy,          v.z,           v.normal.x.raw(), v.normal.y.raw(), v.normal.z.raw(),
      v.w.raw(), v.eye.x.raw(), v.eye.y.raw(), v.eye.z.raw()};
}
bool before(const KbAdaptiveMethod::VertexKey& a, const KbAdaptiveMethod::VertexKey& b) {
  if (a.sx != b.sx) return a.sx < b.sx;
  if (a.sy != b.sy) return a.sy < b.sy;
  if (a.z != b.z) return a.z < b.z;
  if (a.nx != b.nx) return a.nx < b.nx;
  if (a.ny != b.ny) return a.ny < b.ny;
  if (a.nz != b.nz) return a.nz < b.nz;
  if (a.w != b.w) return a.w < b.w;
  if (a.ex != b.ex) return a.ex < b.ex;
  if (a.ey != b.ey) return a.ey < b.ey;
  return a.ez < b.ez;
}
}  // namespace

// A sample on the triangle's boundary: a function of the edge's two vertices alone
// (PointShader::edge_point), so that neighbouring triangles share it through the memo, keyed on
// everything the value depends on: both vertices (screen position, depth, w, normal, eye-space
// position), the position along the edge and the set of terminator lights; the memo is emptied
// when the material, a light or the eye mode changes. out: the lattice's kChannels.
void KbAdaptiveMethod::edge_sample(int la, int lb, int lc, std::int32_t out[]) {
  // Barycentric weights (vertex 0, 1, 2) = (lc, la, lb); the edge holds the two non-zero ones,
  // and they add up to kLatticeRes.
  int a = 0, b = 1;
  std::int64_t ka = lc, kb = la;
  if (la == 0) {
    a = 0, b = 2, ka = lc, kb = lb;
  } else if (lc == 0) {
    a = 1, b = 2, ka = la, kb = lb;
  }
  if (ka == 0 || kb == 0) {  // a vertex: both ends the same
    a = b = ka == 0 ? b : a;
    ka = kb = kLatticeRes / 2;
  } else if (edge_.swapped[a + b - 1]) {  // canonical order, so that either triangle finds it
    const int v = a;
    a = b;
    b = v;
    const std::int64_t w = ka;
    ka = kb;
    kb = w;
  }
  const VertexKey& key_a = edge_.key[a];
  const VertexKey& key_b = edge_.key[b];
  const auto share = static_cast<std::int32_t>(ka * (kMemoScale / kLatticeRes));  // of kMemoScale
  const std::uint32_t h =
      edge_.hash_first[a] ^ edge_.hash_second[b] ^ static_cast<std::uint32_t>(share) * 40503u;
  EdgeMemo& m = edge_memo_[(h ^ (h >> 15)) % kEdgeMemo];
  // The colours, then the N·L of the terminators (whose diffuse the colours leave unclamped):
  // the values depend on which lights are terminators, so the memo's key holds that set too.
  const int channels = 3 + terminators_;
  if (m.valid && m.share == share && m.terminators == terminator_mask_ && m.a == key_a &&
      m.b == key_b) {
    for (int c = 0; c < channels; ++c) out[c] = m.value[c];
    return;
  }
  point_.shade(point_.edge_point(a, b, ka, kb), out, terminator_mask_);
  ++counters_->lattice_samples;
  count_exact(1);
  m.a = key_a;
  m.b = key_b;
  m.share = share;
  m.terminators = terminator_mask_;
  for (int c = 0; c < channels; ++c) m.value[c] = out[c];
  m.valid = true;
}

// The memo's keys of the triangle's vertices, the canonical order of each edge (edge a + b − 1
// joins a < b) and the vertices' parts of the memo's hash: once per triangle, not per sample.
void KbAdaptiveMethod::prepare_edge_keys(const Triangle& tri) {
  for (int i = 0; i < 3; ++i) {
    edge_.key[i] = key_of(tri.v[i]);
    const auto x = static_cast<std::uint32_t>(tri.v[i].sx),
               y = static_cast<std::uint32_t>(tri.v[i].sy);
    edge_.hash_first[i] = x * 73856093u ^ y * 19349663u;
    edge_.hash_second[i] = x * 83492791u ^ y * 2654435761u;
  }
  edge_.swapped[0] = before(edge_.key[1], edge_.key[0]);
  edge_.swapped[1] = before(edge_.key[2], edge_.key[0]);
  edge_.swapped[2] = before(edge_.key[2], edge_.key[1]);
}

// The six samples of a cell, channel ch (already evaluated: the cell was checked).
Samples6 KbAdaptiveMethod::samples_of(const Cell& cell, int ch) const {
  const auto at = [&](int qu, int qv) {
    int a = 0, b = 0;
    cell_point(cell, qu, qv, a, b);
    return lattice_.value[index(a, b)][ch];
  };
  return Samples6{{at(0, 0), at(4, 0), at(0, 4), at(2, 0), at(2, 2), at(0, 2)}};
}

// The fifteen points of a cell's quarter lattice (six samples, then the nine checks), evaluated
// where needed.
void KbAdaptiveMethod::cell_points(const Cell& cell, const std::int32_t* v[15]) {
  static constexpr std::int8_t kQuarters[15][2] = {{0, 0}, {4, 0}, {0, 4}, {2, 0}, {2, 2},
                                                   {0, 2}, {1, 0}, {3, 0}, {0, 1}, {0, 3},
                                                   {3, 1}, {1, 3}, {1, 1}, {2, 1}, {1, 2}};
  for (int k = 0; k < 15; ++k) {
    int a = 0, b = 0;
    cell_point(cell, kQuarters[k][0], kQuarters[k][1], a, b);
    v[k] = lattice_at(a, b);
  }
}

namespace {
// 8·|g − q| at check point K: its weights are compile-time constants, so the zero ones (the
// edge points') and the small ones fold away.
template <std::size_t K>
std::int64_t point_error(const std::int64_t s[6], const std::int32_t* const v[15], int ch) {
  constexpr SampleWeights w = kCheckWeights[K];
  const std::int64_t q8 =
      w.w[0] * s[0] + w.w[1] * s[1] + w.w[2] * s[2] + w.w[3] * s[3] + w.w[4] * s[4] + w.w[5] * s[5];
  return abs64(8 * std::int64_t{v[6 + K][ch]} - q8);
}
template <std::size_t... K>
std::int64_t worst_point_error(const std::int64_t s[6], const std::int32_t* const v[15], int ch,
                               std::index_sequence<K...>) {
  std::int64_t worst = 0;
  ((worst = std::max(worst, point_error<K>(s, v, ch))), ...);
  return worst;
}
// The same weights as small integers, for size builds' loop over the check points (54 bytes of
// table instead of nine specialised copies of the sum).
static_assert([] {
  for (const SampleWeights& p : kCheckWeights)
    for (const std::int64_t w : p.w)
      if (w < -128 || w > 127) return false;
  return true;
}());
inline constexpr auto kCheckWeights8 = [] {
  std::array<std::array<std::int8_t, 6>, 9> t{};
  for (std::size_t k = 0; k < 9; ++k)
    for (std::size_t j = 0; j < 6; ++j) t[k][j] = static_cast<std::int8_t>(kCheckWeights[k].w[j]);
  return t;
}();
// max over the nine check points of |g − q| for channel ch (rounded up).
std::int64_t channel_error(const std::int32_t* const v[15], int ch) {
  const std::int64_t s[6] = {v[0][ch], v[1][ch], v[2][ch], v[3][ch], v[4][ch], v[5][ch]};
  if constexpr (kSizeBuild) {
    std::int64_t worst = 0;
    for (std::size_t k = 0; k < 9; ++k) {
      std::int64_t q8 = 0;
      for (std::size_t j = 0; j < 6; ++j) q8 += kCheckWeights8[k][j] * s[j];
      worst = std::max(worst, abs64(8 * std::int64_t{v[6 + k][ch]} - q8));
    }
    return (worst + 7) / 8;
  } else {
    return (worst_point_error(s, v, ch, std::make_index_sequence<9>{}) + 7) / 8;
  }
}

// How a terminator's N·L behaves over a cell, from its six samples: the exact N·L keeps its sign
// where the quadratic through them does over the cell (their range widened by the quadratic's
// departure from the vertex plane), widened again by a bound on the quadratic's error (err: its
// error at the cell's check points, or its parent's) and 2^-12.
TerminatorSign terminator_sign(const Samples6& samples, std::int64_t err, LocalQuadratic& nl) {
  nl = fit_quadratic(samples);
  std::int64_t lo = samples.g[0], hi = samples.g[0];
  for (int k = 1; k < 6; ++k) {
    lo = samples.g[k] < lo ? samples.g[k] : lo;
    hi = samples.g[k] > hi ? samples.g[k] : hi;
  }
  const std::int64_t slack = curvature_bound(nl) + err + (std::int64_t{1} << 12);
  if (lo - slack > 0) return TerminatorSign::kLit;
  if (hi + slack < 0) return TerminatorSign::kDark;
  return TerminatorSign::kCrossing;
}
}  // namespace

// The error estimate of a cell, Q.14 levels: the worst colour channel, plus for each terminator
// that is not lit over the whole cell its N·L error (Q.24) times its heaviest channel weight —
// max(0, ·) is 1-Lipschitz. A lit one adds nothing: its unclamped diffuse in the colours is the
// exact one there (add_leaf makes the same test).
// nl_error[t]: terminator t's N·L error at the check points (Q.24), for add_leaf; fits_[t] its
// N·L quadratic and sign over the cell, which add_leaf of this same cell reuses.
std::int64_t KbAdaptiveMethod::check_error(const Cell& cell, std::int64_t nl_error[]) {
  const std::int32_t* v[15];
  cell_points(cell, v);
  std::int64_t crossing = 0;
  std::uint32_t dark = 0;
  for (int t = 0; t < terminators_; ++t) {
    const std::int64_t err = channel_error(v, 3 + t);
    nl_error[t] = err;
    const int ch = 3 + t;
    const TerminatorSign sign = fits_[t].sign = terminator_sign(
        Samples6{{v[0][ch], v[1][ch], v[2][ch], v[3][ch], v[4][ch], v[5][ch]}}, err, fits_[t].nl);
    if (sign == TerminatorSign::kDark) dark |= 1u << t;
    if (sign == TerminatorSign::kCrossing)
      crossing += (err * term_worst_[t] + (std::int64_t{1} << 24) - 1) >> 24;
  }
  // The colours as the leaf will have them: without the diffuse of the lights dark over the cell
  // (add_leaf takes it off the quadratic's coefficients, rounded apart: within a few 2^-14 of a
  // level of these points' values).
  std::int32_t adjusted[15][3];
  const std::int32_t* a[15];
  if (dark != 0) {
    for (int k = 0; k < 15; ++k) {
      for (int ch = 0; ch < 3; ++ch) adjusted[k][ch] = v[k][ch];
      a[k] = adjusted[k];
    }
    for (std::uint32_t m = dark; m != 0; m &= m - 1) {
      const int t = std::countr_zero(m);
      const std::int64_t w0 = term_weight_[t][0], w1 = term_weight_[t][1], w2 = term_weight_[t][2];
      for (int k = 0; k < 15; ++k) {
        const std::int64_t nl = v[k][3 + t];
        adjusted[k][0] -= static_cast<std::int32_t>((w0 * nl) >> 24);
        adjusted[k][1] -= static_cast<std::int32_t>((w1 * nl) >> 24);
        adjusted[k][2] -= static_cast<std::int32_t>((w2 * nl) >> 24);
      }
    }
  }
  std::int64_t worst = 0;
  for (int ch = 0; ch < 3; ++ch) {
    const std::int64_t e = channel_error(dark != 0 ? a : v, ch);
    if (e > worst) worst = e;
  }
  return worst + crossing;
}

namespace {
void children_of(const KbAdaptiveMethod::Cell& c, KbAdaptiveMethod::Cell out[4]) {
  const int l = c.level + 1, i = 2 * c.i, j = 2 * c.j;
  if (c.up) {
    out[0] = {l, i, j, true};
    out[1] = {l, i + 1, j, true};
    out[2] = {l, i, j + 1, true};
    out[3] = {l, i, j, false};
  } else {
    out[0] = {l, i + 1, j + 1, false};
    out[1] = {l, i, j + 1, false};
    out[2] = {l, i + 1, j, false};
    out[3] = {l, i + 1, j + 1, true};
  }
}
}  // namespace

// Records leaf number `leaf` for every deepest-level cell inside `c`. The whole triangle as its
// only leaf needs no map (shade_span reads leaves_[0]). A cell of level L spans m = 2^(D − L)
// deepest steps: an "up" cell (i, j) holds the deepest up cells (a, b) with a >= m·i, b >= m·j,
// (a − m·i) + (b − m·j) <= m − 1 and the down cells with the same offsets summing to <= m − 2;
// a "down" cell the same counted back from its corner (m(i + 1) − 1, m(j + 1) − 1), with the
// roles of up and down exchanged.
void KbAdaptiveMethod::mark(const Cell& c, std::uint16_t leaf) {
  if (c.level == 0) return;
  const int m = 1 << (kMaxLevel - c.level);
  auto& same = c.up ? leaf_up_ : leaf_down_;
  auto& other = c.up ? leaf_down_ : leaf_up_;
  for (int db = 0; db < m; ++db)
    for (int da = 0; da + db <= m - 1; ++da) {
      const int a = c.up ? m * c.i + da : m * (c.i + 1) - 1 - da;
      const int b = c.up ? m * c.j + db : m * (c.j + 1) - 1 - db;
      same[b][a] = leaf;
      if (da + db <= m - 2) other[b][a] = leaf;
    }
}

// Makes c a leaf: its quadratics, or per-pixel evaluation. A terminator whose N·L keeps one
// sign over the cell needs no clamp there: lit, its unclamped diffuse is exact; dark, the
// exact diffuse is 0, so its N·L quadratic times the weights is taken off the colours'.
// nl_error[t]: a bound on terminator t's N·L error at the check points (check_error's).
// checked: c is the cell check_error looked at last, so its terminators' fits are in fits_;
// otherwise they are made here (into fits_ too). Read only for a quadratic leaf.
void KbAdaptiveMethod::add_leaf(const Cell& c, bool quadratic, const std::int64_t nl_error[],
                                bool checked) {
  if (path_ == Path::kSubdivided) ++counters_->subtriangles;  // (not a whole-triangle leaf)
  if (!quadratic) ++counters_->subtriangles_exact;
  Leaf& leaf = leaves_[leaf_count_];
  leaf.cell = c;
  leaf.exact = !quadratic;
  leaf.crossing = 0;
  if (quadratic) {
    // Steps in the cell's own coordinates: 2^level times the triangle's, reversed in a "down"
    // cell (its u, v run from the opposite corner).
    const std::int64_t scale = c.up ? std::int64_t{1} << c.level : -(std::int64_t{1} << c.level);
    const std::int64_t du = du_ * scale, dv = dv_ * scale;
    LocalQuadratic q[3];
    for (int ch = 0; ch < 3; ++ch) q[ch] = fit_quadratic(samples_of(c, ch));
    // The crossings go straight into the pool, past its used part (committed below if they all
    // fit): a local array of kMaxTerminators of them was 1.4 KB of a small part's stack.
    int crossings = 0;
    bool pool_full = false;
    for (int t = 0; t < terminators_; ++t) {
      TerminatorFit& fit = fits_[t];
      if (!checked) fit.sign = terminator_sign(samples_of(c, 3 + t), nl_error[t], fit.nl);
      const TerminatorSign sign = fit.sign;
      const LocalQuadratic& nl = fit.nl;
      if (sign == TerminatorSign::kLit) continue;
      if (sign == TerminatorSign::kDark) {
        for (int ch = 0; ch < 3; ++ch) {
          const std::int64_t w = term_weight_[t][ch];
          q[ch].c0 -= (w * nl.c0) >> 24;
          q[ch].cu -= (w * nl.cu) >> 24;
          q[ch].cv -= (w * nl.cv) >> 24;
          q[ch].cuu -= (w * nl.cuu) >> 24;
          q[ch].cvv -= (w * nl.cvv) >> 24;
          q[ch].cuv -= (w * nl.cuv) >> 24;
        }
        continue;
      }
      if (crossing_count_ + crossings >= kMaxCrossings) {
        pool_full = true;
        ++crossings;
        continue;
      }
      Crossing& x = crossings_[crossing_count_ + crossings++];
      x.nl = prepare_steps(nl, du, dv);
      for (int ch = 0; ch < 3; ++ch) x.weight[ch] = term_weight_[t][ch];
    }
    if (pool_full) {
      leaf.exact = true;  // the pool is full: per pixel (exact, only dearer)
      ++counters_->subtriangles_exact;
      mark(c, static_cast<std::uint16_t>(leaf_count_++));
      return;
    }
    leaf.first = static_cast<std::uint16_t>(crossing_count_);
    leaf.crossing = static_cast<std::uint8_t>(crossings);
    crossing_count_ += crossings;
    if (crossings > 0) ++counters_->terminator_cells;
    leaf.in_range = true;
    for (int ch = 0; ch < 3; ++ch) {
      leaf.in_range = leaf.in_range && inside_levels(q[ch]);
      leaf.q[ch] = prepare_steps(q[ch], du, dv);
    }
  }
  mark(c, static_cast<std::uint16_t>(leaf_count_++));
}

// A cell is a leaf once its samples are dense enough for the highlights (peak_level, checked
// while `guarded`: a cell that passes guarantees it for its descendants) and its check passes; at
// the deepest level a cell that fails either is evaluated per pixel. `peaks`: the lights whose
// highlight may lie on the parent — no other can lie on c, which lies inside it.
//
// A cell of the level above the deepest that misses by at most trusted_miss_ makes its four
// children leaves without checking them: their six samples are its fifteen points, and by the
// h³ law of quadratic interpolation halving the size divides a smooth error by 8 — their own check
// points, a quarter of the samples of the deepest level, would cost more than they tell
// (docs/KUIJK-BLAKE.md). Only where the samples have no kink (smooth_), across which halving
// divides the error by 2 only; the children's terminators are classified with the parent's N·L
// errors, larger than theirs.
void KbAdaptiveMethod::refine(const Cell& c, bool guarded, std::uint32_t peaks) {
  if (guarded && peak_level(c, peaks) == c.level) guarded = false;
  if ((!guarded || c.level == kMaxLevel) && settle(c, guarded)) return;
  Cell kids[4];
  children_of(c, kids);
  for (const Cell& k : kids) refine(k, guarded, peaks);
}

// refine's leaves: c, or its children unchecked, when its check allows (false: refine further).
// Not inlined, so that the check's and the leaf's frames are not stacked once per level of
// refine's recursion (a small part's stack: docs/TARGET.md).
[[gnu::noinline]] bool KbAdaptiveMethod::settle(const Cell& c, bool guarded) {
  std::int64_t nl_error[kMaxTerminators] = {};
  const std::int64_t err = guarded ? 0 : check_error(c, nl_error);
  const bool passes = !guarded && err <= estimate_budget_;
  if (passes || c.level == kMaxLevel) {
    // checked: a guarded cell was not, but then it is no quadratic leaf and needs no fits.
    add_leaf(c, passes, nl_error, true);
    return true;
  }
  if (smooth_ && c.level == kMaxLevel - 1 && err <= trusted_miss_) {
    counters_->subtriangles_unchecked += 4;
    Cell kids[4];
    children_of(c, kids);
    for (const Cell& k : kids) add_leaf(k, true, nl_error, false);
    return true;
  }
  return false;
}

// Level 0 passed its check (estimate err0): the simplest of constant, linear and quadratic
// within the budget.
void KbAdaptiveMethod::choose_cheap_path(std::int64_t err0) {
  bool constant = true, linear = true;
  LocalQuadratic q[3];
  whole_in_range_ = true;
  for (int c = 0; c < 3; ++c) {
    const Samples6 samples = samples_of(kWhole, c);
    q[c] = fit_quadratic(samples);
    const LocalQuadratic lin = linear_of(q[c]);
    constant = constant && err0 + curvature_bound(q[c]) + spread_bound(lin) <= estimate_budget_;
    linear = linear && err0 + curvature_bound(q[c]) <= estimate_budget_;
  }
  if (constant) {
    path_ = Path::kConstant;
    ++counters_->adaptive_constant;
    for (LocalQuadratic& c : q) c = LocalQuadratic{c.c0, 0, 0, 0, 0, 0};
    whole_in_range_ = false;  // (filled, or stepped with the clamp by the no-skip variant)
    const auto level = [](std::int64_t g) {
      return quad_level(g * (std::int64_t{1} << (kQuadStateFrac - kSampleFrac)));
    };
    constant_ = Rgb8{level(q[0].c0), level(q[1].c0), level(q[2].c0)};
  } else if (linear) {
    path_ = Path::kLinear;
    ++counters_->adaptive_linear;
    for (LocalQuadratic& c : q) c = linear_of(c);
  } else {
    path_ = Path::kQuadratic;
    ++counters_->adaptive_quadratic;
  }
  if (path_ != Path::kConstant)
    for (int c = 0; c < 3; ++c) whole_in_range_ = whole_in_range_ && inside_levels(q[c]);
  for (int c = 0; c < 3; ++c) whole_[c] = prepare_steps(q[c], du_, dv_);
}

bool KbAdaptiveMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  tri_ = &tri;
  ctx_ = &ctx;
  counters_ = ctx.counters;
  level_ = 0;
  if (++lattice_.generation == 0) {  // wrapped: forget every stamp
    for (std::uint32_t& st : lattice_.stamp) st = 0;
    lattice_.generation = 1;
  }
  point_.setup(tri, ctx, mode_ == AdaptiveMode::kAdaptive);
  // The boundary samples' memo holds values of this material, these lights and this eye only.
  if (!memo_context_.same(ctx)) {
    for (EdgeMemo& m : edge_memo_) m.valid = false;
    memo_context_.take(ctx);
  }
  // A triangle of fewer than 64 pixels is cheaper evaluated exactly at every pixel than sampled
  // and checked, whatever the check would say (about nine of its fifteen samples are its own on
  // a mesh; docs/KUIJK-BLAKE.md has the measurements).
  if (mode_ == AdaptiveMode::kExactOnly || tri.area2 < kDirectExactArea2) {
    path_ = Path::kExact;
    ++counters_->adaptive_exact;
    return true;
  }
  const Lambdas step = lambdas_step_x(tri);
  de1_ = step.l[1];
  de2_ = step.l[2];
  // Per-pixel steps of λ1, λ2 (Q.30); a cell of level L steps by 2^L times these.
  du_ = fx::div<local_t>(fx::int_q::from_raw(de1_), fx::int_q::from_raw(tri.area2)).raw();
  dv_ = fx::div<local_t>(fx::int_q::from_raw(de2_), fx::int_q::from_raw(tri.area2)).raw();
  area_recip_ = fx::idiv(std::int64_t{1} << 60, tri.area2);
  find_terminators(tri);
  smooth_ = every_terminator_ && (ctx.material.ks.raw() == 0 || ctx.material.n >= 2);
  const std::int64_t budget = ctx.budget_levels >= 1 ? ctx.budget_levels : 1;
  estimate_budget_ = kEstimatePerLevel * budget;
  trusted_miss_ = kTrustedMissPerLevel * budget;
  prepare_edge_keys(tri);
  std::uint32_t peaks = ~std::uint32_t{0};  // every light, until the guard narrows it
  const int guard = peak_level(kWhole, peaks);
  std::int64_t nl_error[kMaxTerminators] = {};
  const std::int64_t err0 = guard == 0 ? check_error(kWhole, nl_error) : 0;
  if (guard == 0 && err0 <= estimate_budget_ && terminators_ == 0) {
    choose_cheap_path(err0);
  } else if (guard == 0 && err0 <= estimate_budget_) {
    // One quadratic, with the terminators' clamps: the triangle is its own leaf.
    path_ = Path::kQuadratic;
    ++counters_->adaptive_quadratic;
    level_ = kMaxLevel;
    leaf_count_ = 0;
    crossing_count_ = 0;
    add_leaf(kWhole, true, nl_error, true);
  } else {
    // The cost of refining, guessed from the guard and from the h³ law of quadratic
    // interpolation (each halving of the size divides the error by 8) applied to err0,
    // against the pixels: a small triangle is cheaper per pixel.
    int k = guard > 1 ? (guard > kMaxLevel ? kMaxLevel : guard) : 1;
    if (guard == 0)
      while (k < kMaxLevel && (err0 >> (3 * k)) > estimate_budget_) ++k;
    const std::int64_t pixels = tri.area2 / (2 * 256);
    if (pixels <= lattice_samples_at(k)) {
      path_ = Path::kExact;
      ++counters_->adaptive_exact;
      return true;
    }
    path_ = Path::kSubdivided;
    ++counters_->adaptive_subdivided;
    level_ = kMaxLevel;
    leaf_count_ = 0;
    crossing_count_ = 0;
    refine(kWhole, guard > 0, peaks);
  }
  return true;
}

void KbAdaptiveMethod::fill_quadratic(const SteppedQuadratic q[3], bool in_range, std::int64_t u,
                                      std::int64_t v, std::int32_t n, Rgb8* out) const {
  if constexpr (kSizeBuild) {
    // shade_terms with no terminator: the same seeds and steps, and its quad_level rounds
    // in-range values as the loop below does (firmware/build.hpp).
    shade_terms(q, 0, nullptr, u, v, n, out);
    return;
  }
  QuadStep r, g, b;
  if (n <= kShortPiece) {
    // The channels share their steps (one cell): the monomials at the first two pixels, once.
    // (The second pixel's only where there is one: a one-pixel piece's steps may point far
    // outside the cell.)
    const Monomials at = monomials(u, v);
    const Monomials second = n > 1 ? monomials(u + q[0].du, v + q[0].dv) : at;
    const Monomials* next = n > 1 ? &second : nullptr;
    r = seed_short(q[0], at, next);
    g = seed_short(q[1], at, next);
    b = seed_short(q[2], at, next);
  } else {
    r = seed_quadratic(q[0], u, v, n);
    g = seed_quadratic(q[1], u, v, n);
    b = seed_quadratic(q[2], u, v, n);
  }
  std::int64_t rv = r.v, rd = r.d1, gv = g.v, gd = g.d1, bv = b.v, bd = b.d1;
  if (in_range) {
    // Every value of the cell's quadratics is inside [0, 255.5): rounding alone.
    constexpr std::int64_t half = std::int64_t{1} << (kQuadStateFrac - 1);
    for (std::int32_t x = 0; x < n; ++x) {
      out[x] = Rgb8{static_cast<std::uint8_t>((rv + half) >> kQuadStateFrac),
                    static_cast<std::uint8_t>((gv + half) >> kQuadStateFrac),
                    static_cast<std::uint8_t>((bv + half) >> kQuadStateFrac)};
      rv += rd;  // forward differences: two additions per channel
      rd += r.d2;
      gv += gd;
      gd += g.d2;
      bv += bd;
      bd += b.d2;
    }
    return;
  }
  for (std::int32_t x = 0; x < n; ++x) {
    out[x] = Rgb8{quad_level(rv), quad_level(gv), quad_level(bv)};
    rv += rd;
    rd += r.d2;
    gv += gd;
    gd += g.d2;
    bv += bd;
    bd += b.d2;
  }
}

// The deepest-level cell that holds the point (s, t) = 2^kMaxLevel·(e1, e2) (λ1 = e1 / area2, …):
// i <= s / area2 < i + 1, j <= t / area2 < j + 1, "up" below the diagonal s + t = (i + j +
// 1)·area2. Points on the triangle's own edges are clamped into it.
TP_PIXEL_INLINE inline KbAdaptiveMethod::Cell KbAdaptiveMethod::finest_cell(std::int64_t s,
                                                                            std::int64_t t) const {
  const std::int64_t area = tri_->area2, cells = std::int64_t{1} << kMaxLevel;
  std::int64_t i = floor_div(s, area), j = floor_div(t, area);
  i = i < 0 ? 0 : (i > cells - 1 ? cells - 1 : i);
  j = j < 0 ? 0 : (j > cells - 1 - i ? cells - 1 - i : j);
  const bool up = s + t < (i + j + 1) * area || i + j == cells - 1;
  return Cell{kMaxLevel, static_cast<int>(i), static_cast<int>(j), up};
}

// Pixels until the point (s, t), in units of cell c's level and stepping by (ds, dt), leaves c.
TP_PIXEL_INLINE inline std::int64_t KbAdaptiveMethod::pixels_in(const Cell& c, std::int64_t s,
                                                                std::int64_t t, std::int64_t ds,
                                                                std::int64_t dt) const {
  const std::int64_t area = tri_->area2;
  std::int64_t len = steps_inside(s, ds, c.i * area, (c.i + 1) * area);
  const std::int64_t lt = steps_inside(t, dt, c.j * area, (c.j + 1) * area);
  len = lt < len ? lt : len;
  const std::int64_t diag = (c.i + c.j + 1) * area, dd = ds + dt;
  if (c.up && dd > 0) {
    const std::int64_t ld = ceil_div(diag - s - t, dd);
    len = ld < len ? ld : len;
  }
  if (!c.up && dd < 0) {
    const std::int64_t ld = floor_div(s + t - diag, -dd) + 1;
    len = ld < len ? ld : len;
  }
  return len < 1 ? 1 : len;
}

// Pixels [xa, xa + n) of row y inside cell c, from the point (s, t) at xa in units of c's level:
// the cell's quadratic, seeded once and forward-differenced.
TP_PIXEL_INLINE inline void KbAdaptiveMethod::shade_cell(const Leaf& leaf, std::int64_t s,
                                                         std::int64_t t, std::int32_t n,
                                                         Rgb8* out) const {
  const Cell& c = leaf.cell;
  const std::int64_t area = tri_->area2;
  const std::int64_t nu = c.up ? s - c.i * area : (c.i + 1) * area - s;
  const std::int64_t nv = c.up ? t - c.j * area : (c.j + 1) * area - t;
  const std::int64_t u = local_of(nu), v = local_of(nv);
  if (leaf.crossing > 0)
    shade_crossing(leaf, u, v, n, out);
  else
    fill_quadratic(leaf.q, leaf.in_range, u, v, n, out);
}

// The colours' quadratics q plus, per crossing terminator, its weights times max(0, −N·L), N·L
// forward-differenced like the colours. With no crossing it is fill_quadratic's clamped loop,
// which a size build takes it for.
void KbAdaptiveMethod::shade_terms(const SteppedQuadratic q[3], int crossings,
                                   const Crossing* crossing, std::int64_t u, std::int64_t v,
                                   std::int32_t n, Rgb8* out) {
  QuadStep st[3 + kMaxTerminators];
  if (n <= kShortPiece) {
    const Monomials at = monomials(u, v);
    const Monomials second = n > 1 ? monomials(u + q[0].du, v + q[0].dv) : at;
    const Monomials* next = n > 1 ? &second : nullptr;
    for (int c = 0; c < 3; ++c) st[c] = seed_short(q[c], at, next);
    for (int k = 0; k < crossings; ++k) st[3 + k] = seed_short(crossing[k].nl, at, next);
  } else {
    for (int c = 0; c < 3; ++c) st[c] = seed_quadratic(q[c], u, v, n);
    for (int k = 0; k < crossings; ++k) st[3 + k] = seed_quadratic(crossing[k].nl, u, v, n);
  }
  // The common cases with their loops unrolled (the states in registers), in speed builds
  // (firmware/build.hpp).
  if constexpr (!kSizeBuild) {
    switch (crossings) {
      case 1: shade_crossings<1>(st, crossing, n, out); return;
      case 2: shade_crossings<2>(st, crossing, n, out); return;
      case 3: shade_crossings<3>(st, crossing, n, out); return;
      default: break;
    }
  }
  const int count = 3 + crossings;
  for (std::int32_t x = 0; x < n; ++x) {
    std::int64_t colour[3] = {st[0].v, st[1].v, st[2].v};
    for (int k = 0; k < crossings; ++k) {
      // N·L: Q.24 samples stepped in the state's scale (× 2^(40 − 14)); below zero the diffuse
      // was left out of the colours.
      const std::int64_t nl = st[3 + k].v;
      if (nl >= 0) continue;
      const std::int64_t dark = (-nl) >> (kQuadStateFrac - kSampleFrac);  // Q.24
      for (int c = 0; c < 3; ++c)                                         // Q.24 × Q.14 -> Q.40
        colour[c] += (dark * crossing[k].weight[c]) << (kQuadStateFrac - 24 - kSampleFrac);
    }
    out[x] = Rgb8{quad_level(colour[0]), quad_level(colour[1]), quad_level(colour[2])};
    for (int i = 0; i < count; ++i) {
      st[i].v += st[i].d1;
      st[i].d1 += st[i].d2;
    }
  }
}

// A cell that terminators cross.
void KbAdaptiveMethod::shade_crossing(const Leaf& leaf, std::int64_t u, std::int64_t v,
                                      std::int32_t n, Rgb8* out) const {
  shade_terms(leaf.q, leaf.crossing, crossings_ + leaf.first, u, v, n, out);
}

// shade_terms' loop for K terminators, unrolled, the same arithmetic: Q.24 × Q.14 << 2 -> Q.40.
template <std::size_t K>
void KbAdaptiveMethod::shade_crossings(const QuadStep st[], const Crossing* crossing,
                                       std::int32_t n, Rgb8* out) {
  constexpr int kUp = kQuadStateFrac - 24 - kSampleFrac;
  std::int64_t w[K][3];
  std::int64_t nl[K], nld[K], nl2[K];
  for (std::size_t k = 0; k < K; ++k) {
    for (std::size_t c = 0; c < 3; ++c) w[k][c] = crossing[k].weight[c] * (std::int64_t{1} << kUp);
    nl[k] = st[3 + k].v;
    nld[k] = st[3 + k].d1;
    nl2[k] = st[3 + k].d2;
  }
  std::int64_t r = st[0].v, rd = st[0].d1, g = st[1].v, gd = st[1].d1, b = st[2].v, bd = st[2].d1;
  for (std::int32_t x = 0; x < n; ++x) {
    std::int64_t cr = r, cg = g, cb = b;
    for (std::size_t k = 0; k < K; ++k) {
      if (nl[k] < 0) {  // below zero the diffuse was left out of the colours
        const std::int64_t dark = (-nl[k]) >> (kQuadStateFrac - kSampleFrac);  // Q.24
        cr += dark * w[k][0];
        cg += dark * w[k][1];
        cb += dark * w[k][2];
      }
      nl[k] += nld[k];
      nld[k] += nl2[k];
    }
    out[x] = Rgb8{quad_level(cr), quad_level(cg), quad_level(cb)};
    r += rd;
    rd += st[0].d2;
    g += gd;
    gd += st[1].d2;
    b += bd;
    bd += st[2].d2;
  }
}

Rgb8 KbAdaptiveMethod::exact_at(std::int32_t x, std::int32_t y) const {
  Rgb8 px;
  shade_exact(y, x, 1, &px);
  return px;
}

// Per pixel: the exact evaluation at every pixel centre of [xa, xa + n) in row y
// (PointShader::shade_pixels, the same pixels as exact Phong's).
void KbAdaptiveMethod::shade_exact(std::int32_t y, std::int32_t xa, std::int32_t n,
                                   Rgb8* out) const {
  point_.shade_pixels(y, xa, n, out);
  count_exact(n);
}

// Early depth (kSkipsHiddenPixels): the exact evaluation and the constant are the same at a
// pixel wherever a run starts, so they shade [first, last) alone; a quadratic piece's seed
// depends on where the piece starts and how long it is, so the pieces keep their bounds and
// only those wholly hidden are left out.
void KbAdaptiveMethod::shade_span(const Span& s, Rgb8* out) {
  if (path_ == Path::kExact) {
    shade_exact(s.y, s.first, s.last - s.first, out + (s.first - s.x0));
    return;
  }
  const std::int32_t n = s.x1 - s.x0;
  if (path_ == Path::kConstant && mode_ == AdaptiveMode::kAdaptive) {  // every pixel the same
    for (std::int32_t x = s.first; x < s.last; ++x) out[x - s.x0] = constant_;
    return;
  }
  const Lambdas lam = lambdas_at(*tri_, 16 * std::int64_t{s.x0} + 8, 16 * std::int64_t{s.y} + 8);
  if (level_ == 0) {
    const std::int64_t u = local_of(lam.l[1]), v = local_of(lam.l[2]);
    fill_quadratic(whole_, whole_in_range_, u, v, n, out);
    return;
  }
  const std::int64_t e1 = lam.l[1], e2 = lam.l[2];
  if (leaves_[0].cell.level ==
      0) {  // the whole triangle is one leaf (terminators, or refine's root)
    if (leaves_[0].exact)
      shade_exact(s.y, s.first, s.last - s.first, out + (s.first - s.x0));
    else
      shade_cell(leaves_[0], e1, e2, n, out);  // level 0: (s, t) = (e1, e2)
    return;
  }
  shade_pieces(s, e1, e2, out);
}

// Subdivided: each piece of the span lies in one leaf cell (found through the deepest level's
// map of leaves), shaded by that cell's quadratic or, over budget at the deepest level, exactly.
// The point is walked in units of the deepest level's cells; a leaf of level l reads it in units
// of its own as (s, t) / 2^(kMaxLevel − l), an exact shift: s = 2^kMaxLevel·e1.
void KbAdaptiveMethod::shade_pieces(const Span& s, std::int64_t e1, std::int64_t e2,
                                    Rgb8* out) const {
  // The span's bounds in locals: a field of `s` read after a piece is shaded (a call, and bytes
  // written through `out`, either of which may change any memory) would be read again.
  const std::int32_t n = s.last - s.x0;  // the pieces after the last visible pixel are left out
  const std::int32_t first = s.first - s.x0, width = s.x1 - s.x0;
  constexpr std::int64_t kCells = std::int64_t{1} << kMaxLevel;
  std::int64_t fs = e1 * kCells, ft = e2 * kCells;
  const std::int64_t fds = de1_ * kCells, fdt = de2_ * kCells;
  for (std::int32_t x = 0; x < n;) {
    const Cell finest = finest_cell(fs, ft);
    const Leaf& leaf = leaves_[(finest.up ? leaf_up_ : leaf_down_)[finest.j][finest.i]];
    const int coarser = kMaxLevel - leaf.cell.level;
    const std::int64_t ls = fs >> coarser, lt = ft >> coarser;
    std::int64_t len = pixels_in(leaf.cell, ls, lt, fds >> coarser, fdt >> coarser);
    if (len > width - x) len = width - x;
    const auto run = static_cast<std::int32_t>(len);
    if (x + run <= first) {
      // Wholly hidden: nothing to shade.
    } else if (leaf.exact) {
      const std::int32_t a = x > first ? x : first, b = x + run < n ? x + run : n;
      shade_exact(s.y, s.x0 + a, b - a, out + a);
    } else {
      shade_cell(leaf, ls, lt, run, out + x);  // whole: its seed depends on its bounds
    }
    fs += len * fds;
    ft += len * fdt;
    x += run;
  }
}

}  // namespace tp::fw::kb
