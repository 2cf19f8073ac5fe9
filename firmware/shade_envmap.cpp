// Vlasic's environment map (methods.hpp, 10): setup reflects the view at the vertices and takes
// the sphere map's coordinates there; the pixel loop adds Gouraud's diffuse-and-ambient colour
// and the map's bilinear sample at the screen-linear coordinates.
#include "firmware/methods.hpp"

namespace tp::fw {
namespace {

constexpr std::int64_t kOne30 = std::int64_t{1} << 30;

bool has_point_light(const ShadeContext& ctx) {
  for (const LightState& l : ctx.lights)
    if (contributes(l) && l.type == LightType::kPoint) return true;
  return false;
}
bool has_light(const ShadeContext& ctx) {
  for (const LightState& l : ctx.lights)
    if (contributes(l)) return true;
  return false;
}

// The sphere map's coordinates of the view E reflected about the unit normal N: W = 2 (N·E) N - E,
// then Vlasic eqs. 5.1-5.3 centred on the texture, (u, v) = (W_x, W_y) / |W + (0, 0, 1)|: the x
// and y of the unit vector along (W_x, W_y, W_z + 1). W = (0, 0, -1) (a normal perpendicular to
// the view) is the map's rim, any point of which holds it.
void sphere_coordinates(const Vec3u& n, const Vec3u& e, std::int64_t& u, std::int64_t& v) {
  const std::int64_t ne = fx::dot<q1_30>(n, e).raw();
  const auto reflect = [ne](q1_30 nc, q1_30 ec) {
    return fx::round_shift_right(ne * nc.raw(), 29) - ec.raw();
  };
  const Vec3u s =
      fx::normalize_fast(reflect(n.x, e.x), reflect(n.y, e.y), reflect(n.z, e.z) + kOne30);
  if (s.x.raw() == 0 && s.y.raw() == 0 && s.z.raw() == 0) {
    u = kCoordOne;
    v = 0;
    return;
  }
  u = fx::round_shift_right(s.x.raw(), 30 - kCoordFrac);
  v = fx::round_shift_right(s.y.raw(), 30 - kCoordFrac);
}

}  // namespace

// The shading state without the specular term for the Gouraud part, and the map, when the
// state changes or, with a point light, when the draw's centre moves.
void EnvmapMethod::refresh(const ShadeContext& ctx) {
  const bool changed = ctx.revision == 0 || &ctx != ctx_ || ctx.revision != revision_;
  if (changed) {
    ctx_ = &ctx;
    revision_ = ctx.revision;
    diffuse_ctx_ = ctx;
    diffuse_ctx_.material.ks = q1_30::zero();
    point_lights_ = has_point_light(ctx);
    specular_ = ctx.material.ks.raw() != 0 && has_light(ctx);
  }
  if (!specular_) return;
  const bool moved = point_lights_ && !(ctx.object_centre == centre_);
  if (changed || moved) {
    centre_ = ctx.object_centre;
    build_sphere_map(texture_, kTextureLog2Cells, ctx, centre_);
  }
}

bool EnvmapMethod::setup(const Triangle& tri, const ShadeContext& ctx) {
  refresh(ctx);
  diffuse_ctx_.counters = ctx.counters;
  gouraud_.setup(tri, diffuse_ctx_);
  if (!specular_) return true;
  for (int i = 0; i < 3; ++i) {
    const Vec3u e = eye_direction(ctx, tri.v[i].eye);
    sphere_coordinates(tri.v[i].normal, e, coord_[0].vertex[i], coord_[1].vertex[i]);
  }
  ctx.counters->normalizations += ctx.eye == EyeMode::kFinite ? 6u : 3u;
  bary_.setup(tri, true);  // the coordinates are interpolated in screen space, as colours are
  coord_[0].setup(bary_);
  coord_[1].setup(bary_);
  return true;
}

void EnvmapMethod::shade_span(const Span& s, Rgb8* out) {
  LinearColours g = gouraud_.linear_span(s);  // diffuse and ambient, as Gouraud
  constexpr int k = LinearColours::kShift;
  const int length = s.x1 - s.x0;
  if (!specular_) {
    for (int x = 0; x < length; ++x) {
      out[x] = Rgb8{static_cast<std::uint8_t>(g.c[0] >> k), static_cast<std::uint8_t>(g.c[1] >> k),
                    static_cast<std::uint8_t>(g.c[2] >> k)};
      for (int ch = 0; ch < 3; ++ch) g.c[ch] += g.dc[ch];
    }
    return;
  }
  bary_.start(s.x0, s.y);  // the coordinates at the span's first pixel and their step, Q.40
  std::int64_t c[2] = {coord_[0].start(bary_), coord_[1].start(bary_)};
  const std::int64_t dc[2] = {coord_[0].step, coord_[1].step};
  constexpr std::int64_t kTop = std::int64_t{255} << k;
  for (int x = 0; x < length; ++x) {
    const TexelPosition p =
        texel_position(c[0] >> (40 - kCoordFrac), c[1] >> (40 - kCoordFrac), kTextureLog2Cells);
    std::uint8_t level[3];
    for (int ch = 0; ch < 3; ++ch) {
      // The map's ks sum_l Il_c highlight_l (Q1.15) in the colours' units, on Gouraud's colour.
      const std::int64_t spec = sample_bilinear(texture_ + ch, kTextureLog2Cells, 3, p);
      const std::int64_t acc = g.c[ch] + 255 * (spec << (k - kTexelFrac));
      level[ch] = static_cast<std::uint8_t>((acc > kTop ? kTop : acc) >> k);
      g.c[ch] += g.dc[ch];
    }
    out[x] = Rgb8{level[0], level[1], level[2]};
    c[0] += dc[0];
    c[1] += dc[1];
  }
}

}  // namespace tp::fw
