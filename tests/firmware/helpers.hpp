// Test helpers: a device over a heap block (the host side may allocate), float -> fixed
// conversion, meshes, and matrix conversion from GLM.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "firmware/device.hpp"
#include "firmware/registry.hpp"

namespace tp::fw::test {

// Every method the device implements: the registry's ids (firmware/registry.hpp).
inline constexpr auto kImplementedMethods = [] {
  std::array<Method, std::size(kMethodTable)> ids{};
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = kMethodTable[i].id;
  return ids;
}();

inline q15_16 q16(double v) {
  return q15_16::from_raw(static_cast<std::int32_t>(std::llround(v * 65536.0)));
}
inline q1_30 q30(double v) {
  return q1_30::from_raw(static_cast<std::int32_t>(std::llround(v * 1073741824.0)));
}
inline double d16(q15_16 v) { return v.raw() / 65536.0; }
inline double d30(q1_30 v) { return v.raw() / 1073741824.0; }

inline Mat4 to_mat4(const glm::dmat4& m) {
  Mat4 r;
  for (int c = 0; c < 4; ++c)
    for (int k = 0; k < 4; ++k) r.m[c][k] = q16(m[c][k]);
  return r;
}

inline Vertex vertex(glm::dvec3 p, glm::dvec3 n) {
  n = glm::normalize(n);
  return Vertex{Vec3q16{q16(p.x), q16(p.y), q16(p.z)}, Vec3u{q30(n.x), q30(n.y), q30(n.z)}};
}

struct Mesh {
  std::vector<glm::dvec3> positions;
  std::vector<glm::dvec3> normals;
  std::vector<std::uint32_t> indices;
};

// Regular octahedron subdivided `levels` times, vertices pushed onto the sphere of radius r
// centred at c, normal = direction from the centre. Triangles are CCW seen from outside.
inline Mesh octasphere(int levels, double r = 1.0, glm::dvec3 c = {0, 0, 0}) {
  std::vector<glm::dvec3> tris = {
      {1, 0, 0}, {0, 1, 0},  {0, 0, 1},  {0, 1, 0},  {-1, 0, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0},
      {0, 0, 1}, {0, -1, 0}, {1, 0, 0},  {0, 0, 1},  {0, 1, 0},  {1, 0, 0}, {0, 0, -1}, {-1, 0, 0},
      {0, 1, 0}, {0, 0, -1}, {0, -1, 0}, {-1, 0, 0}, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}, {0, 0, -1}};
  for (int l = 0; l < levels; ++l) {
    std::vector<glm::dvec3> next;
    for (std::size_t i = 0; i < tris.size(); i += 3) {
      const glm::dvec3 a = tris[i], b = tris[i + 1], cc = tris[i + 2];
      const glm::dvec3 ab = glm::normalize(a + b), bc = glm::normalize(b + cc),
                       ca = glm::normalize(cc + a);
      for (const glm::dvec3& v : {a, ab, ca, ab, b, bc, ca, bc, cc, ab, bc, ca}) next.push_back(v);
    }
    tris = next;
  }
  // Weld identical directions so that shared edges use the same vertex.
  Mesh m;
  for (const glm::dvec3& d : tris) {
    std::uint32_t idx = 0;
    bool found = false;
    for (std::uint32_t k = 0; k < m.normals.size(); ++k)
      if (glm::length(m.normals[k] - d) < 1e-12) {
        idx = k;
        found = true;
        break;
      }
    if (!found) {
      idx = static_cast<std::uint32_t>(m.normals.size());
      m.normals.push_back(d);
      m.positions.push_back(c + r * d);
    }
    m.indices.push_back(idx);
  }
  return m;
}

// A device with its memory block, configured for a viewport and a mesh capacity.
struct Rig {
  std::vector<std::byte> memory;
  Device dev;
  explicit Rig(std::uint32_t w, std::uint32_t h, std::uint32_t max_v = 4096,
               std::uint32_t max_i = 3 * 8192, bool counts = true,
               PixelFormat fmt = PixelFormat::kRgb888)
      : memory(Device::memory_required(ViewportCmd{w, h, fmt, counts},
                                       BufferCapacityCmd{max_v, max_i}) +
               8),
        dev(memory) {
    check(dev.set_buffer_capacity(BufferCapacityCmd{max_v, max_i}));
    check(dev.set_viewport(ViewportCmd{w, h, fmt, counts}));
  }
  static void check(Error e) {
    if (e != Error::kOk) throw static_cast<int>(e);
  }
  Error load(const Mesh& m) {
    std::vector<Vertex> v;
    for (std::size_t i = 0; i < m.positions.size(); ++i)
      v.push_back(vertex(m.positions[i], m.normals[i]));
    Error e = dev.upload_vertices(0, v);
    if (e != Error::kOk) return e;
    return dev.upload_indices(0, m.indices);
  }
  Error draw_all(const Mesh& m) {
    return dev.draw(DrawCmd{0, static_cast<std::uint32_t>(m.indices.size())});
  }
  std::uint8_t count(std::uint32_t x, std::uint32_t y) const {
    return dev.write_counts()[std::size_t{y} * dev.state().viewport.width + x];
  }
  Rgb8 pixel(std::uint32_t x, std::uint32_t y) const {
    const FramebufferView fb = dev.framebuffer();
    const std::uint8_t* p = fb.data + std::size_t{y} * fb.stride + 3 * std::size_t{x};
    return Rgb8{p[0], p[1], p[2]};
  }
};

}  // namespace tp::fw::test
