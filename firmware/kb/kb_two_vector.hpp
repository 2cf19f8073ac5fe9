// What the two-vector Kuijk-Blake methods (eq. 1 exact, eq. 2 decomposition) share: N and,
// per light, L and H interpolated separately by slerp along the edges, and the frame of a
// great circle on a span.
#pragma once

#include <cstdint>

#include "firmware/kb/kb_common.hpp"
#include "firmware/method.hpp"

namespace tp::fw::kb {

// Per light: L and H along the edges, and the weights of its two terms.
struct TwoVectorLight {
  EdgeArcs l, h;
  q1_30 wd[3], ws[3];  // Il_c·kd·O_c and Il_c·ks, in span units (·255/4096)
};

// The per-triangle part shared by both methods.
struct TwoVectorTriangle {
  const Triangle* tri = nullptr;
  Counters* counters = nullptr;
  EdgeArcs n;
  int lights = 0;
  TwoVectorLight light[kMaxLights];
  // Per light, L's and H's terms: false where the vector is undefined at a vertex
  // (firmware/lighting.hpp), and the term is left out of the triangle.
  bool defined[kMaxLights][2];
  std::int64_t ambient[3] = {0, 0, 0};

  void setup(const Triangle& t, const ShadeContext& ctx) {
    tri = &t;
    counters = ctx.counters;
    const MaterialCmd& m = ctx.material;
    for (int c = 0; c < 3; ++c) ambient[c] = ambient_value(m.ka, m.color[c]);
    Unit nv[3], eye[3];
    for (int i = 0; i < 3; ++i) {
      nv[i] = t.v[i].normal;
      eye[i] = eye_direction(ctx, t.v[i].eye);
    }
    n.set(nv);
    lights = 0;
    for (const LightState& ls : ctx.lights) {
      if (ls.type == LightType::kOff) continue;
      TwoVectorLight& out = light[lights++];
      Unit lv[3], hv[3];
      for (int i = 0; i < 3; ++i) {
        lv[i] = light_direction(ls, t.v[i].eye);
        hv[i] = halfway(lv[i], eye[i]);
      }
      out.l.set(lv);
      out.h.set(hv);
      defined[lights - 1][0] = !undefined_direction(lv, 3);
      defined[lights - 1][1] = !undefined_direction(hv, 3);
      for (int c = 0; c < 3; ++c) {
        out.wd[c] = term_weight(ls.color[c], fx::mul_sat<q1_30>(m.kd, m.color[c]));
        out.ws[c] = term_weight(ls.color[c], m.ks);
      }
    }
  }
};

// A great circle through a span's arc: an orthonormal frame (e1 = start, e2 = tangent,
// e3 = pole) and the arc angle. An arc too short to have a direction borrows its plane from
// `hint` (the other vector's position), or from a fixed perpendicular: any circle through a
// constant vector describes it, with angle 0.
struct CircleFrame {
  Unit e1{}, e2{}, e3{};
  angle_t angle{};
};
inline CircleFrame circle_frame(const Arc& arc, const Unit& hint) {
  CircleFrame f{arc.from, arc.tangent, Unit{}, arc.angle};
  if (!arc.has_direction()) {
    // Tangent toward the hint (so that the hint lies on the circle), else any.
    const Unit w =
        combine(q1_30::one(), hint, fx::neg_sat(fx::dot<q1_30>(hint, arc.from)), arc.from);
    if (is_negligible(w) || !fx::try_normalize<q1_30>(w, f.e2)) f.e2 = any_perpendicular(arc.from);
    f.angle = angle_t::zero();
  }
  f.e3 = fx::cross<q1_30>(f.e1, f.e2);
  return f;
}
inline CircleFrame circle_frame(const Unit& from, const Unit& to, const Unit& hint) {
  return circle_frame(make_arc(from, to), hint);
}

// Signed angle of x around the frame's pole, from e1 toward e2 (longitude), and its angle out
// of the circle's plane (latitude).
inline angle_t longitude(const CircleFrame& f, const Unit& x) {
  return fx::atan2_fast(fx::dot<q1_30>(x, f.e2), fx::dot<q1_30>(x, f.e1));
}
inline angle_t latitude(const CircleFrame& f, const Unit& x) {
  const Unit in_plane{fx::dot<q1_30>(x, f.e1), fx::dot<q1_30>(x, f.e2), q1_30::zero()};
  return fx::atan2_fast(fx::dot<q1_30>(x, f.e3), length(in_plane));
}

// Linear angle along the span's pixels: value at the first centre and step per pixel, from
// the values at the span ends (x_left, x_right).
struct AngleLine {
  angle_t first{};
  angle_t step{};
};
inline AngleLine angle_line(std::int64_t at_left, std::int64_t at_right, xpos_t xl, xpos_t xr,
                            xpos_t first_centre) {
  // Reuse span_line with φ_L = at_left and θ = at_right − at_left, the latter taken the short
  // way round (angles from atan2 jump by 2π where the other way is meant).
  SpanCircle c;
  c.phi_left = angle_t::from_raw_sat(wrap_pi(at_left));
  c.theta = angle_t::from_raw_sat(wrap_pi(at_right - at_left));
  const SpanLine line = span_line(c, xl, xr, first_centre);
  return {line.phi_first, dphi_angle(line)};
}

}  // namespace tp::fw::kb
