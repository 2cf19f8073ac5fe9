// Kuijk-Blake one-vector method (eq. 4), the core of tinyphong.
//
// Per triangle: O, then per vertex the rotation R(N_i→O), and per light and term the vector
// V_i = R(N_i→O)·L_i (diffuse) or ·H_i (specular), so that angle(V_i, O) = angle(N_i, L_i).
// Only V is interpolated: slerped along the edges in y, then along the span in x. On a span,
// cos α = cos φ · cos s (kb_geometry.hpp), so cos^n α ≈ f(φ)·f(s): a per-span constant times
// f of an angle linear in x; every term's pieces are summed into one quadratic per channel
// (kb_sections.hpp).
//
// Choice of O. Any O shared by the triangle's three vertices satisfies eq. 4. We use the
// paper's fixed O = (0, 0, 1) (eye space): V at a vertex then depends on that vertex alone, so
// two triangles sharing an edge interpolate the same V along it and the shading is continuous
// across edges. A normal near −O makes R(N→O) a near half turn whose axis swings from vertex to
// vertex; a triangle with a vertex normal within ~26° of −O (never a front face of the paper
// scenes) takes the normalised mean of its vertex normals as its own O instead. The
// per-triangle mean for every triangle (OChoice::kTriangleMean) scores about the same colour
// correctness but shows visible steps along the edges (docs/KUIJK-BLAKE.md).
//
// Skipping (conservative, bit-identical; tests/kb/test_kb_device.cpp):
//  - triangle: a term whose V stays, over the whole spherical triangle V_0 V_1 V_2, at an angle
//    from O of at least B + margin, where f(φ)·f(s) > 0 needs |φ| < b and s < b, hence
//    cos α = cos φ·cos s > cos²b (b <= π/2) or > cos b (b > π/2): B = acos(cos²b) or b. The
//    triangle is bounded by the cap around C = normalize(ΣV_i) of radius r = max angle(C, V_i)
//    (caps under a hemisphere are convex, and slerped V stays in the spherical triangle), so the
//    smallest angle to O is at least angle(C, O) − r. Margin 2^-14 rad covers the fixed-point
//    rounding of V, s and φ (each below 1e-7 rad, tests/kb/test_kb_geometry.cpp).
//  - span: s >= b gives f(s) = 0 exactly, and φ beyond ±b on one side over the whole span puts
//    every pixel on a zero piece of f: either way the term adds nothing.
//  - segment: where every term is on a zero piece, the ambient colour without stepping.
//  - triangle with no term left (dark, or facing away from every light): ambient fill.
#include "firmware/kb/kb_methods.hpp"
#include "firmware/raster.hpp"

