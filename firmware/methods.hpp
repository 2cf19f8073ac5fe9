// The shading methods outside firmware/kb/ (docs/CONVENTIONS.md, "Methods"), one unit each.
// Each states what it handles exactly: flat, Gouraud and Phong take point lights, a finite eye
// and up to kMaxLights lights with the exact Blinn-Phong formula and differ in where it is
// evaluated; Duff takes L and H once per triangle.
#pragma once

#include "firmware/interp.hpp"
#include "firmware/lighting.hpp"
#include "firmware/method.hpp"
#include "firmware/point_shader.hpp"
#include "firmware/texture.hpp"

namespace tp::fw {

// 1. Flat (shade_flat.cpp): one evaluation per triangle, at the eye-space centroid with the
//    renormalised mean of the vertex normals; every pixel gets that colour.
class FlatMethod final : public ShadingMethod {
 public:
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
  void shade_span(const Span& s, Rgb8* out) override;
  static constexpr bool kColoursLinear = true;
  LinearColours linear_span(const Span& s) override;

 private:
  Rgb8 colour_{0, 0, 0};
};

// 2. Gouraud (shade_gouraud.cpp): lighting at the three vertices, clamped to [0, 1], then
//    interpolated linearly in SCREEN space (the 1980s assumption, not perspective-correct):
//    one addition per channel per row and per pixel.
class GouraudMethod final : public ShadingMethod {
 public:
  // Lights each vertex once per draw, through the triangle's VertexLevels cache.
  static constexpr bool kLightsVertices = true;
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
  void shade_span(const Span& s, Rgb8* out) override;
  static constexpr bool kColoursLinear = true;
  LinearColours linear_span(const Span& s) override;

 private:
  const Triangle* tri_ = nullptr;
  ScreenPlane plane_[3];
  // The colours at the previous span's start, stepped to the next span's: exact (at()) for the
  // triangle's first span, then per row and per pixel in x by the planes' steps, as along a span.
  std::int64_t start_[3] = {0, 0, 0};  // ScreenPlane::kStepFrac more fraction bits
  std::int64_t step_x_[3] = {0, 0, 0}, step_y_[3] = {0, 0, 0};
  std::int32_t x_ = 0, y_ = 0;  // the previous span's start
  bool stepping_ = false;       // start_ holds the previous span's start
  bool steps_exact_ = false;    // no step saturated: row steps allowed
};

// 3. Phong, exact (shade_phong.cpp): Blinn-Phong at every pixel, at the perspective-correct
//    point (normal and eye-space position interpolated with hyperbolic barycentrics, like the
//    double reference), the normal renormalised, L, the eye direction and H exact there, the
//    power by repeated squaring: PointShader (point_shader.hpp), with one reciprocal root per
//    direction instead of a normalised vector, and along a row by exact integer steps.
class PhongMethod final : public ShadingMethod {
 public:
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
  void shade_span(const Span& s, Rgb8* out) override;
  static constexpr bool kSkipsHiddenPixels = true;

 private:
  PointShader point_;
  Counters* counters_ = nullptr;
};

// 4. Duff (shade_duff.cpp; Duff 1979, as Bishop & Weimer give it): Phong's normal interpolated
//    linearly in SCREEN space (as the paper, and as Gouraud; not perspective-correct), with the
//    lighting rewritten as (ax + by + c) / sqrt(dx² + exy + fy² + gx + hy + i): along a span each
//    light's N·L and N·H numerators are forward-differenced (one addition each per pixel) and so
//    is the radicand |N|² (two additions), then one square root and one division per pixel give
//    1/|N| for every light; the power as exact Phong's. L and H are the paper's constants: per
//    triangle, at its eye-space centroid (exact for directional lights seen from an eye at
//    infinity; point lights and a finite eye approximated). Every step is exact integer
//    arithmetic, so a pixel's value does not depend on where its span's stepping began.
class DuffMethod final : public ShadingMethod {
 public:
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
  void shade_span(const Span& s, Rgb8* out) override;
  static constexpr bool kSkipsHiddenPixels = true;

  // Fraction bits of the stepped normal: |N|² at twice that stays below 2^59 and its second
  // difference 2 Σ s² (|s| <= 2^30 per component after the planes' saturation) below 2^63.
  static constexpr int kNormalFrac = 28;

