// Double-precision reference renderer: clip, project, snap, top-left coverage, z-test, shade.
#include "host/reference.hpp"

#include <algorithm>
#include <cmath>

namespace tp::host {

namespace {

__extension__ typedef __int128 i128;  // edge products of far off-screen vertices exceed 64 bits

// A vertex after transformation: clip position, eye position, eye normal.
struct ClipVertex {
  glm::dvec4 clip;
  glm::dvec3 eye;
  glm::dvec3 normal;  // not necessarily unit (see clipping)
};

ClipVertex lerp(const ClipVertex& a, const ClipVertex& b, double t) {
  return {a.clip + t * (b.clip - a.clip), a.eye + t * (b.eye - a.eye),
          a.normal + t * (b.normal - a.normal)};
}

// Sutherland-Hodgman against one homogeneous plane d(v) >= 0.
template <class Dist>
std::vector<ClipVertex> clip_plane(const std::vector<ClipVertex>& in, Dist dist) {
  std::vector<ClipVertex> out;
  for (std::size_t i = 0; i < in.size(); ++i) {
    const ClipVertex& a = in[i];
    const ClipVertex& b = in[(i + 1) % in.size()];
    const double da = dist(a), db = dist(b);
    if (da >= 0) out.push_back(a);
    if ((da >= 0) != (db >= 0)) out.push_back(lerp(a, b, da / (da - db)));
  }
  return out;
}

// Near plane z >= -w, then w > 0 (conventions: clip in homogeneous space before the divide).
std::vector<ClipVertex> clip_near(std::vector<ClipVertex> poly) {
  poly = clip_plane(poly, [](const ClipVertex& v) { return v.clip.z + v.clip.w; });
  if (poly.size() < 3) return {};
  return clip_plane(poly, [](const ClipVertex& v) { return v.clip.w - 1e-12; });
}

struct ScreenVertex {
  std::int64_t x16, y16;  // snapped, 1/16 pixel
  double z_ndc, inv_w;
  glm::dvec3 eye, normal;
};

constexpr std::int64_t kGuard = std::int64_t{1} << 40;  // guard band, in 1/16 pixels

ScreenVertex to_screen(const ClipVertex& v, const FrameSetup& f) {
  const glm::dvec3 ndc = glm::dvec3(v.clip) / v.clip.w;
  const double sx = (ndc.x + 1) / 2 * f.width;  // conventions: viewport
  const double sy = (1 - ndc.y) / 2 * f.height;
  return {std::clamp(snap16(sx), -kGuard, kGuard),
          std::clamp(snap16(sy), -kGuard, kGuard),
          ndc.z,
          1 / v.clip.w,
          v.eye,
          v.normal};
}

// Edge a -> b as E(p) = (bx−ax)(py−ay) − (by−ay)(px−ax), in 1/16² pixel units.
struct Edge {
  std::int64_t ax, ay, dx, dy;
  i128 at(std::int64_t px, std::int64_t py) const {
    return i128(dx) * (py - ay) - i128(dy) * (px - ax);
  }
};

// Top-left rule (conventions): with E oriented positive inside, a pixel centre exactly on the
// edge is covered iff the edge is a left edge (interior towards +x: gradient x > 0) or a top
// edge (horizontal, interior below, y down: gradient x == 0 and gradient y > 0).
bool owns_boundary(const Edge& e, int sign) {
  const std::int64_t gx = -e.dy * sign, gy = e.dx * sign;
  return gx > 0 || (gx == 0 && gy > 0);
}

// The Angular scheme's normal at pixel centre (cx, cy) (see reference.hpp).
glm::dvec3 angular_normal(const ScreenVertex* v[3], double cx, double cy) {
  double xl = 0, xr = 0;
  glm::dvec3 nl(0), nr(0);
  bool any = false;
  for (int k = 0; k < 3; ++k) {
    const ScreenVertex& a = *v[k];
    const ScreenVertex& b = *v[(k + 1) % 3];
    const double ay = a.y16 / 16.0, by = b.y16 / 16.0;
    if (ay == by || cy < std::min(ay, by) || cy > std::max(ay, by)) continue;
    const double t = (cy - ay) / (by - ay);
    const double x = a.x16 / 16.0 + t * (b.x16 - a.x16) / 16.0;
    const glm::dvec3 n = slerp(glm::normalize(a.normal), glm::normalize(b.normal), t);
    if (!any || x < xl) {
      xl = x;
      nl = n;
    }
    if (!any || x > xr) {
      xr = x;
      nr = n;
    }
    any = true;
  }
  if (!any) return glm::normalize(v[0]->normal);
  return xr > xl ? slerp(nl, nr, (cx - xl) / (xr - xl)) : nl;
}

class Rasterizer {
 public:
  Rasterizer(const FrameSetup& f, Interpolation interp, ReferenceImage& out)
      : f_(f), interp_(interp), out_(out) {}

