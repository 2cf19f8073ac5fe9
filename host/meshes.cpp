// Sphere-like test meshes of the papers (scenes/README.md, "Meshes"), the single triangle, OBJ
// loading.
#include "host/meshes.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <utility>

#include <tiny_obj_loader.h>

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

// tinyobjloader reads a token that is not a number ("nan", "inf", "1e999", "x") as 0 or as
// infinity without a word, so the numbers of every vertex record are read here first: each
// must be a finite double. The error names the file, the line and the field.
void check_obj_numbers(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::string line;
  static constexpr const char* kFields[] = {"x", "y", "z", "w"};
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();  // CRLF files
    std::istringstream words(line);
    std::string record;
    words >> record;
    if (record != "v" && record != "vn" && record != "vt") continue;
    std::string token;
    for (int k = 0; words >> token; ++k) {
      if (token[0] == '#') break;
      double value = 0;
      const char* begin = token.data() + (token[0] == '+' ? 1 : 0);  // from_chars takes no '+'
      const char* end = token.data() + token.size();
      const auto [ptr, ec] = std::from_chars(begin, end, value);
      if (ec != std::errc() || ptr != end || !std::isfinite(value)) {
        const std::string field = k < 4 ? kFields[k] : "value " + std::to_string(k + 1);
        throw MeshError("malformed OBJ " + file.string() + ":" + std::to_string(number) + ": " +
                        record + " " + field + " '" + token.substr(0, 32) +
                        "' is not a finite number");
      }
    }
  }
}

}  // namespace

Mesh load_obj(const std::filesystem::path& file) {
  tinyobj::ObjReaderConfig cfg;
  cfg.triangulate = true;
  cfg.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!std::filesystem::is_regular_file(file))
    throw MeshError("mesh file not found: " + file.string());
  check_obj_numbers(file);
  if (!reader.ParseFromFile(file.string(), cfg))
    throw MeshError("malformed OBJ " + file.string() + ": " + reader.Error());
  const auto& attrib = reader.GetAttrib();
  Mesh m;
  bool missing_normals = false;
  // OBJ indexes positions and normals separately; one mesh vertex per distinct pair.
  std::map<std::pair<int, int>, std::uint32_t> index;
  const auto nv = static_cast<int>(attrib.vertices.size() / 3);
  const auto nn = static_cast<int>(attrib.normals.size() / 3);
  for (const auto& shape : reader.GetShapes()) {
    const auto& ids = shape.mesh.indices;
    for (std::size_t f = 0; f + 2 < ids.size(); f += 3) {
      std::array<std::uint32_t, 3> tri{};
      for (int k = 0; k < 3; ++k) {
        const auto& id = ids[f + static_cast<std::size_t>(k)];
        if (id.vertex_index < 0 || id.vertex_index >= nv)
          throw MeshError("malformed OBJ " + file.string() + ": face refers to a missing vertex");
        if (id.normal_index >= nn)
          throw MeshError("malformed OBJ " + file.string() + ": face refers to a missing normal");
        if (id.normal_index < 0) missing_normals = true;
        const auto key = std::make_pair(id.vertex_index, id.normal_index);
        auto it = index.find(key);
        if (it == index.end()) {
          const auto vi = static_cast<std::size_t>(3 * id.vertex_index);
          m.positions.emplace_back(attrib.vertices[vi], attrib.vertices[vi + 1],
                                   attrib.vertices[vi + 2]);
          glm::dvec3 n(0, 0, 1);
          if (id.normal_index >= 0) {
            const auto ni = static_cast<std::size_t>(3 * id.normal_index);
            n = glm::dvec3(attrib.normals[ni], attrib.normals[ni + 1], attrib.normals[ni + 2]);
            if (!(glm::length(n) > 0))
              throw MeshError("malformed OBJ " + file.string() + ": zero normal");
            n = glm::normalize(n);
          }
          m.normals.push_back(n);
          it = index.emplace(key, static_cast<std::uint32_t>(m.positions.size() - 1)).first;
        }
        tri[static_cast<std::size_t>(k)] = it->second;
      }
      m.triangles.push_back(tri);
    }
  }
  if (m.triangles.empty()) throw MeshError("malformed OBJ " + file.string() + ": no faces");
  for (const auto& p : m.positions)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw MeshError("malformed OBJ " + file.string() + ": non-finite coordinate");
  if (missing_normals) compute_normals(m);
  return m;
}

namespace {

// Strict parameter reading: every key known, integers in range.
int int_param(const nlohmann::json& p, const char* key, int def, int lo, int hi) {
  if (!p.contains(key)) return def;
  const auto& v = p[key];
  if (!v.is_number_integer()) throw MeshError(std::string(key) + ": expected an integer");
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
