// Scene files: strict JSON reading (every key known, every number finite and in range) with
// errors that name file, line and JSON pointer; matrices and eye-space lights.
#include "host/scene.hpp"

#include <cmath>
#include <set>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>

#include "firmware/types.hpp"
#include "host/text_file.hpp"

namespace tp::host {

using nlohmann::json;

SceneError::SceneError(std::string file, int line, std::string path, std::string problem)
    : std::runtime_error(file + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " +
                         (path.empty() ? std::string() : path + ": ") + problem),
      file_(std::move(file)),
      line_(line),
      path_(std::move(path)),
      problem_(std::move(problem)) {}

namespace {

// Everything a check needs to report an error: the file, its text (for line numbers).
struct Reader {
  std::string file;
  std::string_view text;
  std::filesystem::path base_dir;

  [[noreturn]] void fail(const std::string& path, const std::string& problem) const {
    throw SceneError(file, line_of_pointer(text, path), path, problem);
  }

  // Rejects keys not in `allowed` (typos must not be ignored) and missing `required` ones.
  void keys(const json& j, const std::string& path, std::initializer_list<const char*> allowed,
            std::initializer_list<const char*> required = {}) const {
    if (!j.is_object()) fail(path, "expected an object, got " + std::string(j.type_name()));
    std::set<std::string> ok(allowed.begin(), allowed.end());
    for (const auto& [k, v] : j.items()) {
      if (!ok.count(k)) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
        fail(path + "/" + json_pointer_token(k),
             "unknown key \"" + k + "\" (allowed: " + list + ")");
      }
    }
    for (const char* r : required)
      if (!j.contains(r)) fail(path, std::string("missing key \"") + r + "\"");
  }

  double number(const json& j, const std::string& path, double lo, double hi) const {
    if (!j.is_number()) fail(path, "expected a number, got " + std::string(j.type_name()));
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail(path, "number is not finite");
    if (v < lo || v > hi) {
      std::ostringstream s;
      s << "value " << v << " out of range [" << lo << ", " << hi << "]";
      fail(path, s.str());
    }
    return v;
  }

  int integer(const json& j, const std::string& path, int lo, int hi) const {
    if (!j.is_number_integer())
      fail(path, "expected an integer, got " + std::string(j.type_name()));
    if (j.is_number_unsigned() && j.get<unsigned long long>() > static_cast<unsigned>(hi))
      fail(path, "value " + std::to_string(j.get<unsigned long long>()) + " out of range [" +
                     std::to_string(lo) + ", " + std::to_string(hi) + "]");
    const auto v = j.get<long long>();
    if (v < lo || v > hi)
      fail(path, "value " + std::to_string(v) + " out of range [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "]");
    return static_cast<int>(v);
  }

  std::string string(const json& j, const std::string& path) const {
    if (!j.is_string()) fail(path, "expected a string, got " + std::string(j.type_name()));
    std::string s = j.get<std::string>();
    // A NUL would end the string where the operating system reads it (a mesh path).
    if (s.find('\0') != std::string::npos) fail(path, "string contains a NUL character (\\u0000)");
    return s;
  }

  bool boolean(const json& j, const std::string& path) const {
    if (!j.is_boolean()) fail(path, "expected true or false, got " + std::string(j.type_name()));
    return j.get<bool>();
  }