 private:
  struct LightTerm {
    std::int32_t l[3], h[3];  // L and H, Q1.30, this triangle's
    std::int32_t colour[3];   // Il_c, Q15.16
  };
  // One light's numerators on the current span: N·L and N·H at the pixel and their steps, at
  // kNormalFrac + 30 fraction bits.
  struct Numerators {
    std::int64_t d = 0, dd = 0, h = 0, dh = 0;
  };
  void start_span(const Span& s);

  const Triangle* tri_ = nullptr;
  Counters* counters_ = nullptr;
  ScreenPlane normal_[3];
  std::int64_t ambient_[3] = {0, 0, 0};  // ka O_c, Q.30
  std::int64_t diffuse_[3] = {0, 0, 0};  // kd O_c, Q.30
  std::int64_t ks_ = 0;                  // Q.30
  std::uint32_t exponent_ = 1;
  PowerFn power_ = nullptr;  // the unrolled power of exponent_, or null: power()
  int lights_ = 0;
  LightTerm light_[kMaxLights];
  // The span: |N|², its first and second differences, and every light's numerators.
  std::int64_t m_ = 0, dm_ = 0, ddm_ = 0;
  Numerators num_[kMaxLights];
};

// 5. Bishop & Weimer's fast Phong (shade_bishop_weimer.cpp; Bishop & Weimer 1986): Duff's
//    N·L/|N| and N·H/|N| of the screen-linear normal, each replaced by its second-order
//    two-dimensional Taylor expansion about the triangle's centre (the pixel centre nearest
//    its screen centroid), forward-differenced: two additions per polynomial per pixel. The
//    lights' diffuse polynomials, weighted by kd O_c Il_c, and the ambient term add into one
//    polynomial per channel (six additions per pixel whatever the number of lights); each
//    light's N·H polynomial addresses the exponent table (cosn_bw.hpp: 1 KiB for n <= 20, 8 KiB
//    for n <= 164, filled when the material changes), two additions and one lookup per light
//    per pixel; above n = 164 the power is taken by repeated squaring. L and H are the paper's
//    constants, per triangle at its eye-space centroid, as in Duff. A light that faces away from
//    all three vertex normals is left out of the triangle; one whose terminator crosses it
//    keeps a diffuse polynomial of its own, clamped at zero per pixel (summed, its negative
//    side would take light away from the others): two additions, a comparison and three
//    multiply-adds per such light per pixel.
class BishopWeimerMethod : public ShadingMethod {
 public:
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
  void shade_span(const Span& s, Rgb8* out) final;

  static constexpr int kCoeffFrac = 40;  // the Taylor coefficients
  static constexpr int kStateFrac = 36;  // the forward-differenced values
  // A polynomial in the pixel offsets (u, v) from the expansion pixel, Q.kCoeffFrac:
  // T(u, v) = c0 + c1 u + c2 v + c11 u² + c12 u v + c22 v².
  struct Taylor {
    std::int64_t c0 = 0, c1 = 0, c2 = 0, c11 = 0, c12 = 0, c22 = 0;
  };
  // A screen-linear vector (the normal; in the finite-eye method also H and a point light's L)
  // at the expansion pixel and its steps per pixel in x and y, Q.kCoeffFrac.
  struct VectorField {
    std::int64_t c[3], a[3], b[3];
  };
  // The second-order expansion of dir·N(u, v) / |N(u, v)| about (0, 0), dir a unit vector in
  // Q.kCoeffFrac; `saturated` is set when |N| at the centre is below 1/4 (normals more than
  // 150° apart) or a coefficient was clamped to its range.
  // With `quadratic` false, the first-order terms only (the others 0).
  static Taylor expand(const VectorField& n, const std::int64_t dir[3], bool quadratic,
                       bool& saturated);
  // The same for two varying vectors, N(u, v)·D(u, v) / (|N(u, v)| |D(u, v)|): the paper's
  // finite-eye expression (D = H), and a point light's diffuse term (D = L). First order only
  // where `quadratic` is false or D turns by more than a unit per pixel.
  static Taylor expand_pair(const VectorField& n, const VectorField& d, bool quadratic,
                            bool& saturated);
  // Whether a field changes by more than its centre's length per pixel (a triangle less than a
  // pixel across in that direction, or a point light within a pixel of it).
  static bool steep(const VectorField& f);
  // A term whose vector faces away from every vertex normal by this much (Q1.30) adds nothing.
  static constexpr std::int64_t kAwayMargin = std::int64_t{1} << 18;  // 2^-12