  void triangle(const ScreenVertex& v0, const ScreenVertex& v1, const ScreenVertex& v2) {
    const ScreenVertex* v[3] = {&v0, &v1, &v2};
    // Edges opposite v0, v1, v2: E_12, E_20, E_01; each equals A at its opposite vertex.
    const Edge e[3] = {{v1.x16, v1.y16, v2.x16 - v1.x16, v2.y16 - v1.y16},
                       {v2.x16, v2.y16, v0.x16 - v2.x16, v0.y16 - v2.y16},
                       {v0.x16, v0.y16, v1.x16 - v0.x16, v1.y16 - v0.y16}};
    const i128 area = e[2].at(v2.x16, v2.y16);
    if (area == 0) return;  // zero-area triangles cover nothing
    // Front faces are CCW in NDC, i.e. negative area in y-down screen coordinates.
    if (f_.cull_backfaces && area > 0) return;
    const int sign = area > 0 ? 1 : -1;
    const double abs_area = static_cast<double>(area > 0 ? area : -area);
    bool owns[3];
    for (int k = 0; k < 3; ++k) owns[k] = owns_boundary(e[k], sign);

    const auto [xmin, xmax] = std::minmax({v0.x16, v1.x16, v2.x16});
    const auto [ymin, ymax] = std::minmax({v0.y16, v1.y16, v2.y16});
    // Pixel i has its centre at 16i + 8 (in 1/16 units).
    const std::int64_t i0 = std::max<std::int64_t>(0, (xmin - 8) / 16 - 1);
    const std::int64_t i1 = std::min<std::int64_t>(f_.width - 1, (xmax - 8) / 16 + 1);
    const std::int64_t j0 = std::max<std::int64_t>(0, (ymin - 8) / 16 - 1);
    const std::int64_t j1 = std::min<std::int64_t>(f_.height - 1, (ymax - 8) / 16 + 1);
    for (std::int64_t j = j0; j <= j1; ++j) {
      for (std::int64_t i = i0; i <= i1; ++i) {
        const std::int64_t px = 16 * i + 8, py = 16 * j + 8;
        double lambda[3];
        bool inside = true;
        for (int k = 0; k < 3 && inside; ++k) {
          const i128 ev = e[k].at(px, py) * sign;
          inside = ev > 0 || (ev == 0 && owns[k]);
          lambda[k] = static_cast<double>(ev) / abs_area;
        }
        if (inside) pixel(static_cast<int>(i), static_cast<int>(j), v, lambda);
      }
    }
  }

 private:
  void pixel(int i, int j, const ScreenVertex* v[3], const double lambda[3]) {
    const std::size_t idx = static_cast<std::size_t>(j) * static_cast<std::size_t>(f_.width) +
                            static_cast<std::size_t>(i);
    ++out_.coverage[idx];
    // NDC z is affine in screen space: screen-linear barycentrics.
    const double z = lambda[0] * v[0]->z_ndc + lambda[1] * v[1]->z_ndc + lambda[2] * v[2]->z_ndc;
    if (!(z < out_.depth[idx])) return;  // strictly nearer wins
    out_.depth[idx] = z;
    out_.mask[idx] = 1;
    // Perspective-correct (hyperbolic) barycentrics.
    double h[3], hs = 0;
    for (int k = 0; k < 3; ++k) hs += h[k] = lambda[k] * v[k]->inv_w;
    glm::dvec3 p(0), n(0);
    for (int k = 0; k < 3; ++k) {
      p += (h[k] / hs) * v[k]->eye;
      n += (h[k] / hs) * v[k]->normal;
    }
    if (interp_ == Interpolation::Angular)
      n = angular_normal(v, i + 0.5, j + 0.5);
    else
      n = glm::length(n) > 0 ? glm::normalize(n) : glm::dvec3(0, 0, 1);
    const glm::dvec3 c = blinn_phong(n, p, f_);
    float* lin = out_.linear.at(i, j);
    float* cl = out_.clamped.at(i, j);
    std::uint8_t* b = out_.rgb8.at(i, j);
    for (int k = 0; k < 3; ++k) {
      const double clamped = std::clamp(c[k], 0.0, 1.0);
      lin[k] = static_cast<float>(c[k]);
      cl[k] = static_cast<float>(clamped);
      b[k] = static_cast<std::uint8_t>(std::lround(255 * clamped));  // ties away from zero
    }
  }