  glm::dvec3 vec3(const json& j, const std::string& path, double lo, double hi) const {
    if (!j.is_array() || j.size() != 3) fail(path, "expected an array of 3 numbers");
    glm::dvec3 v;
    for (int i = 0; i < 3; ++i)
      v[i] = number(j[static_cast<std::size_t>(i)], path + "/" + std::to_string(i), lo, hi);
    return v;
  }
};

constexpr double kCoordLimit = 1e4;  // scene coordinates: far inside what the device converts
constexpr double kColourLimit = 16;  // light intensities and object colours

Camera read_camera(const Reader& r, const json& j, const std::string& p) {
  Camera c;
  r.keys(j, p, {"type", "extents", "near", "far", "position", "target", "up", "fov_y"}, {"type"});
  const std::string type = r.string(j["type"], p + "/type");
  if (type == "orthographic") {
    c.kind = CameraKind::Orthographic;
    r.keys(j, p, {"type", "extents", "near", "far"});
    if (j.contains("extents")) {
      const json& e = j["extents"];
      if (!e.is_array() || e.size() != 4)
        r.fail(p + "/extents", "expected [left, right, bottom, top]");
      double* dst[4] = {&c.left, &c.right, &c.bottom, &c.top};
      for (std::size_t i = 0; i < 4; ++i)
        *dst[i] = r.number(e[i], p + "/extents/" + std::to_string(i), -kCoordLimit, kCoordLimit);
      if (!(c.left < c.right) || !(c.bottom < c.top))
        r.fail(p + "/extents", "need left < right and bottom < top");
    }
  } else if (type == "perspective") {
    c.kind = CameraKind::Perspective;
    r.keys(j, p, {"type", "position", "target", "up", "fov_y", "near", "far"},
           {"position", "target", "fov_y"});
    c.position = r.vec3(j["position"], p + "/position", -kCoordLimit, kCoordLimit);
    c.target = r.vec3(j["target"], p + "/target", -kCoordLimit, kCoordLimit);
    if (j.contains("up")) c.up = r.vec3(j["up"], p + "/up", -kCoordLimit, kCoordLimit);
    c.fov_y_deg = r.number(j["fov_y"], p + "/fov_y", 1, 179);
    c.near = 0.1;
    c.far = 100;
    const glm::dvec3 fwd = c.target - c.position;
    if (glm::length(fwd) < 1e-9) r.fail(p + "/target", "target equals position");
    // lookAt uses only up's direction: kept as a unit vector, so that its products cannot
    // underflow into a NaN view matrix; a zero (or vanishing) up has no direction at all.
    const double up_length = glm::length(c.up);
    if (!(up_length > 1e-100) ||
        glm::length(glm::cross(glm::normalize(fwd), c.up / up_length)) < 1e-9)
      r.fail(p + "/up", "up is zero or parallel to the viewing direction");
    c.up /= up_length;
  } else {
    r.fail(p + "/type", "unknown camera type \"" + type + "\" (orthographic, perspective)");
  }
  if (j.contains("near")) c.near = r.number(j["near"], p + "/near", -kCoordLimit, kCoordLimit);
  if (j.contains("far")) c.far = r.number(j["far"], p + "/far", -kCoordLimit, kCoordLimit);
  if (c.kind == CameraKind::Perspective && !(c.near > 0))
    r.fail(p + "/near", "a perspective near plane must be > 0");
  if (!(c.far > c.near)) r.fail(p + "/far", "far must be greater than near");
  return c;
}

Light read_light(const Reader& r, const json& j, const std::string& p) {
  Light l;
  r.keys(j, p, {"type", "position", "direction", "colour"}, {"type"});
  const std::string type = r.string(j["type"], p + "/type");
  if (type == "point") {
    l.kind = LightKind::Point;
    r.keys(j, p, {"type", "position", "colour"}, {"position"});
    l.vector = r.vec3(j["position"], p + "/position", -kCoordLimit, kCoordLimit);
  } else if (type == "directional") {
    l.kind = LightKind::Directional;
    r.keys(j, p, {"type", "direction", "colour"}, {"direction"});
    l.vector = r.vec3(j["direction"], p + "/direction", -kCoordLimit, kCoordLimit);
    if (glm::length(l.vector) < 1e-9) r.fail(p + "/direction", "direction is zero");
    l.vector = glm::normalize(l.vector);
  } else {
    r.fail(p + "/type", "unknown light type \"" + type + "\" (point, directional)");
  }
  if (j.contains("colour")) l.colour = r.vec3(j["colour"], p + "/colour", 0, kColourLimit);
  return l;
}

Material read_material(const Reader& r, const json& j, const std::string& p) {
  Material m;
  r.keys(j, p, {"colour", "ka", "kd", "ks", "n", "a", "b"});
  if (j.contains("colour")) m.colour = r.vec3(j["colour"], p + "/colour", 0, 1);
  if (j.contains("ka")) m.ka = r.number(j["ka"], p + "/ka", 0, 1);
  if (j.contains("kd")) m.kd = r.number(j["kd"], p + "/kd", 0, 1);
  if (j.contains("ks")) m.ks = r.number(j["ks"], p + "/ks", 0, 1);
  if (j.contains("n")) m.n = r.number(j["n"], p + "/n", 1, fw::kMaxExponent);
  if (j.contains("a") != j.contains("b")) r.fail(p, "give both \"a\" and \"b\" or neither");
  if (j.contains("a")) {
    // Kuijk-Blake f(θ): 0 < a < b <= π/2 (f is 1 − θ²/(ab) near 0 and 0 beyond b).
    m.a = r.number(j["a"], p + "/a", kMinAngleAB, 1.5707963267948966);
    m.b = r.number(j["b"], p + "/b", kMinAngleAB, 1.5707963267948966);
    if (!(*m.a < *m.b)) r.fail(p + "/b", "need a < b");
  }
  return m;
}

Transform read_transform(const Reader& r, const json& j, const std::string& p) {
  Transform t;
  r.keys(j, p, {"translate", "rotate", "scale"});
  if (j.contains("translate"))
    t.translate = r.vec3(j["translate"], p + "/translate", -kCoordLimit, kCoordLimit);
  if (j.contains("rotate")) {
    const json& rot = j["rotate"];
    r.keys(rot, p + "/rotate", {"axis", "degrees"}, {"axis", "degrees"});
    t.rotate_axis = r.vec3(rot["axis"], p + "/rotate/axis", -kCoordLimit, kCoordLimit);
    if (glm::length(t.rotate_axis) < 1e-9) r.fail(p + "/rotate/axis", "axis is zero");
    t.rotate_deg = r.number(rot["degrees"], p + "/rotate/degrees", -360, 360);
  }
  if (j.contains("scale")) t.scale = r.number(j["scale"], p + "/scale", 1e-6, kCoordLimit);
  return t;
}

MeshSpec read_mesh(const Reader& r, const json& j, const std::string& p) {
  MeshSpec m;
  r.keys(j, p, {"obj", "generator", "params", "transform"});
  if (j.contains("obj") == j.contains("generator"))
    r.fail(p, "give exactly one of \"obj\" and \"generator\"");
  if (j.contains("transform")) m.transform = read_transform(r, j["transform"], p + "/transform");
  if (j.contains("obj")) {
    if (j.contains("params")) r.fail(p + "/params", "\"params\" only goes with \"generator\"");
    const std::filesystem::path rel = r.string(j["obj"], p + "/obj");
    m.obj = rel.is_absolute() ? rel : r.base_dir / rel;
    // load_obj checks that the file exists (a name the OS refuses included): its MeshError is the
    // scene's error at this key.
    try {
      m.mesh = load_obj(m.obj);
    } catch (const MeshError& e) {
      r.fail(p + "/obj", e.what());
    }
  } else {
    m.generator = r.string(j["generator"], p + "/generator");
    if (j.contains("params")) {
      m.params = j["params"];
      if (!m.params.is_object()) r.fail(p + "/params", "expected an object");
    }
    try {
      m.mesh = generate_mesh(m.generator, m.params);
    } catch (const MeshError& e) {
      // Messages start with the offending parameter name; point at it when it exists.
      const std::string msg = e.what();
      const std::string key = msg.substr(0, msg.find(':'));
      if (key == "generator") r.fail(p + "/generator", msg);
      if (m.params.contains(key)) r.fail(p + "/params/" + key, msg);
      r.fail(m.params.empty() ? p + "/generator" : p + "/params", msg);
    }
  }
  return m;
}

// The meshes, within the scene's limits: their number first, then the running totals of
// vertices and triangles (the error names the mesh that crosses one).
std::vector<MeshSpec> read_meshes(const Reader& r, const json& meshes) {
  if (!meshes.is_array() || meshes.empty()) r.fail("/meshes", "expected a non-empty array");
  if (meshes.size() > kMaxSceneMeshes)
    r.fail("/meshes", "at most " + std::to_string(kMaxSceneMeshes) + " meshes, got " +
                          std::to_string(meshes.size()));
  std::vector<MeshSpec> out;
  std::size_t vertices = 0, triangles = 0;
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const std::string path = "/meshes/" + std::to_string(i);
    out.push_back(read_mesh(r, meshes[i], path));
    vertices += out.back().mesh.positions.size();
    triangles += out.back().mesh.triangles.size();
    if (vertices > kMaxSceneVertices)
      r.fail(path, "the meshes have " + std::to_string(vertices) +
                       " vertices together, more than " + std::to_string(kMaxSceneVertices) +
                       " (the limit of a scene)");
    if (triangles > kMaxSceneTriangles)
      r.fail(path, "the meshes have " + std::to_string(triangles) +
                       " triangles together, more than " + std::to_string(kMaxSceneTriangles) +
                       " (the limit of a scene)");
  }
  return out;
}