namespace tp::fw::kb {
namespace {

constexpr std::int64_t kSkipMarginRaw = std::int64_t{1} << (29 - 14);  // 2^-14 rad
constexpr std::int64_t kMaxRate = std::int64_t{1} << 40;               // 1 rad per pixel

// B' = B + margin as a cosine/sine pair: beyond B from O, f(φ)·f(s) is zero (header comment).
Support support_of(const cosn::CosnCoeffs& c) {
  const angle_t b = angle_t::from_raw(static_cast<std::int32_t>(c.b));
  std::int64_t big_b = b.raw();
  if (b <= kHalfPi) {
    const q1_30 cb = fx::sin_cos(b).cos;
    big_b = fx::acos_unit(fx::mul_sat<q1_30>(cb, cb)).raw();
  }
  big_b += kSkipMarginRaw;
  if (big_b >= kPi.raw()) return Support{};  // nothing is ever that far from O
  const fx::SinCos sc = fx::sin_cos(angle_t::from_raw(static_cast<std::int32_t>(big_b)));
  return Support{sc.cos, sc.sin, true};
}

// The spherical triangle V_0 V_1 V_2 lies in the cap around C = normalize(ΣV_i) of radius
// r = max angle(C, V_i); the term is zero on it if angle(C, O) >= r + B', i.e. (r + B' <= π)
// C·O <= cos(r + B') = cos r cos B' − sin r sin B'. Compared in Q.60 with a 2^-24 slack on the
// cosine side (the roundings of C·O and of the right side are ~2^-30 each).
bool beyond_support(const Unit v[3], const Unit& o, const Support& support) {
  if (!support.possible) return false;
  const Unit c = normalize_wide(std::int64_t{v[0].x.raw()} + v[1].x.raw() + v[2].x.raw(),
                                std::int64_t{v[0].y.raw()} + v[1].y.raw() + v[2].y.raw(),
                                std::int64_t{v[0].z.raw()} + v[1].z.raw() + v[2].z.raw());
  if (c.x.raw() == 0 && c.y.raw() == 0 && c.z.raw() == 0) return false;
  q1_30 cos_r = q1_30::one();
  for (int i = 0; i < 3; ++i) {
    const q1_30 d = fx::dot<q1_30>(c, v[i]);
    if (d < cos_r) cos_r = d;
  }
  if (cos_r.raw() <= 0) return false;  // the cap would reach a hemisphere: no useful bound
  if (cos_r.raw() < -static_cast<std::int64_t>(support.cos.raw())) return false;  // r + B' > π
  using Q60 = fx::Q<2, 60, std::int64_t>;
  const Q60 one_minus = Q60::from_raw((std::int64_t{1} << 60) -
                                      std::int64_t{cos_r.raw()} * cos_r.raw());  // 1 − cos²r >= 0
  const q1_30 sin_r = fx::sqrt<q1_30>(one_minus);
  const std::int64_t rhs = std::int64_t{cos_r.raw()} * support.cos.raw() -
                           std::int64_t{sin_r.raw()} * support.sin.raw();  // Q.60, |.| <= 2^60
  const std::int64_t lhs = std::int64_t{fx::dot<q1_30>(c, o).raw()} << 30;
  return lhs <= rhs - (std::int64_t{1} << 36);
}

// A vertex normal within ~26° of −O (N_z < −0.9): R(N→O) is a near half turn whose axis
// swings between neighbouring vertices; such a triangle takes its own O instead.
bool near_antipode(const Triangle& tri) {
  constexpr std::int32_t kLimit = -966367642;  // round(−0.9 · 2^30)
  for (const ShadeVertex& v : tri.v)
    if (v.normal.z.raw() < kLimit) return true;
  return false;
}

Unit mean_normal(const Triangle& tri) {
  const Unit m = normalize_wide(
      std::int64_t{tri.v[0].normal.x.raw()} + tri.v[1].normal.x.raw() + tri.v[2].normal.x.raw(),
      std::int64_t{tri.v[0].normal.y.raw()} + tri.v[1].normal.y.raw() + tri.v[2].normal.y.raw(),
      std::int64_t{tri.v[0].normal.z.raw()} + tri.v[1].normal.z.raw() + tri.v[2].normal.z.raw());
  return m.x.raw() == 0 && m.y.raw() == 0 && m.z.raw() == 0 ? kO : m;
}

}  // namespace

Rotation KbOneVectorMethod::rotation_of(const Unit& n, const Unit& o) {
  for (const RotationMemo& m : rotation_memo_)
    if (m.valid && m.n == n && m.o == o) return m.r;
  RotationMemo& m = rotation_memo_[rotation_next_];
  rotation_next_ = (rotation_next_ + 1) % kRotationMemo;
  m = RotationMemo{n, o, rotation_to(n, o), true};
  return m.r;
}

Unit KbOneVectorMethod::halfway_of(std::size_t light, const Unit& l, const Unit& e) {
  HalfwayMemo& m = halfway_memo_[light];
  if (!m.valid || !(m.l == l) || !(m.e == e)) m = HalfwayMemo{l, e, halfway(l, e), true};
  return m.h;
}

KbOneVectorMethod::VertexMemo& KbOneVectorMethod::vertex_of(const ShadeVertex& v, const Unit& o,
                                                            const ShadeContext& ctx) {
  for (VertexMemo& m : vertex_memo_)
    if (m.valid && m.n == v.normal && m.o == o && m.p == v.eye && m.eye == ctx.eye) return m;
  VertexMemo& m = vertex_memo_[vertex_next_];
  vertex_next_ = (vertex_next_ + 1) % kVertexMemo;
  m.n = v.normal;
  m.o = o;
  m.p = v.eye;
  m.eye = ctx.eye;
  m.r = rotation_of(v.normal, o);
  m.e = eye_direction(ctx, v.eye);
  for (VertexLight& l : m.light) l.valid = false;
  m.valid = true;
  return m;
}

bool KbOneVectorMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  tri_ = &tri;
  x_may_saturate_ = may_saturate_x(tri);
  counters_ = ctx.counters;
  terms_ = 0;
  chunk_key_ = 0;
  chunk_last_ = -1;  // a new triangle starts a new chunk
  sample_row_ = -2;
  const MaterialCmd& m = ctx.material;
  for (int c = 0; c < 3; ++c) ambient_[c] = ambient_value(m.ka, m.color[c]);
  ambient_rgb_ = Rgb8{level_of(ambient_[0]), level_of(ambient_[1]), level_of(ambient_[2])};
  if (coeffs_.refresh(m)) {
    diffuse_support_ = support_of(coeffs_.diffuse);
    specular_support_ = support_of(coeffs_.specular);
  }

