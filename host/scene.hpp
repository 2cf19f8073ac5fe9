// Scene model of the desktop side: what a JSON scene file describes, and the matrices and
// eye-space lights derived from it (docs/CONVENTIONS.md: OpenGL conventions, column vectors,
// eye looks along -z; lights are given in world space in the file and used in eye space).
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "host/meshes.hpp"
#include "host/text_file.hpp"

namespace tp::host {

// Every problem found in a scene file (or in a mesh it names): which file, which line (0 when
// unknown, and then not in the message: "FILE: POINTER: PROBLEM"), which JSON pointer (e.g.
// "/lights/2/position"; empty for whole-file problems), what.
class SceneError : public std::runtime_error {
 public:
  SceneError(std::string file, int line, std::string path, std::string problem);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& path() const { return path_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string file_;
  int line_;
  std::string path_;
  std::string problem_;
};

inline constexpr int kMaxLights =
    16;  // the device has 16 light slots (docs/CONVENTIONS.md, "Limits")
// Limits of a scene file (scenes/README.md, "Limits"). Beyond one is a SceneError naming the
// file, the limit and, where there is one, the line and JSON pointer; nothing is truncated.
// Lines have no limit of their own (JSON may be one line): the file size bounds them.
inline constexpr std::size_t kMaxSceneFileBytes = std::size_t{1} << 20;  // 1 MiB; scenes are ~1 KB
// JSON nesting a scene file may use (scenes need 5 levels): deeper files are refused before
// they are parsed, because the JSON library recurses per level.
inline constexpr int kMaxSceneNesting = 64;
inline constexpr std::size_t kMaxSceneMeshes = 64;
// Kuijk-Blake's (a, b) in radians, given in place of n: kMinAngleAB <= a < b <= π/2. The scene
// files and the server's set_exponent share the bound (the server's was 1e-4 until 2026-12-08,
// refusing from the page what a scene file may hold).
inline constexpr double kMinAngleAB = 1e-6;
// All meshes of a scene together: the same bounds as one mesh (host/meshes.hpp).
inline constexpr std::size_t kMaxSceneVertices = kMaxMeshVertices;
inline constexpr std::size_t kMaxSceneTriangles = kMaxMeshTriangles;

enum class CameraKind { Orthographic, Perspective };

struct Camera {
  CameraKind kind = CameraKind::Orthographic;
  // Orthographic: the view is the identity (world = eye space, view along -z, eye at
  // infinity) and these are glm::ortho's extents.
  double left = -1.25, right = 1.25, bottom = -1.25, top = 1.25;
  // Perspective: glm::lookAt(position, target, up), glm::perspective(fov_y, aspect, near, far).
  glm::dvec3 position{0, 0, 5}, target{0, 0, 0}, up{0, 1, 0};
  double fov_y_deg = 40;
  // Both: eye-space depth range (orthographic near may be negative: the eye is at infinity).
  double near = -10, far = 10;
};

enum class LightKind { Directional, Point };

struct Light {
  LightKind kind = LightKind::Directional;
  glm::dvec3 vector{0, 0, 1};  // directional: direction TOWARD the light; point: position
  glm::dvec3 colour{1, 1, 1};
};

struct Material {
  glm::dvec3 colour{1, 1, 1};
  double ka = 0.1, kd = 0.6, ks = 0.4, n = 20;
  std::optional<double> a, b;  // Kuijk-Blake f(θ) parameters when given explicitly
};

struct Transform {
  glm::dvec3 translate{0, 0, 0};
  glm::dvec3 rotate_axis{0, 1, 0};
  double rotate_deg = 0;
  double scale = 1;           // uniform only: normals then transform by the upper 3x3 (conventions)
  glm::dmat4 matrix() const;  // T · R · S
};

struct MeshSpec {
  std::filesystem::path obj;  // absolute (resolved against the scene file's folder), or empty
  std::string generator;      // or a generator name (see meshes.hpp)
  nlohmann::json params = nlohmann::json::object();  // generator parameters
  Transform transform;
  Mesh mesh;  // loaded / generated while the scene is read, in model space
};

struct Scene {
  std::string file;  // where it came from ("" when parsed from a string)
  std::string name;
  int width = 512, height = 512;
  Camera camera;
  std::vector<Light> lights;
  Material material;
  std::vector<MeshSpec> meshes;
  std::string method = "phong";
  // The error budget in output levels, for the methods that choose their evaluation under one
  // (kb-adaptive; 1 .. fw::kMaxBudgetLevels).
  int budget = 1;
  glm::dvec3 background{0, 0, 0};
  bool cull_backfaces = true;
  // false: the device lays out no depth buffer (ViewportCmd::depth_buffer; the CLI's
  // --no-depth-buffer): enough for a closed convex mesh with back faces culled.
  bool depth_buffer = true;
  // true: the frame a part with little RAM lays out (`tinyphong record --small-part`; docs/
  // TARGET.md, "A small part"): RGB565, and no write counts even without a depth buffer (the
  // host's comparisons read coverage from them, so only record sets it).
  bool small_part_frame = false;
};

// Light in eye space, as the reference and the device use it.
struct EyeLight {
  LightKind kind = LightKind::Directional;
  glm::dvec3 vector{0, 0, 1};  // directional: unit direction toward the light; point: position
  glm::dvec3 colour{1, 1, 1};
};

// Read and validate a scene file; throws SceneError. Accept::regular_file refuses anything but a
// regular file without blocking on it (the server's scenes folder: host/text_file.hpp).
Scene load_scene(const std::filesystem::path& file, Accept accept = Accept::any_file);
// Same from text; `file` names it in errors, relative OBJ paths resolve against base_dir.
Scene parse_scene(std::string_view text, const std::string& file,
                  const std::filesystem::path& base_dir);

// The same frame's specular part alone, as Vlasic shows his methods' (his Figures 6.1-6.14):
// ka = kd = 0, the lights, exponent and ks unchanged; for the device and the reference alike.
void keep_specular_only(Scene& scene);

glm::dmat4 view_matrix(const Camera& camera);
glm::dmat4 projection_matrix(const Camera& camera, int width, int height);
// MV for one mesh = view · model.
glm::dmat4 model_view(const Scene& scene, const MeshSpec& mesh);
std::vector<EyeLight> eye_lights(const Scene& scene);
bool eye_at_infinity(const Camera& camera);  // orthographic: V = (0, 0, 1)

// 1-based line of a byte offset in text (for parse errors). Lines end at "\n", "\r\n" or a lone
// "\r", as in the OBJ reader (a file with old Mac line ends was all line 1).
int line_of_offset(std::string_view text, std::size_t offset);
// The byte offset where 1-based line `line` starts (the text's size past its last line).
std::size_t start_of_line(std::string_view text, int line);
// 1-based line where the value at a JSON pointer starts, 0 if not found. `text` must be
// valid JSON (the scene parser calls it only after nlohmann accepted the text).
int line_of_pointer(std::string_view text, std::string_view pointer);
// A key as one reference token of a JSON pointer (RFC 6901: "~" → "~0", "/" → "~1").
std::string json_pointer_token(std::string_view key);
// Offset of the first occurrence of token outside every JSON string of text, npos if none.
std::size_t find_outside_strings(std::string_view text, std::string_view token);

}  // namespace tp::host