Scene read_scene(const Reader& r, const json& j) {
  Scene s;
  s.file = r.file;
  r.keys(j, "",
         {"name", "resolution", "camera", "lights", "material", "meshes", "method", "budget",
          "background", "cull"},
         {"camera", "lights", "meshes"});
  if (j.contains("name")) s.name = r.string(j["name"], "/name");
  if (j.contains("resolution")) {
    const json& res = j["resolution"];
    if (!res.is_array() || res.size() != 2) r.fail("/resolution", "expected [width, height]");
    constexpr int kMax = static_cast<int>(fw::kMaxDimension);  // the device's viewport
    s.width = r.integer(res[0], "/resolution/0", 1, kMax);
    s.height = r.integer(res[1], "/resolution/1", 1, kMax);
  }
  s.camera = read_camera(r, j["camera"], "/camera");
  const json& lights = j["lights"];
  if (!lights.is_array()) r.fail("/lights", "expected an array");
  if (lights.size() > static_cast<std::size_t>(kMaxLights))
    r.fail("/lights", "at most " + std::to_string(kMaxLights) + " lights, got " +
                          std::to_string(lights.size()));
  for (std::size_t i = 0; i < lights.size(); ++i)
    s.lights.push_back(read_light(r, lights[i], "/lights/" + std::to_string(i)));
  if (j.contains("material")) s.material = read_material(r, j["material"], "/material");
  s.meshes = read_meshes(r, j["meshes"]);
  if (j.contains("method")) s.method = r.string(j["method"], "/method");
  if (j.contains("budget"))
    s.budget = r.integer(j["budget"], "/budget", 1, static_cast<int>(fw::kMaxBudgetLevels));
  if (j.contains("background")) s.background = r.vec3(j["background"], "/background", 0, 1);
  if (j.contains("cull")) s.cull_backfaces = r.boolean(j["cull"], "/cull");
  return s;
}

