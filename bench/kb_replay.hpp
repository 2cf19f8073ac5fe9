// Replays a frame's triangles through a Kuijk-Blake method outside the device, for the
// benchmark (setup vs per-pixel split) and the tests (coherent vs exact span setup): the device
// state after rendering a scene gives the matrices and lighting, the scene's mesh the vertices;
// transform, clip, project and cull as the device does (firmware/geometry.hpp), no depth test.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <vector>

#include "firmware/geometry.hpp"
#include "firmware/kb/kb_methods.hpp"
#include "firmware/raster.hpp"
#include "host/device_renderer.hpp"
#include "host/scene.hpp"

namespace tp::kbbench {

// The frame's triangles as the device's rasterizer sees them (transform, clip, project, cull),
// from the state the device holds after rendering the scene (one mesh per paper scene).
struct Frame {
  std::vector<fw::Triangle> tris;
  fw::ShadeContext ctx;
  fw::Counters counters;
  int width = 0, height = 0;
};

inline Frame replay_frame(host::DeviceRenderer& r, const host::Scene& scene) {
  Frame f;
  const fw::DeviceState& st = r.device().state();
  f.ctx = st.shading;
  f.ctx.counters = &f.counters;
  f.width = scene.width;
  f.height = scene.height;
  const host::Mesh& mesh = scene.meshes.at(0).mesh;
  const auto q = [](double v, int frac) {
    return static_cast<std::int32_t>(std::llround(std::ldexp(v, frac)));
  };
  std::vector<fw::ClipVertex> cv(mesh.positions.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    fw::Vertex v;
    const auto& p = mesh.positions[i];
    const auto& n = mesh.normals[i];
    v.position = {fw::q15_16::from_raw(q(p.x, 16)), fw::q15_16::from_raw(q(p.y, 16)),
                  fw::q15_16::from_raw(q(p.z, 16))};
    v.normal = {fw::q1_30::from_raw(q(n.x, 30)), fw::q1_30::from_raw(q(n.y, 30)),
                fw::q1_30::from_raw(q(n.z, 30))};
    fw::transform_vertex(st.modelview, st.projection, v, cv[i]);
  }
  for (const auto& t : mesh.triangles) {
    const fw::ClipVertex in[3] = {cv[t[0]], cv[t[1]], cv[t[2]]};
    fw::ClipVertex poly[fw::kMaxClipVertices];
    const fw::ClipResult cr = fw::clip_triangle(in, poly);
    if (cr.count < 3) continue;
    fw::ShadeVertex sv[fw::kMaxClipVertices];
    for (int i = 0; i < cr.count; ++i) sv[i] = fw::project(poly[i], f.width, f.height);
    for (int i = 1; i + 1 < cr.count; ++i) {
      fw::Triangle tri;
      const std::int64_t area2 = fw::edge_function(sv[0], sv[i], sv[i + 1].sx, sv[i + 1].sy);
      if (area2 >= 0) continue;  // back-facing (culled) or degenerate
      tri.v[0] = sv[0];
      tri.v[1] = sv[i + 1];
      tri.v[2] = sv[i];
      tri.area2 = -area2;
      f.tris.push_back(tri);
    }
  }
  return f;
}

// Coherent span setup against the exact one, span by span (no depth test needed).
struct CoherenceTarget final : fw::SpanTarget {
  fw::kb::KbOneVectorMethod *coherent = nullptr, *exact = nullptr;
  fw::Rgb8 a[fw::kMaxDimension], b[fw::kMaxDimension];
  long long pixels = 0, differing = 0, sum = 0;
  int max = 0;
  void span(const fw::Span& s) override {
    coherent->shade_span(s, a);
    exact->shade_span(s, b);
    for (int i = 0; i < s.x1 - s.x0; ++i) {
      const int d = std::max(
          {std::abs(a[i].r - b[i].r), std::abs(a[i].g - b[i].g), std::abs(a[i].b - b[i].b)});
      ++pixels;
      differing += d > 0;
      sum += d;
      max = std::max(max, d);
    }
  }
};

// The frame's triangles shaded by the coherent and by the exact span setup side by side: how
// many pixels differ and by how much.
struct CoherenceDiff {
  long long pixels = 0, differing = 0, sum = 0;
  int max = 0;
};
inline CoherenceDiff compare_coherent_with_exact(const Frame& f) {
  auto coherent = std::make_unique<fw::kb::KbOneVectorMethod>(true, true);
  auto exact = std::make_unique<fw::kb::KbOneVectorMethod>(true, false);
  auto target = std::make_unique<CoherenceTarget>();
  target->coherent = coherent.get();
  target->exact = exact.get();
  for (const auto& t : f.tris) {
    coherent->setup(t, f.ctx);
    exact->setup(t, f.ctx);
    fw::rasterize(t, f.width, f.height, *target);
  }
  return {target->pixels, target->differing, target->sum, target->max};
}

}  // namespace tp::kbbench