 protected:
  // setup()'s parts, shared with the finite-eye method. begin(): the counters, the exponent
  // table, the expansion pixel, the screen-linear normal there (and whether it is steep), the
  // ambient polynomial; `lam` the expansion pixel's edge weights, for further fields.
  void begin(const Triangle& tri, const ShadeContext& ctx, VectorField& normal, bool& steep_normal,
             Lambdas& lam);
  // The field of three vertex vectors (any fixed-point format, |v| <= 2^33 per component).
  static VectorField screen_field(const Triangle& tri, const Lambdas& lam,
                                  const std::int64_t v[3][3]);
  // A light's N·L term weighted by kd O_c Il_c: into the channels' sum where it lights the whole
  // triangle, else a polynomial of its own (clamped at zero per pixel).
  void add_diffuse(const Taylor& t, const LightState& l, const MaterialCmd& m, bool whole);
  // A light's N·H term, weighted by ks Il_c.
  void add_specular(const Taylor& t, const LightState& l, const MaterialCmd& m);
  // Keeps the sums in the coefficients' range; counts a saturation.
  void finish(bool saturated);
  Counters* counters() const { return counters_; }

 private:
  struct Stepper {  // a polynomial along the current span, Q.kStateFrac
    std::int64_t value = 0, delta = 0, delta2 = 0;
  };
  void refresh_material(const ShadeContext& ctx);
  Stepper start(const Taylor& t, std::int64_t u, std::int64_t v, std::int64_t n,
                bool& saturated) const;

  Counters* counters_ = nullptr;
  std::int64_t xr_ = 0, yr_ = 0;         // the expansion pixel
  std::int64_t ambient_[3] = {0, 0, 0};  // ka O_c, Q.kStateFrac: the floor of the diffuse sum
  Taylor diffuse_[3];    // per channel: ka O_c + Σ kd O_c Il_c N·L/|N| of the lights lighting
                         // all three vertices
  int terminators_ = 0;  // lights whose terminator crosses the triangle
  Taylor terminator_[kMaxLights];                       // N·L/|N| per such light
  std::int64_t terminator_weight_[kMaxLights][3] = {};  // kd O_c Il_c, Q.30
  Stepper terminator_step_[kMaxLights];
  int lights_ = 0;               // specular terms on this triangle
  Taylor specular_[kMaxLights];  // N·H/|N| per light
  // ks Il_c: per table unit in Q.36, or in Q.30 where the power is computed (table_size_ 0).
  std::int64_t spec_weight_[kMaxLights][3] = {};
  Stepper specular_step_[kMaxLights];
  // The material the table was filled for.
  const ShadeContext* ctx_ = nullptr;
  std::uint64_t revision_ = 0;
  std::uint32_t exponent_ = 0;
  int table_size_ = 0;  // 0: above the 8 KiB table's range, power() per pixel
  std::uint8_t table_[8192] = {};
};

// 5b. Bishop & Weimer's finite-eye extension (shade_bishop_weimer_finite.cpp): the specular
//    term N·H / (|N| |H|) with H varying over the triangle as well, H interpolated linearly in
//    screen space from the halfway vectors at the three vertices (the paper interpolates the
//    eye vector E and adds the constant L; this takes each vertex's own L too, so point lights
//    vary as well), expanded to second order about the same centre; a point light's diffuse
//    term N·L / (|N| |L|) likewise, with L = P_light - P interpolated unnormalised (exact in
//    direction where screen space is affine in eye space: orthographic views). A directional
//    light's diffuse, and the specular of one whose H is the same at all three vertices (the
//    eye at infinity), are bishop-weimer's. The pixel loop is bishop-weimer's: the extension
//    costs only setup.
class BishopWeimerFiniteMethod final : public BishopWeimerMethod {
 public:
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
};

// 7. Brown's Bézier-triangle highlights (shade_brown.cpp; Brown 1999): the diffuse and ambient
//    colour as Gouraud's (lit at the vertices without the specular term, interpolated in screen
//    space); each light's N·H as a quadratic Bézier triangle through six cosines — the three
//    vertex normals' and the three renormalised edge-midpoint normals', with H at each of the six
//    points (one H for a directional light seen from an eye at infinity) — evaluated per pixel
//    from perspective-correct barycentrics (Brown eq. 18 with eq. 9), and the power replaced by
//    the smoothstep s = t²(3 − 2t) of t = (c − c_lo) / (c_hi − c_lo), whose range is fitted to n
//    (lower_cosine). Brown's blend g = s g_s + (1 − s) g_da with the specular colour
//    g_s = g_da + ks Il is the additive model every other method renders: g = g_da + s ks Il.
//    Convex-hull culling: a light whose six control points all lie below c_lo cannot light any
//    pixel of the triangle and is left out of it (counted in lights_skipped_triangle; the
//    highlights evaluated are specular_evaluations).
class BrownMethod final : public ShadingMethod {
 public:
  // Its diffuse-and-ambient vertex colours, once per draw (GouraudMethod's cache).
  static constexpr bool kLightsVertices = true;
  // cull: the convex-hull test on (brown), or off (brown-noskip, which must give the same image).
  explicit BrownMethod(bool cull) : cull_(cull) {}
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
  void shade_span(const Span& s, Rgb8* out) override;