// JSON allows a key twice in one object and nlohmann keeps the last value: in a scene file
// that is almost always a copy-paste slip whose first value silently stops mattering, so it is
// an error. The parser callback sees every key; a stack of open containers gives its path.
// The line is that of the key's second occurrence after the object's start (a text search,
// which is exact unless the same key text appears in a string value in between).
void reject_duplicate_keys(std::string_view text, const std::string& file) {
  struct Frame {
    bool object = true;
    std::set<std::string> keys;
    std::string key;  // current key (objects)
    long index = -1;  // current element (arrays)
  };
  std::vector<Frame> stack;
  const auto path = [&stack](std::size_t upto) {
    std::string p;
    for (std::size_t i = 0; i < upto; ++i)
      p += "/" +
           (stack[i].object ? json_pointer_token(stack[i].key) : std::to_string(stack[i].index));
    return p;
  };
  const auto enter_element = [&stack] {
    if (!stack.empty() && !stack.back().object) ++stack.back().index;
  };
  json::parser_callback_t cb = [&](int, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
      case json::parse_event_t::array_start:
        enter_element();
        stack.push_back({event == json::parse_event_t::object_start, {}, {}, -1});
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end: stack.pop_back(); break;
      case json::parse_event_t::key: {
        Frame& top = stack.back();
        top.key = parsed.get<std::string>();
        if (!top.keys.insert(top.key).second) {
          const std::string parent = path(stack.size() - 1);
          const std::string needle = "\"" + top.key + "\"";
          std::size_t at = 0;
          if (const int pl = line_of_pointer(text, parent); pl > 0) at = start_of_line(text, pl);
          at = text.find(needle, at);
          if (at != std::string_view::npos) at = text.find(needle, at + 1);
          const int line = at == std::string_view::npos ? 0 : line_of_offset(text, at);
          throw SceneError(file, line, parent + "/" + json_pointer_token(top.key),
                           "duplicate key \"" + top.key + "\" (JSON would keep only the last one)");
        }
        break;
      }
      case json::parse_event_t::value: enter_element(); break;
    }
    return true;
  };
  [[maybe_unused]] const json tree = json::parse(text.begin(), text.end(), cb);
}

// A scene nests a few levels deep; the JSON library's value tree is recursive, so a file of
// tens of thousands of nested brackets would exhaust the stack (found with 100,000 levels: a
// segmentation fault). Brackets are counted outside strings before anything is parsed.
void reject_deep_nesting(std::string_view text, const std::string& file) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
      continue;
    }
    if (c == '"')
      in_string = true;
    else if (c == '[' || c == '{') {
      if (++depth > kMaxSceneNesting)
        throw SceneError(file, line_of_offset(text, i), "",
                         "nested deeper than " + std::to_string(kMaxSceneNesting) +
                             " levels (a scene needs at most 5)");
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

[[noreturn]] void throw_too_large(const std::string& file) {
  throw SceneError(
      file, 0, "",
      "larger than " + std::to_string(kMaxSceneFileBytes) + " bytes (the limit of a scene file)");
}

}  // namespace

