// Kuijk-Blake one-vector method (eq. 4), the core of tinyphong.
//
// Per triangle: O, then per vertex the rotation R(N_i→O), and per light and term the vector
// V_i = R(N_i→O)·L_i (diffuse) or ·H_i (specular), so that angle(V_i, O) = angle(N_i, L_i).
// Only V is interpolated: slerped along the edges in y, then along the span in x. On a span,
// cos α = cos φ · cos s (kb_geometry.hpp), so cos^n α ≈ f(φ)·f(s): a per-span constant times
// f of an angle linear in x; every term's pieces are summed into one quadratic per channel
// (kb_sections.hpp).
//
// Choice of O. The paper fixes O = (0, 0, 1); any O shared by the three vertices satisfies
// eq. 4. We take the normalised mean of the triangle's vertex normals by default: the rotations
// R(N_i→O) are then small and nearly "parallel" (no twist about O between vertices), which is
// what keeps the interpolated V close to the two-vector angular interpolation, and a vertex
// normal can never be antipodal to O (where R(N→O) is undefined and neighbouring vertices would
// get unrelated half turns). The paper's fixed O is kept as an option (OChoice::kPaper) and
// measured in docs/KUIJK-BLAKE.md.
//
// Skipping (conservative, bit-identical; tests/kb/test_kb_device.cpp):
//  - triangle: a term whose V stays, over the whole spherical triangle V_0 V_1 V_2, at an angle
//    from O of at least B + margin, where f(φ)·f(s) > 0 needs |φ| < b and s < b, hence
//    cos α = cos φ·cos s > cos²b (b <= π/2) or > cos b (b > π/2): B = acos(cos²b) or b. The
//    triangle is bounded by the cap around C = normalize(ΣV_i) of radius r = max angle(C, V_i)
//    (caps under a hemisphere are convex, and slerped V stays in the spherical triangle), so the
//    smallest angle to O is at least angle(C, O) − r. Margin 2^-14 rad covers the fixed-point
//    rounding of V, s and φ (each below 1e-7 rad, tests/kb/test_kb_geometry.cpp).
//  - span: s >= b gives f(s) = 0 exactly: the term adds nothing.
//  - segment: where every term is on a zero piece, the ambient colour without stepping.
//  - triangle with no term left (dark, or facing away from every light): ambient fill.
#include "firmware/kb/kb_methods.hpp"

namespace tp::fw::kb {
namespace {

constexpr std::int64_t kSkipMarginRaw = std::int64_t{1} << (29 - 14);  // 2^-14 rad

// B: beyond this angle from O, f(φ)·f(s) is zero (see the header comment).
angle_t support_angle(const cosn::CosnCoeffs& c) {
  const angle_t b = angle_t::from_raw(static_cast<std::int32_t>(c.b));
  if (b > kHalfPi) return b;
  const q1_30 cb = fx::sin_cos(b).cos;
  return fx::acos_unit(fx::mul_sat<q1_30>(cb, cb));
}

bool beyond_support(const Unit v[3], const Unit& o, angle_t support) {
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
  const std::int64_t gap = std::int64_t{fx::acos_unit(fx::dot<q1_30>(c, o)).raw()} -
                           fx::acos_unit(cos_r).raw();
  return gap >= std::int64_t{support.raw()} + kSkipMarginRaw;
}

Unit mean_normal(const Triangle& tri) {
  const Unit m = normalize_wide(
      std::int64_t{tri.v[0].normal.x.raw()} + tri.v[1].normal.x.raw() + tri.v[2].normal.x.raw(),
      std::int64_t{tri.v[0].normal.y.raw()} + tri.v[1].normal.y.raw() + tri.v[2].normal.y.raw(),
      std::int64_t{tri.v[0].normal.z.raw()} + tri.v[1].normal.z.raw() + tri.v[2].normal.z.raw());
  return m.x.raw() == 0 && m.y.raw() == 0 && m.z.raw() == 0 ? kO : m;
}

}  // namespace

bool KbOneVectorMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  tri_ = &tri;
  counters_ = ctx.counters;
  terms_ = 0;
  const MaterialCmd& m = ctx.material;
  for (int c = 0; c < 3; ++c) ambient_[c] = ambient_value(m.ka, m.color[c]);
  ambient_rgb_ = Rgb8{level_of(ambient_[0]), level_of(ambient_[1]), level_of(ambient_[2])};
  diffuse_ = cosn::make_coeffs(diffuse_params());
  specular_ = cosn::make_coeffs(specular_params(m));
  const angle_t diffuse_support = support_angle(diffuse_);
  const angle_t specular_support = support_angle(specular_);

