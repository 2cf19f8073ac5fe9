// Kuijk-Blake decomposition method (eq. 2).
//
// On a span, N runs along its great circle from N_L to N_R. Take the frame e1 = N_L,
// e2 = tangent, e3 = pole; a direction X has longitude λ(X) and latitude β(X) in it, and
//   N·X = cos(λ_N − λ_X) · cos β_X            (N on the equator: a right spherical triangle).
// The paper rotates L_2 (and N_2) about the pole until L_1 and L_2 share a meridian, which is
// the same as interpolating the two angles u = λ_N − λ_X and v = β_X linearly between their
// values at the span ends (eq. 2: cos α_t = cos(n1 + t(n2 − n1))·cos(l1 + t(l2 − l1))). It is
// exact at both ends and a first-order approximation between them (the paper's Figure 8).
// cos^n α ≈ f(u)·f(v), each factor forward-differenced from cosn's segments.
//
// Skipping: a term whose v (or u) stays beyond ±b on one side over the whole span is zero there
// (both factors are exact zeros on zero pieces) and is left out, counted per span.
#include "firmware/kb/kb_methods.hpp"

namespace tp::fw::kb {
namespace {

// f·g of two Q.S factor values (<= 2^S) in Q.30.
std::int64_t product_q30(std::int64_t f, std::int64_t g) {
  constexpr int cut = cosn::kStateFrac - 15;  // each factor to Q.15, the product to Q.30
  return fx::round_shift_right(f, cut) * fx::round_shift_right(g, cut);
}

bool beyond_max_step(angle_t step) {
  return step.raw() > cosn::kMaxDThetaRaw || step.raw() < -cosn::kMaxDThetaRaw;
}

bool beyond_on_one_side(std::int64_t a, std::int64_t b, std::int64_t support) {
  return (a >= support && b >= support) || (a <= -support && b <= -support);
}

}  // namespace

bool KbDecompositionMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  t_.setup(tri, ctx);
  coeffs_.refresh(ctx.material);
  return true;
}

// Span setup: N's arc, then per term its circle (N's own while N moves; through the term's
// direction where it does not), the angles u, v at the span ends (skipping the terms that are
// zero over the whole span) and the forward-differenced segments of f(u) and f(v).
inline void KbDecompositionMethod::prepare_span(const Span& s) {
  const int length = s.x1 - s.x0;
  const xpos_t xl = edge_x(*t_.tri, s.left), xr = edge_x(*t_.tri, s.right);
  t_.counters->saturations += static_cast<std::uint64_t>(saturated_ends(xl, xr));
  const xpos_t first = pixel_centre(s.x0);
  const Unit nl = t_.n.at(s.left), nr = t_.n.at(s.right);
  terms_ = 0;
  const Arc n_arc = make_arc(nl, nr);
  CircleFrame frame{};
  bool have_frame = false;
  for (int li = 0; li < t_.lights; ++li) {
    const TwoVectorLight& light = t_.light[li];
    for (int k = 0; k < 2; ++k) {
      const bool spec = k == 1;
      const cosn::CosnCoeffs& c = spec ? coeffs_.specular : coeffs_.diffuse;
      if (!c.valid || !t_.defined[li][k]) continue;
      const EdgeArcs& arcs = spec ? light.h : light.l;
      const Unit x_l = arcs.at(s.left), x_r = arcs.at(s.right);
      // N's circle: once per span where N moves along it. Where it does not (a flat face), each
      // term takes the circle through its own direction, as kb-exact does: one term's circle for
      // all made the others' angles depend on which light came first, a dark one included.
      if (!have_frame || !n_arc.has_direction()) {
        frame = circle_frame(n_arc, x_l);
        have_frame = true;
      }
      const std::int64_t u1 = -std::int64_t{longitude(frame, x_l).raw()};
      const std::int64_t u2 = std::int64_t{frame.angle.raw()} - longitude(frame, x_r).raw();
      const std::int64_t v1 = latitude(frame, x_l).raw(), v2 = latitude(frame, x_r).raw();
      if (beyond_on_one_side(v1, v2, c.b) ||
          beyond_on_one_side(wrap_pi(u1), wrap_pi(u1) + wrap_pi(u2 - u1), c.b)) {
        ++t_.counters->lights_skipped_span;
        continue;
      }
      Term& t = term_[terms_++];
      t.weight = spec ? light.ws : light.wd;
      if (spec) t_.counters->specular_evaluations += static_cast<std::uint64_t>(length);
      const AngleLine ul = angle_line(u1, wrap_pi(u1) + wrap_pi(u2 - u1), xl, xr, first);
      const AngleLine vl = angle_line(v1, v2, xl, xr, first);
      // make_one_channel steps at most 1 rad per pixel (kb_sections.hpp): a faster step on a
      // span of two or more pixels is clamped there.
      if (length > 1 && (beyond_max_step(ul.step) || beyond_max_step(vl.step)))
        ++t_.counters->saturations;
      t.u.count = make_one_channel(c, ul.first, ul.step, q1_30::one(), length, t.u.seg);
      t.v.count = make_one_channel(c, vl.first, vl.step, q1_30::one(), length, t.v.seg);
      t.u.next = t.v.next = 0;
    }
  }
}

// Pixel loop: per term f(u)·f(v) (eq. 2), weighted, both factors stepped.
inline void KbDecompositionMethod::evaluate_span(const Span& s, Rgb8* out) {
  const int length = s.x1 - s.x0;
  std::int64_t acc[3];
  for (int x = 0; x < length; ++x) {
    for (int c = 0; c < 3; ++c) acc[c] = t_.ambient[c];
    for (int j = 0; j < terms_; ++j) {
      Term& t = term_[j];
      for (Factor* f : {&t.u, &t.v}) {  // one comparison per segment, two additions per pixel
        if (f->next < f->count && f->seg[f->next].x == x) f->st = f->seg[f->next++].st;
      }
      const std::int64_t p = product_q30(t.u.st.v, t.v.st.v);  // eq. 2: f(u)·f(v), per pixel
      for (int c = 0; c < 3; ++c)
        acc[c] += fx::round_shift_right(t.weight[c].raw() * p, 60 - cosn::kStateFrac);
      cosn::step(t.u.st);
      cosn::step(t.v.st);
    }
    out[x] = Rgb8{level_of(acc[0]), level_of(acc[1]), level_of(acc[2])};
  }
}

void KbDecompositionMethod::shade_span(const Span& s, Rgb8* out) {
  prepare_span(s);
  evaluate_span(s, out);
}

}  // namespace tp::fw::kb
