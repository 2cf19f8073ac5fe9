// Sphere-like test meshes of the papers (scenes/README.md, "Meshes") and the single triangle
// (OBJ files: obj_reader.cpp).
#include "host/meshes.hpp"

#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <utility>

namespace tp::host {

namespace {

std::uint32_t add_unit_vertex(Mesh& m, glm::dvec3 p) {
  p = glm::normalize(p);
  m.positions.push_back(p);
  m.normals.push_back(p);  // on the unit sphere the normal is the position
  return static_cast<std::uint32_t>(m.positions.size() - 1);
}

// Adds triangle (a, b, c) oriented so that its geometric normal points away from the origin
// (all our sphere meshes are star-shaped about it): CCW seen from outside.
void add_outward(Mesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  const glm::dvec3 &pa = m.positions[a], &pb = m.positions[b], &pc = m.positions[c];
  if (glm::dot(glm::cross(pb - pa, pc - pa), pa + pb + pc) < 0) std::swap(b, c);
  m.triangles.push_back({a, b, c});
}

}  // namespace

Mesh octa_sphere(int subdivisions) {
  Mesh m;
  const glm::dvec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const auto& a : axes) add_unit_vertex(m, a);
  for (std::uint32_t x : {0u, 1u})
    for (std::uint32_t y : {2u, 3u})
      for (std::uint32_t z : {4u, 5u}) add_outward(m, x, y, z);
  for (int s = 0; s < subdivisions; ++s) {
    // Split every edge at its midpoint (shared between the two triangles of the edge, so the
    // mesh stays closed), push it onto the sphere, replace each triangle by four.
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      const std::uint32_t v = add_unit_vertex(m, m.positions[a] + m.positions[b]);
      mid.emplace(key, v);
      return v;
    };
    std::vector<std::array<std::uint32_t, 3>> next;
    for (const auto& t : m.triangles) {
      const std::uint32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]),
                          ca = midpoint(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({ab, t[1], bc});
      next.push_back({ca, bc, t[2]});
      next.push_back({ab, bc, ca});
    }
    m.triangles = std::move(next);
  }
  return m;
}

Mesh uv_sphere(int slices, int stacks) {
  Mesh m;
  const double pi = std::numbers::pi;
  const std::uint32_t top = add_unit_vertex(m, {0, 1, 0});
  for (int i = 1; i < stacks; ++i) {
    const double theta = pi * i / stacks;  // polar angle from +y
    for (int k = 0; k < slices; ++k) {
      const double phi = 2 * pi * k / slices;
      add_unit_vertex(
          m, {std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)});
    }
  }
  const std::uint32_t bottom = add_unit_vertex(m, {0, -1, 0});
  auto ring = [&](int i, int k) {  // vertex k of ring i (1 .. stacks-1)
    return static_cast<std::uint32_t>(1 + (i - 1) * slices + (k % slices));
  };
  for (int k = 0; k < slices; ++k) {
    add_outward(m, top, ring(1, k), ring(1, k + 1));
    add_outward(m, bottom, ring(stacks - 1, k), ring(stacks - 1, k + 1));
    for (int i = 1; i + 1 < stacks; ++i) {
      add_outward(m, ring(i, k), ring(i + 1, k), ring(i + 1, k + 1));
      add_outward(m, ring(i, k), ring(i + 1, k + 1), ring(i, k + 1));
    }
  }
  return m;
}

Mesh coarse_sphere_30() {
  Mesh m;
  const double pi = std::numbers::pi;
  const std::uint32_t top = add_unit_vertex(m, {0, 1, 0});
  for (int i = 0; i < 3; ++i) {
    const double theta = pi * (i + 1) / 4;  // 45°, 90°, 135° from +y
    for (int k = 0; k < 5; ++k) {
      const double phi = 2 * pi * (k + 0.5 * i) / 5;  // each ring turned 36° further
      add_unit_vertex(
          m, {std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)});
    }
  }
  const std::uint32_t bottom = add_unit_vertex(m, {0, -1, 0});
  auto ring = [](int i, int k) { return static_cast<std::uint32_t>(1 + 5 * i + (k % 5)); };
  for (int k = 0; k < 5; ++k) {
    add_outward(m, top, ring(0, k), ring(0, k + 1));
    add_outward(m, bottom, ring(2, k), ring(2, k + 1));
    for (int i = 0; i < 2; ++i) {
      // Ring i+1 vertex k sits between ring i vertices k and k+1 (antiprism band).
      add_outward(m, ring(i, k), ring(i + 1, k), ring(i, k + 1));
      add_outward(m, ring(i + 1, k), ring(i + 1, k + 1), ring(i, k + 1));
    }
  }
  return m;
}