  // The control points of a quadratic Bézier triangle through cosines c at its vertices
  // (c[0..2], vertex 0, 1, 2) and edge midpoints (c[3..5]: edges 0-1, 1-2, 2-0), Q.30: the
  // vertex points are the cosines, the edge points by Brown's eq. 12, C011 = (4 c011 − C020 −
  // C002) / 2, kept doubled (d011 = 2 C011, as eq. 18 uses them) so that they are exact.
  struct Bezier {
    std::int64_t c200, c020, c002;  // Q.30
    std::int64_t d110, d011, d101;  // 2 C110, 2 C011, 2 C101, Q.30
  };
  static Bezier control_points(const std::int64_t c[6]);
  // The Bézier triangle at barycentrics b (Q.30, each in [0, 1]; Brown eq. 18), Q.30, rounded
  // once (the products are summed exactly): at the six points it returns the six cosines.
  static std::int64_t evaluate(const Bezier& z, const std::int64_t b[3]);
  // The smoothstep's range for exponent n, Q.30 (c_hi a little above 1): shade_brown.cpp and
  // docs/DECISIONS.md, "Brown".
  static std::int64_t lower_cosine(std::uint32_t n);
  static std::int64_t upper_cosine(std::uint32_t n);

 private:
  struct Highlight {
    Bezier bezier;
    std::int64_t weight[3];  // ks Il_c, Q.30
  };
  void refresh_material(const ShadeContext& ctx);

  bool cull_ = true;
  GouraudMethod gouraud_;     // the diffuse and ambient colour
  ShadeContext diffuse_ctx_;  // the shading state with ks = 0, for gouraud_
  std::uint64_t revision_ = 0;
  const ShadeContext* ctx_ = nullptr;
  std::int64_t c_lo_ = 0;       // Q.30
  std::int64_t inv_range_ = 0;  // 1 / (c_hi − c_lo), Q.40
  Counters* counters_ = nullptr;
  SteppedBarycentrics bary_;  // Brown eq. 9
  int lights_ = 0;            // highlights on this triangle
  Highlight highlight_[kMaxLights];
};

// 8. Vlasic's quadratic shading (shade_quadratic.cpp; Vlasic 2002, section 4.3): the colour lit
//    at the six points (six_points.hpp) and clamped, the six coefficients of
//    r(s, t) = C0 + C1 s + C2 t + C3 s² + C4 s t + C5 t² by his eq. 4.2, evaluated per pixel
//    and channel at the pixel's (s, t) = (b1, b2) and clamped. Where (s, t) are affine in screen
//    space (an orthographic view, or screen_linear) r is a quadratic along the span: forward
//    differencing, two additions per channel and pixel from the span's first pixel. Under
//    perspective (s, t) are the perspective-correct barycentrics, as Vlasic's "with the
//    perspective divide": eq. 4.1 at every pixel, after one reciprocal. quadratic-screen takes
//    screen-linear (s, t) under perspective too, and forward-differences everywhere.
class QuadraticMethod final : public ShadingMethod {
 public:
  static constexpr bool kLightsVertices = true;  // the vertices' colours through the cache
  explicit QuadraticMethod(bool screen_linear) : screen_linear_(screen_linear) {}
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
  void shade_span(const Span& s, Rgb8* out) override;

