// Triangle meshes of the desktop side: the papers' test objects (scenes/README.md), built by
// generators, and OBJ files read with tinyobjloader. Model space; y is up.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace tp::host {

// Indexed triangles with one normal per vertex. Triangles are counter-clockwise seen from
// outside (the normal side), so that a front face is CCW in NDC (conventions: facing).
struct Mesh {
  std::vector<glm::dvec3> positions;
  std::vector<glm::dvec3> normals;  // unit length, one per position
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

// A mesh problem (bad OBJ, unknown generator, bad parameter); the scene reader wraps it into a
// SceneError that names the scene file and JSON path.
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Regular octahedron, each face split into 4^subdivisions, vertices pushed onto the unit
// sphere, normal = position: 8·4^s triangles (s = 1: 32, s = 3: 512; scenes/README.md).
Mesh octa_sphere(int subdivisions);
// UV sphere: `slices` around y, `stacks` from pole to pole; fans at the poles, so
// 2·slices·(stacks − 1) triangles (5 × 5: 40, Vlasic's sphere).
Mesh uv_sphere(int slices, int stacks);
// "dodecahedron-30": a closed 30-triangle sphere with 17 vertices: the two poles (0, ±1, 0) and
// three rings of 5 vertices at polar angles 45°, 90°, 135°, each ring turned 36° against the
// previous one, so that the bands between rings are pentagonal antiprism bands (10 triangles
// each) and the caps are 5-triangle fans: 5 + 10 + 10 + 5 = 30. Normal = position.
Mesh coarse_sphere_30();
// Vlasic's single triangle (−1, −0.9, 0), (1, −0.9, 0), (0, 1, 0) with vertex normals
// normalize(0.6·P + (0, 0, 1)).
Mesh big_triangle();
// A square [−h, h]² in the plane z = 0 facing +z, two triangles, normals (0, 0, 1).
Mesh quad(double half_size);
// The Utah teapot from Newell's 32 bicubic Bézier patches (306 control points), each patch
// tessellated into tess × tess quads; see teapot.cpp for the facet count and the pole normals.
// Rotated from the data's z-up to y-up; the bottom sits at y = 0.
Mesh teapot(int tess = 8);
// Number of triangles teapot(tess) produces, from the patch structure (for documentation/tests).
int teapot_triangle_count(int tess);

// Limits of the OBJ reader (scenes/README.md, "Limits"). A file beyond one is refused with a
// MeshError naming the file, the limit and, where the count is crossed, the line: never read
// in part, never truncated. 2^20 triangles load and render in seconds (`tinyphong render`,
// release: a 200,000-face OBJ in 1.1 s, 2^20 faces in 3.4 s; docs/DECISIONS.md).
inline constexpr std::size_t kMaxObjFileBytes = std::size_t{64} << 20;  // 64 MiB
inline constexpr std::size_t kMaxObjLineBytes = 4096;
// One mesh (and, in host/scene.hpp, all meshes of a scene together).
inline constexpr std::size_t kMaxMeshVertices = std::size_t{1} << 20;
inline constexpr std::size_t kMaxMeshTriangles = std::size_t{1} << 20;

// Positions and normals (normals computed, area-weighted, when the file has none).
// Throws MeshError naming the file (and line) on a missing, malformed or too large file.
Mesh load_obj(const std::filesystem::path& file);
// The same from the file's text; `file` names it in errors.
Mesh parse_obj(std::string_view text, const std::string& file);

// Generator by name: "octa-sphere" {subdivisions}, "uv-sphere" {slices, stacks},
// "dodecahedron-30" {}, "triangle" {}, "quad" {half_size}, "teapot" {tessellation}.
// Unknown names, unknown parameters, wrong types and out-of-range values throw MeshError whose
// message starts with the parameter name (e.g. "subdivisions: ...").
Mesh generate_mesh(const std::string& name, const nlohmann::json& params);

// Area-weighted vertex normals from the triangles (used when an OBJ has none).
void compute_normals(Mesh& mesh);

}  // namespace tp::host