Mesh big_triangle() {
  Mesh m;
  m.positions = {{-1, -0.9, 0}, {1, -0.9, 0}, {0, 1, 0}};
  for (const auto& p : m.positions)
    m.normals.push_back(glm::normalize(0.6 * p + glm::dvec3(0, 0, 1)));
  m.triangles = {{0, 1, 2}};  // CCW seen from +z
  return m;
}

Mesh quad(double h) {
  Mesh m;
  m.positions = {{-h, -h, 0}, {h, -h, 0}, {h, h, 0}, {-h, h, 0}};
  m.normals.assign(4, glm::dvec3(0, 0, 1));
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

void compute_normals(Mesh& m) {
  m.normals.assign(m.positions.size(), glm::dvec3(0));
  for (const auto& t : m.triangles) {
    const glm::dvec3 n = glm::cross(m.positions[t[1]] - m.positions[t[0]],
                                    m.positions[t[2]] - m.positions[t[0]]);  // 2·area·normal
    for (auto v : t) m.normals[v] += n;
  }
  for (auto& n : m.normals) n = glm::length(n) > 0 ? glm::normalize(n) : glm::dvec3(0, 0, 1);
}

namespace {

// Strict parameter reading: every key known, integers in range.
int int_param(const nlohmann::json& p, const char* key, int def, int lo, int hi) {
  if (!p.contains(key)) return def;
  const auto& v = p[key];
  if (!v.is_number_integer()) throw MeshError(std::string(key) + ": expected an integer");
  if (v.is_number_unsigned() && v.get<unsigned long long>() > static_cast<unsigned>(hi))
    throw MeshError(std::string(key) + ": value " + std::to_string(v.get<unsigned long long>()) +
                    " out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  const auto x = v.get<long long>();
  if (x < lo || x > hi)
    throw MeshError(std::string(key) + ": value " + std::to_string(x) + " out of range [" +
                    std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return static_cast<int>(x);
}

void only_keys(const nlohmann::json& p, std::initializer_list<const char*> allowed) {
  std::set<std::string> ok(allowed.begin(), allowed.end());
  for (const auto& [k, v] : p.items())
    if (!ok.count(k)) throw MeshError(k + ": unknown parameter");
}

}  // namespace

Mesh generate_mesh(const std::string& name, const nlohmann::json& p) {
  if (name == "octa-sphere") {
    only_keys(p, {"subdivisions"});
    return octa_sphere(int_param(p, "subdivisions", 1, 0, 6));
  }
  if (name == "uv-sphere") {
    only_keys(p, {"slices", "stacks"});
    return uv_sphere(int_param(p, "slices", 5, 3, 512), int_param(p, "stacks", 5, 2, 512));
  }
  if (name == "dodecahedron-30") {
    only_keys(p, {});
    return coarse_sphere_30();
  }
  if (name == "triangle") {
    only_keys(p, {});
    return big_triangle();
  }
  if (name == "quad") {
    only_keys(p, {"half_size"});
    double h = 1;
    if (p.contains("half_size")) {
      if (!p["half_size"].is_number()) throw MeshError("half_size: expected a number");
      h = p["half_size"].get<double>();
      if (!(h > 0 && h <= 1e4)) throw MeshError("half_size: out of range (0, 10000]");
    }
    return quad(h);
  }
  if (name == "teapot") {
    only_keys(p, {"tessellation"});
    return teapot(int_param(p, "tessellation", 8, 1, 64));
  }
  throw MeshError("generator: unknown generator \"" + name +
                  "\" (octa-sphere, uv-sphere, dodecahedron-30, triangle, quad, teapot)");
}

}  // namespace tp::host