  o_ = o_choice_ == OChoice::kPaper && !near_antipode(tri) ? kO : mean_normal(tri);
  // V of both terms per light and vertex (one vertex's memo entry at a time: looking up the
  // next vertex may evict it).
  Unit vd_all[kMaxLights][3], vs_all[kMaxLights][3];
  for (int i = 0; i < 3; ++i) {
    VertexMemo& vm = vertex_of(tri.v[i], o_, ctx);
    for (std::size_t li = 0; li < kMaxLights; ++li) {
      const LightState& light = ctx.lights[li];
      if (light.type == LightType::kOff) continue;
      VertexLight& vl = vm.light[li];
      if (!vl.valid || vl.type != light.type || !(vl.direction == light.direction) ||
          !(vl.position == light.position)) {
        const Unit l = light_direction(light, tri.v[i].eye);
        vl.type = light.type;
        vl.direction = light.direction;
        vl.position = light.position;
        vl.vd = rotate(vm.r, l);  // Kuijk-Blake Figure 9
        vl.vs = rotate(vm.r, halfway_of(li, l, vm.e));
        vl.valid = true;
      }
      vd_all[li][i] = vl.vd;
      vs_all[li][i] = vl.vs;
    }
  }
  q1_30 kd_colour[3];
  for (int c = 0; c < 3; ++c) kd_colour[c] = fx::mul_sat<q1_30>(m.kd, m.color[c]);
  for (std::size_t li = 0; li < kMaxLights; ++li) {
    const LightState& light = ctx.lights[li];
    if (light.type == LightType::kOff) continue;
    const Unit* vd = vd_all[li];
    const Unit* vs = vs_all[li];
    q1_30 wd[3], ws[3];
    for (int c = 0; c < 3; ++c) {
      wd[c] = term_weight(light.color[c], kd_colour[c]);
      ws[c] = term_weight(light.color[c], m.ks);
    }
    if (coeffs_.diffuse.valid) add_term(vd, coeffs_.diffuse, diffuse_support_, wd);
    if (coeffs_.specular.valid) add_term(vs, coeffs_.specular, specular_support_, ws);
  }
  return true;
}

void KbOneVectorMethod::add_term(const Unit v[3], const cosn::CosnCoeffs& c, const Support& support,
                                 const q1_30 weight[3]) {
  if (weight[0].raw() == 0 && weight[1].raw() == 0 && weight[2].raw() == 0) return;  // adds 0
  // Undefined at a vertex (firmware/lighting.hpp): left out, by the no-skip form as well.
  if (undefined_direction(v, 3)) return;
  if (skipping_ && beyond_support(v, o_, support)) {
    ++counters_->lights_skipped_triangle;
    return;
  }
  OneVectorTerm& t = term_[terms_++];
  t.v.set(v);
  t.coeffs = &c;
  for (int ch = 0; ch < 3; ++ch) t.weight[ch] = weight[ch];
}

