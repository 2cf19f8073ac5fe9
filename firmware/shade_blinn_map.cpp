// Vlasic's Blinn map and quadratic Blinn map (methods.hpp, 11): setup takes each light's four
// texture coordinates at the vertices (blinn-map) or the six points (quadratic-blinn-map); the
// pixel loop interpolates them, linearly in screen space or by eq. 4.1, and sums the lights'
// diffuse and specular texture samples.
#include "firmware/build.hpp"
#include "firmware/methods.hpp"
#include "firmware/six_points.hpp"

namespace tp::fw {
namespace {

constexpr std::int64_t kOne30 = std::int64_t{1} << 30;

// The singularity: where the plane's vector comes within acos(0.9) = 25.8° of the camera's up
// vector, its projection is short and turns fast, and the triangle takes the right vector instead.
constexpr std::int64_t kAxisLimit = kOne30 * 9 / 10;

std::int64_t dot30(const Vec3u& a, const Vec3u& b) { return fx::dot<q1_30>(a, b).raw(); }
std::int64_t magnitude(std::int64_t v) { return v < 0 ? -v : v; }

// The four coordinates: u_D, v_D in the plane of L, u_S, v_S in the plane of H.
constexpr int kCoordinates = 4;

}  // namespace

BlinnMapMethod::Coordinates BlinnMapMethod::coordinates(const Vec3u& n, const Vec3u& x,
                                                        bool up_axis) {
  // û: the global axis g (up (0, 1, 0) or right (1, 0, 0)) projected onto the plane, g - (g·x) x,
  // renormalised; v̂ = x × û (Vlasic, Figure 5.7).
  const std::int64_t gx = (up_axis ? x.y : x.x).raw();
  const Vec3u axis_u =
      fx::normalize_fast((up_axis ? 0 : std::int64_t{1} << 60) - gx * x.x.raw(),
                         (up_axis ? std::int64_t{1} << 60 : 0) - gx * x.y.raw(), -gx * x.z.raw());
  const Vec3u axis_v = fx::cross<q1_30>(x, axis_u);
  // Vlasic eqs. 5.6 and 5.7: û · (N - (N·x) x) = û · N, as û is in the plane (and so is v̂).
  const std::int64_t u = dot30(axis_u, n), v = dot30(axis_v, n);  // Q.30
  if (dot30(n, x) >= 0)
    return Coordinates{fx::round_shift_right(u, 30 - kCoordFrac),
                       fx::round_shift_right(v, 30 - kCoordFrac)};
  // N faces away from x, where the textures' max(0, ·) is 0; its projection would sit inside
  // the disk beside the front's. Moved to radius 2 - r on the same ray (the rim stays put), it
  // lies where the textures are 0, and interpolation to a front normal crosses the rim between.
  // With 1/r from the sample-grade reciprocal root (no division): (2 - r) / r = 2 / r - 1.
  const std::int64_t r2 = u * u + v * v;  // Q.60, <= 2^60 (1 + 2^-28)
  if (r2 < (std::int64_t{1} << 20)) return Coordinates{2 * kCoordOne, 0};  // r < 2^-20: no ray
  const fx::RsqrtFast inv = fx::rsqrt_fast(static_cast<std::uint64_t>(r2));
  const auto away = [&](std::int64_t c) {  // 2 c / r - c, Q.30, to Q.29 (|c / r| <= 1)
    return fx::round_shift_right(2 * ((c * inv.r) >> inv.shift) - c, 30 - kCoordFrac);
  };
  return Coordinates{away(u), away(v)};
}

// The textures for the material, and its per-light weights' common factors.
void BlinnMapMethod::refresh(const ShadeContext& ctx) {
  if (ctx.revision != 0 && &ctx == ctx_ && ctx.revision == revision_) return;
  ctx_ = &ctx;
  revision_ = ctx.revision;
  const MaterialCmd& m = ctx.material;
  diffuse_ = m.kd.raw() != 0;
  specular_ = m.ks.raw() != 0;
  for (int ch = 0; ch < 3; ++ch)
    ambient_[ch] = fx::mul_shift_right(m.ka.raw(), m.color[ch].raw(), 30);
  if (diffuse_ && !diffuse_built_) {
    build_blinn_diffuse(diffuse_texture_, kTextureLog2Cells);
    diffuse_built_ = true;
  }
  if (specular_ && built_n_ != m.n) {
    build_blinn_specular(specular_texture_, kTextureLog2Cells, m.n);
    built_n_ = m.n;
  }
}

bool BlinnMapMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  refresh(ctx);
  counters_ = ctx.counters;
  bary_.setup(tri, !quadratic_);  // blinn-map: screen-linear; quadratic: Vlasic's (s, t)
  // The quadratic's coordinates forward-differenced where (s, t) are affine in x (orthographic
  // views), as quadratic shading's colours; else eq. 4.1 per pixel.
  forward_ = quadratic_ && QuadraticMethod::can_forward(bary_);
  lights_ = 0;
  if (!diffuse_ && !specular_) return true;
  // The points: the vertices, and for the quadratic the edge midpoints too.
  const int points = quadratic_ ? 6 : 3;
  SixPoints six;
  if (quadratic_) {
    six = six_points(tri);
    counters_->normalizations += 3;
  } else {
    for (int i = 0; i < 3; ++i) {
      six.normal[i] = tri.v[i].normal;
      six.point[i] = tri.v[i].eye;
    }
  }
  Vec3u eye[6];
  for (int k = 0; k < points; ++k) eye[k] = eye_direction(ctx, six.point[k]);
  if (ctx.eye == EyeMode::kFinite) counters_->normalizations += static_cast<std::uint64_t>(points);