  // Vlasic eq. 4.2: the coefficients C0..C5 (Q.30, each an exact integer combination) of the
  // quadratic through r0 at (s, t) = (0, 0), r1 (½, 0), r2 (1, 0), r3 (½, ½), r4 (0, 1) and
  // r5 (0, ½), colours in [0, 1] (Q.30): |C| <= 8.
  struct Coefficients {
    std::int64_t c[6];
  };
  static Coefficients coefficients(const std::int64_t r[6]);
  // Vlasic eq. 4.1 at (s, t) in [0, 1] (Q.30), Q.30 (the products at 28 fraction bits).
  static std::int64_t evaluate(const Coefficients& q, std::int64_t s, std::int64_t t);

  // The forward-differenced values' fraction bits (colour units): Q.52, |r| < 2^5 on a span.
  static constexpr int kForwardFrac = 52;
  // Forward differencing of eq. 4.1 along a span (shared with quadratic-blinn-map's
  // coordinates): whether the barycentrics allow it (affine in x, steps of at most 1), the
  // constant second difference per pixel, and the value and first difference at the span's first
  // pixel (b started there), all Q.52 for values of |r| <= 1 in Q.30.
  struct Forward {
    std::int64_t r, d1;
  };
  static bool can_forward(const SteppedBarycentrics& b);
  static std::int64_t second_difference(const Coefficients& q, const SteppedBarycentrics& b);
  static Forward forward_start(const Coefficients& q, const SteppedBarycentrics& b,
                               std::int64_t d2);

 private:
  bool screen_linear_ = false;
  SteppedBarycentrics bary_;
  Coefficients coef_[3];  // per channel
  // Forward differencing (affine (s, t) with steps of at most one per pixel): r and its first
  // difference at the current pixel and the constant second difference, per channel, Q.52.
  bool forward_ = false;
  std::int64_t r_[3] = {0, 0, 0}, d1_[3] = {0, 0, 0}, d2_[3] = {0, 0, 0};
};

// QuadraticMethod's forward differencing, inline: quadratic and quadratic-blinn-map take it at
// every span's start, per channel or coordinate.
// Forward differencing where s and t are affine in x and move at most 1 per pixel (a sliver's
// spans are a pixel or two long: eq. 4.1 directly there).
inline bool QuadraticMethod::can_forward(const SteppedBarycentrics& b) {
  constexpr std::int64_t kOne = std::int64_t{1} << 40;
  const std::int64_t ds = b.dm()[1], dt = b.dm()[2];  // Q.40
  return b.affine() && (ds < 0 ? -ds : ds) <= kOne && (dt < 0 ? -dt : dt) <= kOne;
}

// The second difference per pixel, 2 (C3 ds² + C4 ds dt + C5 dt²), Q.52: each product through
// Q.50 (|C ds| <= 2^53), so that its error, which adds up k²/2 times over k pixels, stays below
// 2^-28 of a colour unit over 4096.
inline std::int64_t QuadraticMethod::second_difference(const Coefficients& q,
                                                       const SteppedBarycentrics& b) {
  const std::int64_t ds = b.dm()[1], dt = b.dm()[2];  // Q.40
  const auto term = [](std::int64_t c, std::int64_t x, std::int64_t y) {
    return fx::mul_shift_right(fx::mul_shift_right(c, x, 20), y, 90 - kForwardFrac);
  };
  return 2 * (term(q.c[3], ds, ds) + term(q.c[4], ds, dt) + term(q.c[5], dt, dt));
}

// The span's first pixel: r by eq. 4.1, and its first difference
// r(s + ds, t + dt) − r(s, t) = (∂r/∂s) ds + (∂r/∂t) dt + d2 / 2, the gradient at Q.40.
inline QuadraticMethod::Forward QuadraticMethod::forward_start(const Coefficients& q,
                                                               const SteppedBarycentrics& b,
                                                               std::int64_t d2) {
  const std::int64_t s0 = b.m()[1], t0 = b.m()[2];  // Q.40
  const std::int64_t ds = b.dm()[1], dt = b.dm()[2];
  const std::int64_t* c = q.c;
  const std::int64_t gs =
      (c[1] << 10) + 2 * fx::mul_shift_right(c[3], s0, 30) + fx::mul_shift_right(c[4], t0, 30);
  const std::int64_t gt =
      (c[2] << 10) + fx::mul_shift_right(c[4], s0, 30) + 2 * fx::mul_shift_right(c[5], t0, 30);
  return Forward{evaluate(q, fx::round_shift_right(s0, 10), fx::round_shift_right(t0, 10))
                     << (kForwardFrac - 30),
                 fx::mul_shift_right(gs, ds, 80 - kForwardFrac) +
                     fx::mul_shift_right(gt, dt, 80 - kForwardFrac) + d2 / 2};
}

// 9. Gouraud on the triangle subdivided into four at the six points (shade_gouraud_subdivided.cpp;
//    Vlasic's fair comparison for quadratic shading, his Table 6.1): the same six colours as
//    quadratic, each sub-triangle — {v0, m01, m20}, {m01, v1, m12}, {m20, m12, v2} and the middle
//    {m01, m12, m20} — Gouraud-shaded in screen space. A midpoint is where the eye-space
//    midpoint projects: (w_a S_a + w_b S_b) / (w_a + w_b) on screen, rounded to 1/16 pixel, so
//    the pixels are those of Gouraud on the subdivided mesh. Per pixel the three inner edges'
//    exact edge functions (one addition each) pick the sub-triangle; a span's run within one
//    sub-triangle starts exactly and steps as Gouraud's.
class GouraudSubdividedMethod final : public ShadingMethod {
 public:
  static constexpr bool kLightsVertices = true;
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
  void shade_span(const Span& s, Rgb8* out) override;