// Exact span parameters of a term for the span between edge positions l and r.
SpanParams KbOneVectorMethod::exact_params(const OneVectorTerm& t, const EdgePos& l,
                                           const EdgePos& r) const {
  const SpanCircle circle = span_circle(t.v.at(l), t.v.at(r), o_);
  SpanParams p;
  p.phi_left = circle.phi_left.raw();
  p.theta = circle.theta;
  const xpos_t width = fx::sub_sat(edge_x(*tri_, r), edge_x(*tri_, l));
  if (!circle.constant && width.raw() > 0) {
    // cosn takes at most 1 rad per pixel (it saturates there): clamp the same way.
    const std::int64_t rate = fx::div<dangle_t>(circle.theta, width).raw();
    p.rate = rate > kMaxRate ? kMaxRate : (rate < -kMaxRate ? -kMaxRate : rate);
    // Counted where a second pixel centre fits in the span (a one-pixel span never steps, so
    // its clamped rate is unused; spans narrower than a pixel make the huge rates).
    if (p.rate != rate && width.raw() > (std::int64_t{1} << 16)) ++counters_->saturations;
  }
  const std::int64_t fs = circle.s.raw() >= t.coeffs->b ? 0 : f_at(*t.coeffs, circle.s);
  for (int c = 0; c < 3; ++c) p.scale[c] = scaled(t.weight[c], fs).raw();
  return p;
}

// The position on the same edge as `like`, at the centre line of `row`.
EdgePos KbOneVectorMethod::edge_at_row(const EdgePos& like, std::int32_t row) const {
  EdgePos e = like;
  const std::int64_t from = tri_->v[like.from].sy, to = tri_->v[like.to].sy;
  const std::int64_t yc = 16 * std::int64_t{row} + 8;
  e.t = fx::div<q1_30>(fx::int_q::from_raw(yc - from),
                       fx::int_q::from_raw(to > from ? to - from : 1));
  if (e.t.raw() < 0) e.t = q1_30::zero();
  if (e.t > q1_30::one()) e.t = q1_30::one();
  return e;
}

// A new chunk of rows starting at s.y: exact samples at its first, middle and last row, fitted
// by a quadratic in y (kb_coherence.hpp); too short a chunk is set up exactly row by row.
void KbOneVectorMethod::start_chunk(const Span& s) {
  const std::int32_t bottom = tri_->v[s.left.to].sy < tri_->v[s.right.to].sy
                                  ? tri_->v[s.left.to].sy
                                  : tri_->v[s.right.to].sy;
  const std::int32_t section_last = first_centre_at_or_after(bottom) - 1;
  chunk_last_ = section_last < s.y + kChunkRows ? section_last : s.y + kChunkRows;
  chunk_row_ = s.y;
  chunk_exact_ = chunk_last_ - s.y < kMinChunkRows;
  // The previous chunk's last sample (row s.y − 1, same section) is this chunk's first.
  const bool reuse = sample_key_ == chunk_key_ && sample_row_ == s.y - 1;
  sample_row_ = -2;
  if (chunk_exact_) return;
  const std::int32_t base = reuse ? s.y - 1 : s.y;
  const std::int64_t h2 = chunk_last_ - base, h1 = h2 / 2;
  const std::int32_t mid = base + static_cast<std::int32_t>(h1);
  const EdgePos lm = edge_at_row(s.left, mid), rm = edge_at_row(s.right, mid);
  const EdgePos ll = edge_at_row(s.left, chunk_last_), rl = edge_at_row(s.right, chunk_last_);
  // Near an apex the span's great circle swings fast from row to row (two nearby V define it
  // poorly), so s and φ_L are not smooth there: rows whose span is narrower than kMinChunkWidth
  // at any sample are set up exactly, one row at a time.
  const auto narrow = [this](const EdgePos& l, const EdgePos& r) {
    return fx::sub_sat(edge_x(*tri_, r), edge_x(*tri_, l)).raw() < kMinChunkWidthRaw;
  };
  if (narrow(s.left, s.right) || narrow(lm, rm) || narrow(ll, rl)) {
    chunk_exact_ = true;
    chunk_last_ = s.y;
    return;
  }
  for (int j = 0; j < terms_; ++j) {
    const SpanParams p0 = reuse ? sample_[j] : exact_params(term_[j], s.left, s.right);
    const SpanParams p1 = exact_params(term_[j], lm, rm);
    const SpanParams p2 = exact_params(term_[j], ll, rl);
    // φ_L unwrapped along y: no 2π jumps between the samples.
    const std::int64_t phi1 = p0.phi_left + wrap_pi(p1.phi_left - p0.phi_left);
    const std::int64_t phi2 = phi1 + wrap_pi(p2.phi_left - phi1);
    quad_[j][0].fit(p0.phi_left, phi1, phi2, h1, h2);
    quad_[j][1].fit(p0.rate, p1.rate, p2.rate, h1, h2);
    for (int c = 0; c < 3; ++c) quad_[j][2 + c].fit(p0.scale[c], p1.scale[c], p2.scale[c], h1, h2);
    if (reuse)
      for (QuadY& q : quad_[j]) q.step();  // from row s.y − 1 to s.y
    sample_[j] = p2;
  }
  sample_key_ = chunk_key_;
  sample_row_ = chunk_last_;
}