  const MaterialCmd& m = ctx.material;
  for (const LightState& l : ctx.lights) {
    if (!contributes(l)) continue;
    LightTerm& t = term_[lights_++];
    for (int ch = 0; ch < 3; ++ch) {  // Il_c kd O_c and Il_c ks: Q.30 × Q15.16 -> Q.30
      t.diffuse[ch] = fx::mul_shift_right(fx::mul_shift_right(m.kd.raw(), m.color[ch].raw(), 30),
                                          l.color[ch].raw(), 16);
      t.specular[ch] = fx::mul_shift_right(m.ks.raw(), l.color[ch].raw(), 16);
    }
    // The planes' vectors at the points: L for the diffuse texture, H for the specular one.
    Vec3u plane[2][6];
    for (int k = 0; k < points; ++k) {
      const LightAndHalfway v = light_and_halfway(l, six.point[k], eye[k], *counters_);
      plane[0][k] = v.l;
      plane[1][k] = v.h;
    }
    std::int64_t coord[kCoordinates][6];
    for (int p = 0; p < 2; ++p) {
      bool up_axis = true;  // one axis for the whole triangle, so its coordinates agree
      for (int k = 0; k < points; ++k)
        up_axis = up_axis && magnitude(plane[p][k].y.raw()) <= kAxisLimit;
      for (int k = 0; k < points; ++k) {
        const Coordinates c = coordinates(six.normal[k], plane[p][k], up_axis);
        coord[2 * p][k] = c.u;
        coord[2 * p + 1][k] = c.v;
      }
    }
    for (int a = 0; a < kCoordinates; ++a) {
      if (quadratic_) {
        std::int64_t r[6];  // Vlasic eq. 4.2 on the coordinates
        for (int k = 0; k < 6; ++k) r[k] = coord[a][kEq42Order[k]];
        t.quadratic[a] = QuadraticMethod::coefficients(r);
        if (forward_) t.d2[a] = QuadraticMethod::second_difference(t.quadratic[a], bary_);
      } else {
        for (int i = 0; i < 3; ++i) t.linear[a].vertex[i] = coord[a][i];
        t.linear[a].setup(bary_);
      }
    }
  }
  return true;
}

