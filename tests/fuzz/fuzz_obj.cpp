// Fuzz target: the OBJ reader (host/obj_reader.cpp, with tinyobjloader) on arbitrary text. Every
// input is either a mesh the renderer can use or a MeshError naming the file: a crash, a hang,
// undefined behaviour or another exception is a failure. An accepted mesh has a unit normal per
// vertex, finite positions, indices inside it and counts within the limits.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "host/meshes.hpp"
#include "tests/fuzz/fuzz_check.hpp"

namespace {

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void check_mesh(const tp::host::Mesh& m) {
  TP_FUZZ_CHECK(!m.triangles.empty(), "a mesh has faces");
  TP_FUZZ_CHECK(m.triangles.size() <= tp::host::kMaxMeshTriangles, "triangles within the limit");
  TP_FUZZ_CHECK(m.positions.size() <= tp::host::kMaxMeshVertices, "vertices within the limit");
  TP_FUZZ_CHECK(m.positions.size() == m.normals.size(), "a normal per vertex");
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    TP_FUZZ_CHECK(finite(m.positions[i]), "finite position");
    TP_FUZZ_CHECK(std::abs(glm::length(m.normals[i]) - 1) < 1e-9, "unit normal");
  }
  for (const auto& t : m.triangles)
    for (const std::uint32_t v : t) TP_FUZZ_CHECK(v < m.positions.size(), "index inside the mesh");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    check_mesh(tp::host::parse_obj(text, "fuzz.obj"));
  } catch (const tp::host::MeshError& e) {
    TP_FUZZ_CHECK(std::string(e.what()).find("fuzz.obj") != std::string::npos,
                  "the error names the file");
  }
  return 0;
}