 private:
  struct Part {
    Triangle tri;  // the sub-triangle's screen positions and area
    ScreenPlane plane[3];
    std::int64_t step[3];     // per pixel, ScreenPlane::kStepFrac more fraction bits
    bool stepped = false;     // steps exact (else every pixel from at())
    bool degenerate = false;  // area2 <= 0 after rounding: its colour is constant
    std::int64_t constant[3];
    // Per channel, its darkest corner's colour and how far above it the brightest is, in the
    // steps' format: the colours a pixel may take. A pixel of the triangle can lie just outside
    // its sub-triangle (the midpoints are rounded to 1/16 pixel off the outer edges), where a
    // sliver's plane extrapolates far: black below an ambient floor (found by review, 2026-12-07).
    std::int64_t lowest[3];
    std::uint64_t range[3];
  };
  void part_start(int k, std::int32_t x, std::int32_t y, std::int64_t c[3]) const;

  // Corners 0, 1, 2, then the middle, whose edges m01→m12, m12→m20 and m20→m01 are the inner
  // edges: a pixel on the far side of one (its edge function negative) is in corner 1, 2 or 0.
  Part part_[4];
};

// 10. Vlasic's environment map (shade_envmap.cpp; Vlasic 2002, section 5.1): diffuse and ambient
//     as Gouraud; the specular part from one RGB sphere map indexed by the reflected view vector
//     W = 2 (N·E) N - E (his eqs. 5.1-5.3), computed at the vertices and interpolated in screen
//     space as Gouraud's colours. The texture holds, summed over the lights, ks Il_c times
//     Blinn's highlight written as a function of W ((1 + W·L) / 2)^(n/2) (texture.hpp); it is
//     built in the method's region when the shading state changes. A sphere map cannot hold a
//     point light: its direction is taken from the centre of the draw's bounding box
//     (ShadeContext::object_centre), and the map rebuilt when that centre moves.
class EnvmapMethod final : public ShadingMethod {
 public:
  static constexpr bool kLightsVertices = true;     // the Gouraud part's vertex colours
  static constexpr bool kNeedsObjectCentre = true;  // for its point lights
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
  void shade_span(const Span& s, Rgb8* out) override;

 private:
  void refresh(const ShadeContext& ctx);