void BlinnMapMethod::shade_span(const Span& s, Rgb8* out) {
  const int length = s.x1 - s.x0;
  bary_.start(s.x0, s.y);
  // The coordinates at the span's first pixel: blinn-map's Q.40, the forward-differenced
  // quadratic's value and first difference (Q.52 for the Q.29 coordinate read as Q.30).
  for (int j = 0; j < lights_; ++j)
    for (int a = 0; a < kCoordinates; ++a) {
      LightTerm& t = term_[j];
      if (!quadratic_) {
        t.at[a] = t.linear[a].start(bary_);
      } else if (forward_) {
        const QuadraticMethod::Forward f =
            QuadraticMethod::forward_start(t.quadratic[a], bary_, t.d2[a]);
        t.at[a] = f.r;
        t.d1[a] = f.d1;
      }
    }
  if constexpr (kSizeBuild)
    shade_pixels<Interpolation::kAny>(length, out);
  else if (!quadratic_)
    shade_pixels<Interpolation::kLinear>(length, out);
  else if (forward_)
    shade_pixels<Interpolation::kForward>(length, out);
  else
    shade_pixels<Interpolation::kPerPixel>(length, out);
  counters_->specular_evaluations +=
      static_cast<std::uint64_t>(length) * static_cast<std::uint64_t>(lights_);
}

// The pixel loop, one instance per way of interpolating the coordinates in speed builds, where
// mode is a constant and only its branch is compiled; one for all three in size builds.
template <BlinnMapMethod::Interpolation kMode>
void BlinnMapMethod::shade_pixels(int length, Rgb8* out) {
  const Interpolation mode = kMode == Interpolation::kAny ? interpolation() : kMode;
  constexpr int kForwardShift = QuadraticMethod::kForwardFrac - 30;
  constexpr int kAccFrac = 30 + kTexelFrac;  // weights Q.30 times samples Q1.15
  constexpr std::int64_t kAccOne = std::int64_t{1} << kAccFrac;
  // The loop's invariants in locals: the output's byte stores may alias any member.
  const bool diffuse = diffuse_, specular = specular_;
  const int lights = lights_;
  LightTerm* const terms = term_;
  const std::uint16_t* const diffuse_texture = diffuse_texture_;
  const std::uint16_t* const specular_texture = specular_texture_;
  const std::int64_t ambient[3] = {ambient_[0] << kTexelFrac, ambient_[1] << kTexelFrac,
                                   ambient_[2] << kTexelFrac};
  for (int x = 0; x < length; ++x) {
    std::int64_t b[3];  // (s, t) = (b1, b2) for eq. 4.1
    if (mode == Interpolation::kPerPixel) bary_.next(b);
    std::int64_t acc[3] = {ambient[0], ambient[1], ambient[2]};
    for (int j = 0; j < lights; ++j) {
      LightTerm& t = terms[j];
      std::int64_t c[kCoordinates];  // Q.29
      for (int a = 0; a < kCoordinates; ++a) {
        if (mode == Interpolation::kLinear) {  // one addition per coordinate
          c[a] = t.at[a] >> (40 - kCoordFrac);
          t.at[a] += t.linear[a].step;
        } else if (mode == Interpolation::kForward) {  // two additions
          c[a] = t.at[a] >> kForwardShift;
          t.at[a] += t.d1[a];
          t.d1[a] += t.d2[a];
        } else {
          c[a] = QuadraticMethod::evaluate(t.quadratic[a], b[1], b[2]);  // Vlasic eq. 4.1
        }
      }
      if (diffuse) {  // Vlasic eq. 5.4's texture at (u_D, v_D)
        const std::int64_t d = sample_bilinear(diffuse_texture, kTextureLog2Cells, 1,
                                               texel_position(c[0], c[1], kTextureLog2Cells));
        for (int ch = 0; ch < 3; ++ch) acc[ch] += t.diffuse[ch] * d;
      }
      if (specular) {  // eq. 5.5's at (u_S, v_S)
        const std::int64_t sp = sample_bilinear(specular_texture, kTextureLog2Cells, 1,
                                                texel_position(c[2], c[3], kTextureLog2Cells));
        for (int ch = 0; ch < 3; ++ch) acc[ch] += t.specular[ch] * sp;
      }
    }
    std::uint8_t level[3];
    for (int ch = 0; ch < 3; ++ch) {
      const std::int64_t v = acc[ch] > kAccOne ? kAccOne : acc[ch];  // >= 0: every term is
      level[ch] = static_cast<std::uint8_t>((255 * v + (kAccOne >> 1)) >> kAccFrac);
    }
    out[x] = Rgb8{level[0], level[1], level[2]};
  }
}

}  // namespace tp::fw