Scene parse_scene(std::string_view text, const std::string& file,
                  const std::filesystem::path& base_dir) {
  if (text.size() > kMaxSceneFileBytes) throw_too_large(file);
  // nlohmann's lexer reads a NUL byte as the end of its input, so a scene followed by "\0" and
  // anything at all loaded without a word (found by review, 2026-12-07). JSON text holds none:
  // inside a string it is written \u0000.
  if (const std::size_t nul = text.find('\0'); nul != std::string_view::npos)
    throw SceneError(file, line_of_offset(text, nul), "",
                     "malformed JSON: a NUL byte (0x00) at byte " + std::to_string(nul + 1) +
                         ", which JSON text cannot hold");
  reject_deep_nesting(text, file);
  json j;
  try {
    j = json::parse(text.begin(), text.end());
  } catch (const json::parse_error& e) {
    // e.byte is 1-based and points just past the offending character.
    const std::size_t at = e.byte > 0 ? e.byte - 1 : 0;
    throw SceneError(file, line_of_offset(text, at), "",
                     std::string("malformed JSON: ") + e.what());
  } catch (const json::exception& e) {
    // E.g. out_of_range 406 "number overflow parsing '1e999'": no position, but the message
    // quotes the offending token; its first occurrence outside a string gives the line.
    const std::string msg = e.what();
    const auto q0 = msg.find('\''), q1 = msg.rfind('\'');
    int line = 0;
    if (q0 != std::string::npos && q1 > q0) {
      const auto at = find_outside_strings(text, msg.substr(q0 + 1, q1 - q0 - 1));
      if (at != std::string_view::npos) line = line_of_offset(text, at);
    }
    throw SceneError(file, line, "", "malformed JSON: " + msg);
  }
  reject_duplicate_keys(text, file);
  const Reader r{file, text, base_dir};
  return read_scene(r, j);
}

Scene load_scene(const std::filesystem::path& file, Accept accept) {
  std::string text;
  int os_error = 0;
  switch (read_text_file(file, kMaxSceneFileBytes, text, &os_error, accept)) {
    case ReadResult::ok: break;
    case ReadResult::cannot_open:
      throw SceneError(file.string(), 0, "", "cannot open scene file" + os_reason(os_error));
    case ReadResult::not_regular:
      throw SceneError(file.string(), 0, "", "not a regular file (a FIFO, a device or a folder)");
    case ReadResult::too_large: throw_too_large(file.string());
  }
  return parse_scene(text, file.string(), file.parent_path());
}

glm::dmat4 Transform::matrix() const {
  glm::dmat4 m = glm::translate(glm::dmat4(1.0), translate);
  if (rotate_deg != 0) m = glm::rotate(m, glm::radians(rotate_deg), glm::normalize(rotate_axis));
  return glm::scale(m, glm::dvec3(scale));
}

void keep_specular_only(Scene& scene) {
  scene.material.ka = 0;
  scene.material.kd = 0;
}

glm::dmat4 view_matrix(const Camera& c) {
  if (c.kind == CameraKind::Orthographic) return glm::dmat4(1.0);  // world = eye space
  return glm::lookAt(c.position, c.target, c.up);
}

glm::dmat4 projection_matrix(const Camera& c, int width, int height) {
  if (c.kind == CameraKind::Orthographic)
    return glm::ortho(c.left, c.right, c.bottom, c.top, c.near, c.far);
  return glm::perspective(glm::radians(c.fov_y_deg),
                          static_cast<double>(width) / static_cast<double>(height), c.near, c.far);
}

glm::dmat4 model_view(const Scene& s, const MeshSpec& m) {
  return view_matrix(s.camera) * m.transform.matrix();
}

bool eye_at_infinity(const Camera& c) { return c.kind == CameraKind::Orthographic; }

std::vector<EyeLight> eye_lights(const Scene& s) {
  const glm::dmat4 v = view_matrix(s.camera);
  std::vector<EyeLight> out;
  for (const Light& l : s.lights) {
    EyeLight e{l.kind, {}, l.colour};
    if (l.kind == LightKind::Point)
      e.vector = glm::dvec3(v * glm::dvec4(l.vector, 1.0));
    else
      e.vector = glm::normalize(glm::dvec3(v * glm::dvec4(l.vector, 0.0)));
    out.push_back(e);
  }
  return out;
}

}  // namespace tp::host