// One term on the span: φ at the first pixel centre, dφ per pixel, the per-channel scales.
void KbOneVectorMethod::add_span_term(const OneVectorTerm& t, std::int64_t phi_first,
                                      std::int64_t rate, const std::int64_t scales[3],
                                      const Span& s) {
  cosn::scale_t scale[3];
  bool zero = true;
  for (int c = 0; c < 3; ++c) {
    // Below 0 is the quadratic-in-y fit undershooting a zero scale (f(s) = 0 near b), not an
    // overflow; above Q1.30's range is one (scales are weight·f(s) <= 1 when exact).
    if (scales[c] > q1_30::max_raw) ++counters_->saturations;
    const std::int64_t q = fx::clamp(scales[c], 0, q1_30::max_raw);
    scale[c] = q1_30::from_raw(static_cast<std::int32_t>(q));
    zero = zero && q == 0;
  }
  if (skipping_ && zero) {  // f(s) = 0 (s >= b): nothing to add
    ++counters_->lights_skipped_span;
    return;
  }
  const angle_t dphi = angle_t::from_raw_sat(fx::round_shift_right(rate, 11));
  // cosn steps at most 1 rad per pixel (cosn_fd.hpp): the exact rate is clamped to that already
  // (exact_params counts it), a rate from the y-quadratic can overshoot it on a span that steps.
  if (s.x1 - s.x0 > 1 && (dphi.raw() > cosn::kMaxDThetaRaw || dphi.raw() < -cosn::kMaxDThetaRaw))
    ++counters_->saturations;
  const std::int64_t phi0 = wrap_pi(phi_first);
  if (skipping_) {
    // φ beyond ±b on one side over the whole span (and not wrapping round past ±π): every
    // pixel is on a zero piece of f, the term adds exactly nothing.
    const std::int64_t d = dphi.raw() > cosn::kMaxDThetaRaw    ? cosn::kMaxDThetaRaw
                           : dphi.raw() < -cosn::kMaxDThetaRaw ? -cosn::kMaxDThetaRaw
                                                               : dphi.raw();  // as cosn steps
    const std::int64_t end = phi0 + d * (s.x1 - s.x0 - 1);
    const std::int64_t lo = end < phi0 ? end : phi0, hi = end < phi0 ? phi0 : end;
    if (lo >= -kPi.raw() && hi <= kPi.raw() && (lo >= t.coeffs->b || hi <= -t.coeffs->b)) {
      ++counters_->lights_skipped_span;
      return;
    }
  }
  make_term(sections_.next_term(), *t.coeffs, angle_t::from_raw_sat(phi0), dphi, scale,
            s.x1 - s.x0);
  sections_.commit();
  if (t.coeffs == &coeffs_.specular)  // one light's specular f on every pixel of the span
    counters_->specular_evaluations += static_cast<std::uint64_t>(s.x1 - s.x0);
}