  const FrameSetup& f_;
  Interpolation interp_;
  ReferenceImage& out_;
};

}  // namespace

std::int64_t snap16(double s) { return static_cast<std::int64_t>(std::round(s * 16)); }

glm::dvec3 slerp(const glm::dvec3& a, const glm::dvec3& b, double t) {
  const double c = std::clamp(glm::dot(a, b), -1.0, 1.0);
  const double omega = std::acos(c);
  const double s = std::sin(omega);
  if (s < 1e-9) {
    const glm::dvec3 l = a + t * (b - a);
    return glm::length(l) > 0 ? glm::normalize(l) : a;
  }
  return (std::sin((1 - t) * omega) / s) * a + (std::sin(t * omega) / s) * b;
}

glm::dvec3 blinn_phong(const glm::dvec3& n, const glm::dvec3& p, const FrameSetup& f) {
  const Material& m = f.material;
  const glm::dvec3 v = f.eye_at_infinity ? glm::dvec3(0, 0, 1) : glm::normalize(-p);
  glm::dvec3 c = m.ka * m.colour;  // Ia = (1, 1, 1)
  for (const EyeLight& light : f.lights) {
    const glm::dvec3 l =
        light.kind == LightKind::Point ? glm::normalize(light.vector - p) : light.vector;
    const glm::dvec3 lv = l + v;
    const double nl = std::max(0.0, glm::dot(n, l));
    // No N·L gate on the specular term (conventions: the formula as written).
    const double nh = glm::length(lv) > 0 ? std::max(0.0, glm::dot(n, glm::normalize(lv))) : 0.0;
    c += light.colour * (m.kd * nl * m.colour + glm::dvec3(m.ks * std::pow(nh, m.n)));
  }
  return c;
}

FrameSetup frame_setup(const Scene& s, int width, int height) {
  FrameSetup f;
  f.width = width > 0 ? width : s.width;
  f.height = height > 0 ? height : s.height;
  f.projection = projection_matrix(s.camera, f.width, f.height);
  f.eye_at_infinity = eye_at_infinity(s.camera);
  f.lights = eye_lights(s);
  f.material = s.material;
  f.cull_backfaces = s.cull_backfaces;
  f.background = s.background;
  return f;
}

std::vector<DrawMesh> draw_list(const Scene& s) {
  std::vector<DrawMesh> out;
  for (const MeshSpec& m : s.meshes) out.push_back({&m.mesh, model_view(s, m)});
  return out;
}

ReferenceImage render_reference(const FrameSetup& f, const std::vector<DrawMesh>& meshes,
                                Interpolation interp) {
  ReferenceImage out;
  const std::size_t npix = static_cast<std::size_t>(f.width) * static_cast<std::size_t>(f.height);
  out.linear = FloatImage(f.width, f.height);
  out.clamped = FloatImage(f.width, f.height);
  out.rgb8 = Image8(f.width, f.height);
  out.mask.assign(npix, 0);
  out.depth.assign(npix, 1.0);  // cleared to the far value
  out.coverage.assign(npix, 0);
  const std::uint8_t bg8[3] = {static_cast<std::uint8_t>(std::lround(255 * f.background.r)),
                               static_cast<std::uint8_t>(std::lround(255 * f.background.g)),
                               static_cast<std::uint8_t>(std::lround(255 * f.background.b))};
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x)
      for (int k = 0; k < 3; ++k) {
        out.linear.at(x, y)[k] = out.clamped.at(x, y)[k] = static_cast<float>(f.background[k]);
        out.rgb8.at(x, y)[k] = bg8[k];
      }
  Rasterizer raster(f, interp, out);
  for (const DrawMesh& dm : meshes) {
    const glm::dmat3 nmat(dm.model_view);
    for (const auto& t : dm.mesh->triangles) {
      std::vector<ClipVertex> poly;
      for (auto vi : t) {
        const glm::dvec3 eye = glm::dvec3(dm.model_view * glm::dvec4(dm.mesh->positions[vi], 1));
        poly.push_back(
            {f.projection * glm::dvec4(eye, 1), eye, glm::normalize(nmat * dm.mesh->normals[vi])});
      }
      poly = clip_near(std::move(poly));
      if (poly.size() < 3) continue;
      std::vector<ScreenVertex> sv;
      sv.reserve(poly.size());
      for (const auto& cv : poly) sv.push_back(to_screen(cv, f));
      if (interp == Interpolation::Angular)
        for (auto& s : sv) s.normal = glm::normalize(s.normal);
      for (std::size_t k = 1; k + 1 < sv.size(); ++k) raster.triangle(sv[0], sv[k], sv[k + 1]);
    }
  }
  return out;
}

ReferenceImage render_reference(const Scene& s, Interpolation interp, int width, int height) {
  return render_reference(frame_setup(s, width, height), draw_list(s), interp);
}

}  // namespace tp::host
