// Kuijk-Blake exact angular interpolation (eq. 1): the slow exact baseline of the family.
//
// On a span, N moves along its great circle (pole P_N) and L (or H) along its own (pole P_L).
// The circles meet at S = normalize(P_N × P_L) at the angle γ (cos γ = P_N·P_L); with n, l the
// signed angles from S to N_L and L_L, and n_t, l_t growing linearly along the span,
//   cos α_t = cos(n + n_t)·cos(l + l_t) + sin(n + n_t)·sin(l + l_t)·cos γ        (eq. 1)
// (the spherical law of cosines in the triangle S N_t L_t). Per pixel and term: two CORDIC
// rotations, then max(0, cos α) for diffuse and cos^n α by repeated squaring for specular —
// no approximation beyond the angular interpolation itself, so its image is the device's
// counterpart of the double angular reference (apart from L, H being slerped, not recomputed).
//
// Degenerate spans: both circles the same (P_N = ±P_L): S = N_L, γ = 0 or π; an arc too short
// to have a direction takes the circle through the other vector (circle_frame).
#include "firmware/kb/kb_methods.hpp"
#include "firmware/lighting.hpp"

namespace tp::fw::kb {
namespace {

// Signed angle from s to x about the pole p (x, s on p's circle).
std::int64_t angle_from(const Unit& s, const Unit& x, const Unit& p) {
  return fx::atan2_fast(fx::dot<q1_30>(x, fx::cross<q1_30>(p, s)), fx::dot<q1_30>(x, s)).raw();
}

}  // namespace

bool KbExactMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  t_.setup(tri, ctx);
  exponent_ = ctx.material.n;
  return true;
}

// Span setup: per term the two circles' intersection S, cos γ, and the angles n, l from S with
// their per-pixel steps.
inline void KbExactMethod::prepare_span(const Span& s) {
  const xpos_t xl = edge_x(*t_.tri, s.left), xr = edge_x(*t_.tri, s.right);
  t_.counters->saturations += static_cast<std::uint64_t>(saturated_ends(xl, xr));
  const xpos_t first = pixel_centre(s.x0);
  const Unit nl = t_.n.at(s.left), nr = t_.n.at(s.right);
  terms_ = 0;
  for (int li = 0; li < t_.lights; ++li) {
    for (int k = 0; k < 2; ++k) {
      const bool spec = k == 1;
      if (!t_.defined[li][k]) continue;
      const EdgeArcs& arcs = spec ? t_.light[li].h : t_.light[li].l;
      const Unit x_l = arcs.at(s.left), x_r = arcs.at(s.right);
      const CircleFrame fn = circle_frame(nl, nr, x_l), fl = circle_frame(x_l, x_r, nl);
      Unit sp{};
      if (!fx::try_normalize<q1_30>(fx::cross<q1_30>(fn.e3, fl.e3), sp) ||
          is_negligible(fx::cross<q1_30>(fn.e3, fl.e3)))
        sp = nl;  // the same circle: any point of it
      Term& t = term_[terms_++];
      t.specular = spec;
      t.weight = spec ? t_.light[li].ws : t_.light[li].wd;
      t.cos_gamma = fx::dot<q1_30>(fn.e3, fl.e3);
      const std::int64_t n0 = angle_from(sp, nl, fn.e3), l0 = angle_from(sp, x_l, fl.e3);
      const AngleLine nline = angle_line(n0, n0 + fn.angle.raw(), xl, xr, first);
      const AngleLine lline = angle_line(l0, l0 + fl.angle.raw(), xl, xr, first);
      t.n = nline.first.raw();
      t.dn = nline.step.raw();
      t.l = lline.first.raw();
      t.dl = lline.step.raw();
    }
  }
}

// Pixel loop: per term two CORDIC rotations, eq. 1, max(0, cos α), cos^n α for specular.
inline void KbExactMethod::evaluate_span(const Span& s, Rgb8* out) {
  const int length = s.x1 - s.x0;
  for (int x = 0; x < length; ++x) {
    std::int64_t acc[3] = {t_.ambient[0], t_.ambient[1], t_.ambient[2]};
    for (int j = 0; j < terms_; ++j) {
      Term& t = term_[j];
      const fx::SinCos a = fx::sin_cos_fast(angle_t::from_raw(static_cast<std::int32_t>(t.n)));
      const fx::SinCos b = fx::sin_cos_fast(angle_t::from_raw(static_cast<std::int32_t>(t.l)));
      // eq. 1; |cos α| <= |cos n cos l| + |sin n sin l| <= 1 (Cauchy-Schwarz) up to rounding,
      // each product < 2^60: the sum over 2^30 is inside Q1.30's [−2, 2), from_raw_sat never
      // clamps here.
      const std::int64_t cc = std::int64_t{a.cos.raw()} * b.cos.raw();
      const std::int64_t ss = fx::round_shift_right(std::int64_t{a.sin.raw()} * b.sin.raw(), 30);
      const std::int64_t sum = cc + ss * t.cos_gamma.raw();
      q1_30 cos_alpha = q1_30::from_raw_sat(fx::round_shift_right(sum, 30));
      if (cos_alpha.raw() < 0) cos_alpha = q1_30::zero();
      if (cos_alpha > q1_30::one()) cos_alpha = q1_30::one();
      const q1_30 value = t.specular ? power(cos_alpha, exponent_) : cos_alpha;
      for (int c = 0; c < 3; ++c)
        acc[c] += fx::round_shift_right(std::int64_t{t.weight[c].raw()} * value.raw(),
                                        60 - cosn::kStateFrac);
      t.n = wrap_pi(t.n + t.dn);  // n + n_t, kept in [−π, π] for the CORDIC
      t.l = wrap_pi(t.l + t.dl);
    }
    out[x] = Rgb8{level_of(acc[0]), level_of(acc[1]), level_of(acc[2])};
  }
  int specular_terms = 0;
  for (int j = 0; j < terms_; ++j) specular_terms += term_[j].specular ? 1 : 0;
  t_.counters->specular_evaluations +=
      static_cast<std::uint64_t>(length) * static_cast<std::uint64_t>(specular_terms);
}

void KbExactMethod::shade_span(const Span& s, Rgb8* out) {
  prepare_span(s);
  evaluate_span(s, out);
}

}  // namespace tp::fw::kb