// The exact setup of a term on the span (also the fallback of the coherent setup).
void KbOneVectorMethod::add_exact_term(const OneVectorTerm& t, const Span& s) {
  const SpanParams p = exact_params(t, s.left, s.right);
  // φ at the first centre from the fraction of the width (exact also on spans narrower than a
  // pixel, where dφ per pixel is saturated and unused).
  SpanCircle c;
  c.phi_left = angle_t::from_raw(static_cast<std::int32_t>(p.phi_left));
  c.theta = p.theta;
  c.constant = p.rate == 0;
  const angle_t phi_first =
      span_phi_first(c, edge_x(*tri_, s.left), edge_x(*tri_, s.right), pixel_centre(s.x0));
  add_span_term(t, phi_first.raw(), p.rate, p.scale, s);
}

void KbOneVectorMethod::prepare_span(const Span& s) {
  sections_.begin(s.x1 - s.x0, ambient_);
  const xpos_t xl = edge_x(*tri_, s.left);
  if (x_may_saturate_)
    counters_->saturations +=
        static_cast<std::uint64_t>(saturated_ends(xl, edge_x(*tri_, s.right)));
  if (!coherent_) {
    for (int j = 0; j < terms_; ++j) add_exact_term(term_[j], s);
    return;
  }
  // Rows of one section arrive top to bottom; anything else starts a new chunk.
  const std::uint32_t key =
      static_cast<std::uint32_t>(s.left.from) | static_cast<std::uint32_t>(s.left.to) << 8 |
      static_cast<std::uint32_t>(s.right.from) << 16 | static_cast<std::uint32_t>(s.right.to) << 24;
  if (key != chunk_key_ || s.y < chunk_row_ || s.y > chunk_last_) {
    chunk_key_ = key;
    start_chunk(s);
  }
  if (chunk_exact_) {
    for (int j = 0; j < terms_; ++j) add_exact_term(term_[j], s);
    chunk_row_ = s.y + 1;
    return;
  }
  for (; chunk_row_ < s.y; ++chunk_row_)  // rows without a span (scissored) still step
    for (int j = 0; j < terms_; ++j)
      for (QuadY& q : quad_[j]) q.step();
  // φ at the first centre: φ_L + (x_c − x_L)·r, (Q.16 × Q.40) >> 27 = Q.29 (spans here are at
  // least kMinChunkWidth wide, so |r| <= π / 8).
  const std::int64_t dx = std::int64_t{pixel_centre(s.x0).raw()} - xl.raw();
  for (int j = 0; j < terms_; ++j) {
    const std::int64_t rate = quad_[j][1].value();
    const std::int64_t scales[3] = {quad_[j][2].value(), quad_[j][3].value(), quad_[j][4].value()};
    add_span_term(term_[j], quad_[j][0].value() + fx::mul_shift_right(dx, rate, 27), rate, scales,
                  s);
    for (QuadY& q : quad_[j]) q.step();  // forward difference to the next row
  }
  ++chunk_row_;
}

void KbOneVectorMethod::evaluate_span(Rgb8* out) {
  const SpanSections::Stats st = sections_.evaluate(out, skipping_);
  counters_->segments += st.segments;
}

void KbOneVectorMethod::shade_span(const Span& s, Rgb8* out) {
  if (terms_ == 0) {  // the cheapest path: nothing but ambient on this triangle
    for (int x = 0; x < s.x1 - s.x0; ++x) out[x] = ambient_rgb_;
    return;
  }
  prepare_span(s);
  evaluate_span(out);
}

}  // namespace tp::fw::kb