  GouraudMethod gouraud_;     // the diffuse and ambient colour
  ShadeContext diffuse_ctx_;  // the shading state with ks = 0, for gouraud_
  const ShadeContext* ctx_ = nullptr;
  std::uint64_t revision_ = 0;
  bool point_lights_ = false;
  Vec3q16 centre_;  // the point lights' origin the map was built for
  bool specular_ = false;
  SteppedBarycentrics bary_;   // screen-linear
  LinearCoordinate coord_[2];  // the sphere map's (u, v)
  std::uint16_t texture_[texture_texels(kTextureLog2Cells) * 3] = {};
};

// 11. Vlasic's Blinn map and quadratic Blinn map (shade_blinn_map.cpp; sections 5.2 and 5.3):
//     per light, the normal's coordinates in the plane perpendicular to L (diffuse) and to H
//     (specular), his eqs. 5.6 and 5.7, index Blinn's two textures (eqs. 5.4 and 5.5); the
//     colour is ka O + sum_lights Il (kd O D + ks S). The plane's u axis is the camera's up
//     vector projected onto it, or, for a triangle where the plane's vector comes within 25.8°
//     of up (the singularity), the camera's right vector. A normal facing away from the
//     plane's vector (N·L < 0, N·H < 0) is placed outside the unit disk, at radius 2 - r, where
//     the textures are 0. blinn-map computes the coordinates at the vertices and interpolates
//     them in screen space; quadratic (quadratic-blinn-map) at the six points of Vlasic's
//     quadratic shading, through his eq. 4.2, at perspective-correct (s, t), forward-differenced
//     where they are affine (orthographic views) as quadratic's colours are. The textures
//     depend on n alone (the colours are applied per pixel): one pair for every light.
class BlinnMapMethod final : public ShadingMethod {
 public:
  explicit BlinnMapMethod(bool quadratic) : quadratic_(quadratic) {}
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
  void shade_span(const Span& s, Rgb8* out) override;

  // A unit normal's Blinn coordinates (u, v) in the plane perpendicular to unit x (Vlasic
  // eq. 5.6 / 5.7 with u = axis_u · N, v = (x × axis_u) · N), Q.29, with a normal facing away
  // from x moved outside the disk.
  struct Coordinates {
    std::int64_t u = 0, v = 0;
  };
  static Coordinates coordinates(const Vec3u& n, const Vec3u& x, bool up_axis);

 private:
  struct LightTerm {
    std::int64_t diffuse[3];   // Il_c kd O_c, Q.30
    std::int64_t specular[3];  // Il_c ks, Q.30
    // The four coordinates u_D, v_D, u_S, v_S: blinn-map's interpolated in screen space (at[]
    // the current pixel's, Q.40); the quadratic's eq. 4.2 coefficients (Q.29 values) and, where
    // forward-differenced, at[] the current pixel's value with its differences d1, d2 (Q.52).
    LinearCoordinate linear[4];
    std::int64_t at[4], d1[4], d2[4];
    QuadraticMethod::Coefficients quadratic[4];
  };
  void refresh(const ShadeContext& ctx);
  // kAny: the span's way read at run time, one pixel loop for all three (size builds).
  enum class Interpolation { kLinear, kForward, kPerPixel, kAny };
  Interpolation interpolation() const {
    return !quadratic_ ? Interpolation::kLinear
                       : (forward_ ? Interpolation::kForward : Interpolation::kPerPixel);
  }
  template <Interpolation kMode>
  void shade_pixels(int length, Rgb8* out);

  bool quadratic_ = false;
  bool forward_ = false;  // the quadratic's coordinates forward-differenced on this triangle
  const ShadeContext* ctx_ = nullptr;
  std::uint64_t revision_ = 0;
  std::uint32_t built_n_ = 0;  // the specular texture's exponent, 0 before the first
  bool diffuse_built_ = false;
  std::int64_t ambient_[3] = {0, 0, 0};  // ka O_c, Q.30
  SteppedBarycentrics bary_;
  Counters* counters_ = nullptr;
  int lights_ = 0;
  bool diffuse_ = false, specular_ = false;
  LightTerm term_[kMaxLights];
  std::uint16_t diffuse_texture_[texture_texels(kTextureLog2Cells)] = {};
  std::uint16_t specular_texture_[texture_texels(kTextureLog2Cells)] = {};
};

}  // namespace tp::fw
