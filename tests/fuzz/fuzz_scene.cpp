// Fuzz target: the scene reader (host/scene.cpp) on arbitrary text. Every input is either a
// scene or a SceneError that names the file given and a line inside the text: any other
// exception escaping (a JSON library error the reader did not turn into its own), a crash, a
// hang or undefined behaviour is a failure. OBJ paths resolve against tests/fuzz/data.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "host/scene.hpp"
#include "tests/fuzz/fuzz_check.hpp"

namespace {

bool finite(const glm::dmat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

// What a scene the reader accepted must satisfy: its limits, and finite matrices and lights.
void check_scene(const tp::host::Scene& scene) {
  TP_FUZZ_CHECK(!scene.meshes.empty() && scene.meshes.size() <= tp::host::kMaxSceneMeshes,
                "mesh count within the limit");
  TP_FUZZ_CHECK(scene.lights.size() <= static_cast<std::size_t>(tp::host::kMaxLights),
                "light count within the limit");
  TP_FUZZ_CHECK(finite(tp::host::projection_matrix(scene.camera, scene.width, scene.height)),
                "finite projection");
  for (const auto& mesh : scene.meshes) {
    TP_FUZZ_CHECK(finite(tp::host::model_view(scene, mesh)), "finite model-view");
    TP_FUZZ_CHECK(mesh.mesh.positions.size() == mesh.mesh.normals.size(), "a normal per vertex");
  }
  for (const auto& light : tp::host::eye_lights(scene))
    TP_FUZZ_CHECK(std::isfinite(light.vector.x) && std::isfinite(light.vector.y) &&
                      std::isfinite(light.vector.z),
                  "finite eye-space light");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    check_scene(tp::host::parse_scene(text, "fuzz.json", TP_FUZZ_DATA));
  } catch (const tp::host::SceneError& e) {
    // Lines end at LF, CRLF or a lone CR, as the reader counts them (host/scene.hpp).
    const int lines = tp::host::line_of_offset(text, text.size());
    TP_FUZZ_CHECK(e.file() == "fuzz.json", "the error names the file");
    TP_FUZZ_CHECK(e.line() >= 0 && e.line() <= lines, "the error's line is in the file");
    TP_FUZZ_CHECK(!e.problem().empty(), "the error says what is wrong");
  }
  return 0;
}
