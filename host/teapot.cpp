// The Utah teapot tessellated from Newell's 32 bicubic Bézier patches.
//
// Facet count: each patch becomes tess × tess quads = 2·tess² triangles. Eight patches (the
// four at the top of the lid knob and the four of the bottom) have their whole first row of
// control points collapsed into one point (a pole), so the first row of quads of each of them
// has one zero-area triangle per quad; those are dropped. Hence 64·tess² − 8·tess triangles:
// tess = 8 gives 4096 − 64 = 4032, the uniform tessellation closest to Vlasic's "3750 facets"
// (tess = 7 gives 3080).
//
// Normals: from the patch derivatives, N = ∂P/∂v × ∂P/∂u (outward for this data's patch
// orientation). At the poles both a row of control points and hence ∂P/∂v vanish; there the
// normal is taken a small step (1e-5 in u) inside the patch, its limit.
#include <cmath>
#include <map>
#include <tuple>

#include "host/meshes.hpp"

namespace tp::host {

namespace {

#include "host/teapot_data.inc"

struct PatchPoint {
  glm::dvec3 p, du, dv;
};

void bernstein(double t, double b[4], double d[4]) {
  const double s = 1 - t;
  b[0] = s * s * s;
  b[1] = 3 * s * s * t;
  b[2] = 3 * s * t * t;
  b[3] = t * t * t;
  d[0] = -3 * s * s;
  d[1] = 3 * s * s - 6 * s * t;
  d[2] = 6 * s * t - 3 * t * t;
  d[3] = 3 * t * t;
}

PatchPoint eval_patch(int patch, double u, double v) {
  double bu[4], du[4], bv[4], dv[4];
  bernstein(u, bu, du);
  bernstein(v, bv, dv);
  PatchPoint r{glm::dvec3(0), glm::dvec3(0), glm::dvec3(0)};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      const double* c = kTeapotPoints[kTeapotPatches[patch][4 * i + j] - 1];
      const glm::dvec3 cp(c[0], c[1], c[2]);
      r.p += bu[i] * bv[j] * cp;
      r.du += du[i] * bv[j] * cp;
      r.dv += bu[i] * dv[j] * cp;
    }
  return r;
}

glm::dvec3 patch_normal(int patch, double u, double v) {
  PatchPoint q = eval_patch(patch, u, v);
  glm::dvec3 n = glm::cross(q.dv, q.du);
  if (glm::length(n) < 1e-10) {
    // A pole (degenerate row): use the limit from inside the patch.
    const double eps = 1e-5;
    q = eval_patch(patch, u < 0.5 ? u + eps : u - eps, v < 0.5 ? v + eps : v - eps);
    n = glm::cross(q.dv, q.du);
  }
  return glm::normalize(n);
}

glm::dvec3 z_up_to_y_up(glm::dvec3 p) { return {p.x, p.z, -p.y}; }  // rotation −90° about x

// Welds vertices of neighbouring patches: the same position (to 1e-9) gets bit-identical
// coordinates, so shared patch boundaries rasterize without cracks; vertices with different
// normals (creases) stay separate.
class Welder {
 public:
  explicit Welder(Mesh& m) : m_(m) {}
  std::uint32_t add(glm::dvec3 p, glm::dvec3 n) {
    const auto key =
        std::make_tuple(std::llround(p.x * 1e9), std::llround(p.y * 1e9), std::llround(p.z * 1e9));
    auto& same = at_[key];
    for (std::uint32_t i : same) {
      if (glm::length(m_.normals[i] - n) < 1e-6) return i;
    }
    if (!same.empty()) p = m_.positions[same.front()];
    m_.positions.push_back(p);
    m_.normals.push_back(n);
    same.push_back(static_cast<std::uint32_t>(m_.positions.size() - 1));
    return same.back();
  }

 private:
  Mesh& m_;
  std::map<std::tuple<long long, long long, long long>, std::vector<std::uint32_t>> at_;
};

}  // namespace

int teapot_triangle_count(int tess) { return 64 * tess * tess - 8 * tess; }

Mesh teapot(int tess) {
  Mesh m;
  Welder weld(m);
  for (int patch = 0; patch < 32; ++patch) {
    std::vector<std::uint32_t> grid;
    for (int i = 0; i <= tess; ++i)
      for (int j = 0; j <= tess; ++j) {
        const double u = static_cast<double>(i) / tess, v = static_cast<double>(j) / tess;
        const glm::dvec3 p = eval_patch(patch, u, v).p;
        grid.push_back(weld.add(z_up_to_y_up(p), z_up_to_y_up(patch_normal(patch, u, v))));
      }
    auto at = [&](int i, int j) { return grid[static_cast<std::size_t>(i * (tess + 1) + j)]; };
    for (int i = 0; i < tess; ++i)
      for (int j = 0; j < tess; ++j) {
        const std::array<std::uint32_t, 3> tris[2] = {{at(i, j), at(i + 1, j), at(i + 1, j + 1)},
                                                      {at(i, j), at(i + 1, j + 1), at(i, j + 1)}};
        for (auto t : tris) {
          const glm::dvec3 g = glm::cross(m.positions[t[1]] - m.positions[t[0]],
                                          m.positions[t[2]] - m.positions[t[0]]);
          if (glm::length(g) < 1e-14) continue;  // pole triangle (see the header comment)
          // CCW seen from the normal side: orient by the vertex normals.
          if (glm::dot(g, m.normals[t[0]] + m.normals[t[1]] + m.normals[t[2]]) < 0)
            std::swap(t[1], t[2]);
          m.triangles.push_back(t);
        }
      }
  }
  return m;
}

}  // namespace tp::host