  o_ = o_choice_ == OChoice::kPaper ? kO : mean_normal(tri);
  Rotation rot[3];
  Unit eye[3];
  for (int i = 0; i < 3; ++i) {
    rot[i] = rotation_to(tri.v[i].normal, o_);
    eye[i] = eye_direction(ctx, tri.v[i].eye);
  }
  q1_30 kd_colour[3];
  for (int c = 0; c < 3; ++c) kd_colour[c] = fx::mul_sat<q1_30>(m.kd, m.color[c]);
  for (const LightState& light : ctx.lights) {
    if (light.type == LightType::kOff) continue;
    Unit vd[3], vs[3];
    for (int i = 0; i < 3; ++i) {
      const Unit l = light_direction(light, tri.v[i].eye);
      vd[i] = rotate(rot[i], l);                       // Kuijk-Blake Figure 9
      vs[i] = rotate(rot[i], halfway(l, eye[i]));
    }
    q1_30 wd[3], ws[3];
    for (int c = 0; c < 3; ++c) {
      wd[c] = term_weight(light.color[c], kd_colour[c]);
      ws[c] = term_weight(light.color[c], m.ks);
    }
    if (diffuse_.valid) add_term(vd, diffuse_, diffuse_support, wd);
    if (specular_.valid) add_term(vs, specular_, specular_support, ws);
  }
  return true;
}

void KbOneVectorMethod::add_term(const Unit v[3], const cosn::CosnCoeffs& c,
                                 angle_t support_angle, const q1_30 weight[3]) {
  if (weight[0].raw() == 0 && weight[1].raw() == 0 && weight[2].raw() == 0) return;  // adds 0
  if (skipping_ && beyond_support(v, o_, support_angle)) {
    ++counters_->lights_skipped_triangle;
    return;
  }
  OneVectorTerm& t = term_[terms_++];
  t.v.set(v);
  t.coeffs = &c;
  for (int ch = 0; ch < 3; ++ch) t.weight[ch] = weight[ch];
}

void KbOneVectorMethod::shade_span(const Span& s, Rgb8* out) {
  const int length = s.x1 - s.x0;
  if (terms_ == 0) {  // the cheapest path: nothing but ambient on this triangle
    for (int x = 0; x < length; ++x) out[x] = ambient_rgb_;
    return;
  }
  const xpos_t xl = edge_x(*tri_, s.left), xr = edge_x(*tri_, s.right);
  const xpos_t first = pixel_centre(s.x0);
  sections_.begin(length, ambient_);
  for (int j = 0; j < terms_; ++j) {
    const OneVectorTerm& t = term_[j];
    const SpanCircle circle = span_circle(t.v.at(s.left), t.v.at(s.right), o_);
    if (skipping_ && circle.s.raw() >= t.coeffs->b) {  // f(s) = 0: nothing to add
      ++counters_->lights_skipped_span;
      continue;
    }
    const std::int64_t fs = f_at(*t.coeffs, circle.s);  // the per-span constant f(s)
    const SpanLine line = span_line(circle, xl, xr, first);
    cosn::scale_t scale[3];
    for (int c = 0; c < 3; ++c) scale[c] = scaled(t.weight[c], fs);
    make_term(sections_.next_term(), *t.coeffs, line.phi_first, dphi_angle(line), scale, length);
    sections_.commit();
  }
  const SpanSections::Stats st = sections_.evaluate(out, skipping_);
  counters_->segments += st.segments;
  counters_->specular_evaluations += static_cast<std::uint64_t>(length) - st.ambient_pixels;
}

}  // namespace tp::fw::kb
