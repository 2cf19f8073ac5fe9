#include "host/device_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

#include <glm/gtc/matrix_transform.hpp>

#include "host/command_stream.hpp"
#include "host/quote_token.hpp"
#include "host/to_fixed.hpp"

namespace tp::host {

namespace {

using fx::q15_16;
using fx::q1_30;
using fx::q2_29;

// Device-side errors are reported as scene errors so that every caller (CLI, server) has one
// error type to show: the scene file, no line (the problem is in the combination), the what.
[[noreturn]] void reject(const Scene& scene, const std::string& path, std::string problem) {
  while (!problem.empty() && problem.back() == '\n') problem.pop_back();  // (a report's last line)
  throw SceneError(scene.file.empty() ? "<scene>" : scene.file, 0, path, problem);
}

// "rotation 45 degrees", for a frame refused at a turn of the model.
std::string at_rotation(double radians) {
  char degrees[32];
  std::snprintf(degrees, sizeof degrees, "%.6g", radians * 180.0 / std::numbers::pi);
  return std::string("rotation ") + degrees + " degrees";
}

fw::Vec3u unit_vector(const glm::dvec3& v, const std::string& what, ConversionReport& report) {
  const auto q = to_fixed3<q1_30>(glm::normalize(v), what, report);
  return q ? fw::Vec3u{(*q)[0], (*q)[1], (*q)[2]} : fw::Vec3u{};
}

// A coordinate or matrix entry as the device takes it: Q15.16 within |v| < 2^14
// (fw::kMaxCoordRaw: its four-term dot products stay within 64 bits). Q15.16's own range is
// twice that, and the device refused what lay between with a message naming only the command
// and its word (a mesh's vertex at 30,000 units: "upload_vertices at word 235 failed").
std::optional<q15_16> coordinate(double v, const std::string& what, ConversionReport& report) {
  const auto q = to_fixed<q15_16>(v, what, report);
  if (q && (q->raw() > fw::kMaxCoordRaw || q->raw() < -fw::kMaxCoordRaw)) {
    const double limit = fw::kMaxCoordRaw / 65536.0;
    report.add({what, v, -limit, limit, "the device's coordinates (Q15.16, |v| < 2^14)"});
    return std::nullopt;
  }
  return q;
}

fw::Vec3q16 position(const glm::dvec3& v, const std::string& what, ConversionReport& report) {
  const auto x = coordinate(v.x, what + ".x", report), y = coordinate(v.y, what + ".y", report),
             z = coordinate(v.z, what + ".z", report);
  return x && y && z ? fw::Vec3q16{*x, *y, *z} : fw::Vec3q16{};
}

fw::Mat4 to_device_matrix(const glm::dmat4& m, const std::string& what, ConversionReport& report) {
  fw::Mat4 out{};
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) {
      const auto q = coordinate(
          m[c][r], what + "[" + std::to_string(c) + "][" + std::to_string(r) + "]", report);
      if (q) out.m[c][r] = *q;
    }
  return out;
}

glm::dmat4 rotation_about_y(double radians) {
  return glm::rotate(glm::dmat4(1.0), radians, glm::dvec3(0, 1, 0));
}

}  // namespace

Image8 DeviceFrame::image() const {
  Image8 img(width, height);
  img.rgb = rgb;
  return img;
}

Image8 ReferenceFrame::image() const {
  Image8 img(width, height);
  img.rgb = rgb;
  return img;
}

std::span<const fw::MethodInfo> method_names() { return fw::kMethodTable; }

fw::Method method_from_name(std::string_view name) {
  if (const fw::MethodInfo* m = fw::find_method(name)) return m->id;
  std::string valid;
  for (const auto& m : method_names()) valid += (valid.empty() ? "" : ", ") + std::string(m.name);
  // Quoted with its control bytes as \xNN: a NUL in it ("phong\0x", sent by a client) ended
  // the message at the name (found by review, 2026-12-07).
  throw std::invalid_argument("unknown shading method " + quote_token(name, 64) +
                              " (valid: " + valid + ")");
}

std::string_view fidelity_name(fw::Fidelity f) {
  return f == fw::Fidelity::kExact ? "exact" : "approximated";
}

std::string capabilities_text(const fw::MethodCapabilities& caps) {
  return "point lights " + std::string(fidelity_name(caps.point_lights)) + ", finite eye " +
         std::string(fidelity_name(caps.finite_eye)) + ", several lights " +
         std::string(fidelity_name(caps.many_lights));
}

std::string_view method_name(fw::Method method) {
  const fw::MethodInfo* m = fw::find_method(method);
  return m != nullptr ? m->name : "unknown";
}

CounterSnapshot counter_snapshot(const fw::Counters& c) {
  return {{"triangles_in", c.triangles_in},
          {"triangles_culled", c.triangles_culled},
          {"triangles_clipped", c.triangles_clipped},
          {"triangles_rejected", c.triangles_rejected},
          {"triangles_degenerate", c.triangles_degenerate},
          {"triangles_drawn", c.triangles_drawn},
          {"triangles_skipped", c.triangles_skipped},
          {"spans", c.spans},
          {"spans_hidden", c.spans_hidden},
          {"pixels_shaded", c.pixels_shaded},
          {"pixels_written", c.pixels_written},
          {"lighting_evaluations", c.lighting_evaluations},
          {"specular_evaluations", c.specular_evaluations},
          {"normalizations", c.normalizations},
          {"lights_skipped_triangle", c.lights_skipped_triangle},
          {"lights_skipped_span", c.lights_skipped_span},
          {"segments", c.segments},
          {"adaptive_constant", c.adaptive_constant},
          {"adaptive_linear", c.adaptive_linear},
          {"adaptive_quadratic", c.adaptive_quadratic},
          {"adaptive_subdivided", c.adaptive_subdivided},
          {"adaptive_exact", c.adaptive_exact},
          {"subtriangles", c.subtriangles},
          {"subtriangles_exact", c.subtriangles_exact},
          {"subtriangles_unchecked", c.subtriangles_unchecked},
          {"terminator_cells", c.terminator_cells},
          {"lattice_samples", c.lattice_samples},
          {"saturations", c.saturations},
          {"frames", c.frames}};
}

struct DeviceRenderer::Prepared {
  fw::ViewportCmd viewport;
  fw::BufferCapacityCmd capacity;
  fw::Mat4 projection{};
  fw::EyeMode eye = fw::EyeMode::kInfinite;
  fw::MaterialCmd material;
  std::vector<fw::LightCmd> lights;
  fw::Method method = fw::Method::kGouraud;
  std::vector<fw::Vertex> vertices;
  std::vector<std::uint32_t> indices;
  std::vector<MeshRange> meshes;
};

namespace {

// The block for the largest frame, refused before it is allocated: a 20000 x 20000 request took
// 2.75 GB before the device refused the viewport. Enough for each layout prepare() may set: with
// the depth buffer; without it, with the write counts and the depth buffer's one row, which for a
// frame one or two pixels high needs more than the depth buffer would; and a small part's frame.
std::size_t block_bytes(int max_width, int max_height, std::uint32_t max_vertices,
                        std::uint32_t max_indices) {
  constexpr int kMax = static_cast<int>(fw::kMaxDimension);
  if (max_width < 1 || max_height < 1 || max_width > kMax || max_height > kMax)
    throw std::invalid_argument("viewport " + std::to_string(max_width) + "x" +
                                std::to_string(max_height) + " beyond the device's 1.." +
                                std::to_string(kMax) + " per side");
  const auto w = static_cast<std::uint32_t>(max_width), h = static_cast<std::uint32_t>(max_height);
  const fw::BufferCapacityCmd capacity{max_vertices, max_indices};
  std::size_t bytes = 0;
  for (const fw::ViewportCmd layout :
       {fw::ViewportCmd{w, h, fw::PixelFormat::kRgb888, /*write_count=*/false, /*depth=*/true},
        fw::ViewportCmd{w, h, fw::PixelFormat::kRgb888, /*write_count=*/true, /*depth=*/false},
        fw::ViewportCmd{w, h, fw::PixelFormat::kRgb565, /*write_count=*/false, /*depth=*/false}})
    bytes = std::max(bytes, fw::Device::memory_required(layout, capacity));
  return bytes;
}

}  // namespace

DeviceRenderer::DeviceRenderer(int max_width, int max_height, std::uint32_t max_vertices,
                               std::uint32_t max_indices)
    : memory_(block_bytes(max_width, max_height, max_vertices, max_indices)),
      device_(std::span<std::byte>(memory_)) {}

DeviceRenderer::Prepared DeviceRenderer::prepare(const Scene& scene) const {
  Prepared p;
  ConversionReport report;
  if (scene.width <= 0 || scene.height <= 0)
    reject(scene, "/resolution", "width and height must be positive");
  // Without a depth buffer the frame's coverage (read_frame) comes from the write counts, except
  // in a small part's frame, which only `record` writes.
  const bool part = scene.small_part_frame;
  p.viewport = {static_cast<std::uint32_t>(scene.width), static_cast<std::uint32_t>(scene.height),
                part ? fw::PixelFormat::kRgb565 : fw::PixelFormat::kRgb888,
                /*write_count=*/!scene.depth_buffer && !part, scene.depth_buffer};
  p.projection = to_device_matrix(projection_matrix(scene.camera, scene.width, scene.height),
                                  "projection", report);
  p.eye = eye_at_infinity(scene.camera) ? fw::EyeMode::kInfinite : fw::EyeMode::kFinite;

  const Material& m = scene.material;
  for (int c = 0; c < 3; ++c)
    if (auto q = to_fixed<q1_30>(m.colour[c], "material colour", report)) p.material.color[c] = *q;
  if (auto q = to_fixed<q1_30>(m.ka, "material ka", report)) p.material.ka = *q;
  if (auto q = to_fixed<q1_30>(m.kd, "material kd", report)) p.material.kd = *q;
  if (auto q = to_fixed<q1_30>(m.ks, "material ks", report)) p.material.ks = *q;
  if (m.n < 1 || m.n > fw::kMaxExponent || m.n != std::floor(m.n))
    reject(scene, "/material/n",
           "n = " + std::to_string(m.n) + " must be an integer in 1.." +
               std::to_string(fw::kMaxExponent) + " for the device");
  p.material.n = static_cast<std::uint32_t>(m.n);
  if (m.a && m.b) {
    if (auto q = to_fixed<q2_29>(*m.a, "material a", report)) p.material.a = *q;
    if (auto q = to_fixed<q2_29>(*m.b, "material b", report)) p.material.b = *q;
    // a < b as doubles can round to one angle: the device would refuse set_material, naming no
    // field.
    if (report.ok() && !(p.material.a < p.material.b))
      reject(scene, "/material/b",
             "b = " + std::to_string(*m.b) + " is a = " + std::to_string(*m.a) +
                 " in the device's angle format (Q2.29, steps of 2^-29 radian): b must exceed a"
                 " by at least that");
  }

  const auto lights = eye_lights(scene);
  if (lights.size() > fw::kMaxLights)
    reject(scene, "/lights", "the device has " + std::to_string(fw::kMaxLights) + " lights");
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const std::string name = "light " + std::to_string(i);
    fw::LightCmd l;
    l.index = static_cast<std::uint32_t>(i);
    for (int c = 0; c < 3; ++c)
      if (auto q = to_fixed<q15_16>(lights[i].colour[c], name + " colour", report)) l.color[c] = *q;
    if (lights[i].kind == LightKind::Directional) {
      l.type = fw::LightType::kDirectional;
      l.direction = unit_vector(lights[i].vector, name + " direction", report);
    } else {
      l.type = fw::LightType::kPoint;
      l.position = position(lights[i].vector, name + " position", report);
    }
    p.lights.push_back(l);
  }
  try {
    p.method = method_from_name(scene.method);
  } catch (const std::invalid_argument& e) {
    reject(scene, "/method", e.what());
  }

  for (std::size_t k = 0; k < scene.meshes.size(); ++k) {
    const Mesh& mesh = scene.meshes[k].mesh;
    const auto base = static_cast<std::uint32_t>(p.vertices.size());
    MeshRange range{static_cast<std::uint32_t>(p.indices.size()),
                    static_cast<std::uint32_t>(mesh.triangles.size() * 3),
                    scene.meshes[k].transform.matrix()};
    const std::string name = "mesh " + std::to_string(k);
    for (std::size_t v = 0; v < mesh.positions.size(); ++v)
      p.vertices.push_back(
          {position(mesh.positions[v], name + " vertex " + std::to_string(v), report),
           unit_vector(mesh.normals[v], name + " normal " + std::to_string(v), report)});
    for (const auto& t : mesh.triangles)
      for (std::uint32_t i : t) p.indices.push_back(base + i);
    p.meshes.push_back(range);
  }
  if (!report.ok())
    reject(scene, "", "does not fit the device's fixed-point formats:\n" + report.to_string());
  p.capacity = {static_cast<std::uint32_t>(p.vertices.size()),
                static_cast<std::uint32_t>(p.indices.size())};
  return p;
}

std::vector<std::uint32_t> DeviceRenderer::setup_commands(const Scene& scene,
                                                          const Prepared& p) const {
  CommandWriter w;
  w.set_viewport(p.viewport);
  w.set_buffer_capacity(p.capacity);
  w.set_projection(p.projection);
  w.set_eye(p.eye);
  w.set_material(p.material);
  for (std::uint32_t i = 0; i < fw::kProtocolLights; ++i) {  // every slot: unused ones off
    fw::LightCmd l = i < p.lights.size() ? p.lights[i] : fw::LightCmd{};
    l.index = i;
    w.set_light(l);
  }
  w.set_method(p.method);
  w.set_budget(static_cast<std::uint32_t>(scene.budget));
  w.set_culling(scene.cull_backfaces);
  w.upload_vertices(0, p.vertices);
  w.upload_indices(0, p.indices);
  // Every mesh's model-view must be representable at the rotations the animation uses; the
  // unrotated one is checked here, the device checks the rest per frame.
  for (const auto& mesh : p.meshes) w.set_modelview(modelview_for(scene, mesh, 0.0));
  return w.words();
}

void DeviceRenderer::apply(const Scene& scene, const std::vector<std::uint32_t>& setup) {
  try {
    run_stream(device_, setup);
  } catch (const StreamError& e) {
    reject(scene, "", std::string("the device rejected the scene: ") + e.what());
  }
}

void DeviceRenderer::set_scene(const Scene& scene) {
  const Prepared p = prepare(scene);
  std::vector<std::uint32_t> setup = setup_commands(scene, p);
  try {
    apply(scene, setup);
  } catch (const SceneError&) {
    // Put the previous scene back so that the device keeps rendering what it had.
    if (loaded_) apply(scene_, setup_words_);
    throw;
  }
  scene_ = scene;
  meshes_ = p.meshes;
  setup_words_ = std::move(setup);
  loaded_ = true;
}

// set_scene checks the model-views unrotated; a vertex's transform, at any turn, is checked by
// the draw that names it (a draw's only refusal once its indices are in range), per frame.
void DeviceRenderer::refused_frame(const StreamError& e, double rotation) const {
  std::string why = "the device refused the frame at " + at_rotation(rotation) + ": " + e.what();
  if (e.opcode == static_cast<std::uint32_t>(fw::Opcode::kDraw) &&
      e.error == fw::Error::kOutOfRange)
    why +=
        " (at this rotation a vertex's eye-space or clip-space coordinates leave the device's"
        " Q15.16 range, |x| < 32768: a smaller model, or a camera nearer its size, fits)";
  reject(scene_, "", why);
}

fw::Mat4 DeviceRenderer::modelview_for(const Scene& scene, const MeshRange& mesh,
                                       double rotation) const {
  ConversionReport report;
  const glm::dmat4 mv = view_matrix(scene.camera) * rotation_about_y(rotation) * mesh.model;
  fw::Mat4 m = to_device_matrix(mv, "model-view", report);
  if (!report.ok())
    reject(scene, "",
           "the model-view at " + at_rotation(rotation) +
               " does not fit the device: " + report.to_string());
  return m;
}

std::vector<std::uint32_t> DeviceRenderer::frame_commands(double model_rotation_radians) const {
  CommandWriter w;
  const glm::dvec3 bg = glm::clamp(scene_.background, 0.0, 1.0) * 255.0;
  w.clear({static_cast<std::uint8_t>(std::lround(bg.r)),
           static_cast<std::uint8_t>(std::lround(bg.g)),
           static_cast<std::uint8_t>(std::lround(bg.b))});
  for (const auto& mesh : meshes_) {
    w.set_modelview(modelview_for(scene_, mesh, model_rotation_radians));
    w.draw({mesh.first_index, mesh.index_count});
  }
  w.end_frame();
  return w.words();
}

std::vector<std::uint32_t> DeviceRenderer::record(double model_rotation_radians) const {
  if (!loaded_) throw std::logic_error("DeviceRenderer::record before set_scene");
  std::vector<std::uint32_t> words = setup_words_;
  const std::vector<std::uint32_t> frame = frame_commands(model_rotation_radians);
  words.insert(words.end(), frame.begin(), frame.end());
  return words;
}

DeviceFrame DeviceRenderer::render(double model_rotation_radians) {
  if (!loaded_) throw std::logic_error("DeviceRenderer::render before set_scene");
  const auto start = std::chrono::steady_clock::now();
  try {
    run_stream(device_, frame_commands(model_rotation_radians));
  } catch (const StreamError& e) {
    refused_frame(e, model_rotation_radians);
  }
  const auto stop = std::chrono::steady_clock::now();
  DeviceFrame f = read_frame(device_);
  f.render_ms = std::chrono::duration<double, std::milli>(stop - start).count();
  return f;
}

DeviceFrame read_frame(const fw::Device& device) {
  DeviceFrame f;
  const fw::FramebufferView fb = device.framebuffer();
  f.width = static_cast<int>(fb.width);
  f.height = static_cast<int>(fb.height);
  const std::size_t pixels = std::size_t{fb.width} * fb.height;
  f.rgb.resize(pixels * 3);
  for (std::uint32_t y = 0; y < fb.height; ++y)
    fw::row_as_rgb888(fb, y, f.rgb.data() + std::size_t{y} * fb.width * 3);
  // Coverage from the depth buffer: the depth test is on and clear sets every depth word to the
  // far value, which no write can store (a write needs a depth below the stored one), so a pixel
  // was written exactly when its depth word is below far. The write counts would say the same at
  // a cost in every pixel loop, so they stay off (docs/DECISIONS.md, "Pipeline"). (A replayed
  // stream that turns the depth test off gets this coverage too; only the tests read it.)
  // Without a depth buffer (DeviceRenderer turns the write counts on then) a pixel was written
  // when its count is not zero; a replayed stream with neither counts every pixel as covered.
  const std::uint32_t* depth = device.depth_buffer();
  const std::uint8_t* counts = device.write_counts();
  f.covered.assign(pixels, 1);
  if (depth != nullptr)
    for (std::size_t i = 0; i < pixels; ++i) f.covered[i] = depth[i] != fw::kDepthFar ? 1 : 0;
  else if (counts != nullptr)
    for (std::size_t i = 0; i < pixels; ++i) f.covered[i] = counts[i] != 0 ? 1 : 0;
  f.counters = counter_snapshot(device.counters());
  return f;
}

ReferenceFrame DeviceRenderer::render_reference(double model_rotation_radians,
                                                Interpolation interpolation) const {
  if (!loaded_) throw std::logic_error("DeviceRenderer::render_reference before set_scene");
  const FrameSetup frame = frame_setup(scene_);
  std::vector<DrawMesh> meshes;
  for (std::size_t k = 0; k < scene_.meshes.size(); ++k)
    meshes.push_back({&scene_.meshes[k].mesh, view_matrix(scene_.camera) *
                                                  rotation_about_y(model_rotation_radians) *
                                                  scene_.meshes[k].transform.matrix()});
  const ReferenceImage ref = host::render_reference(frame, meshes, interpolation);
  return {ref.rgb8.width, ref.rgb8.height, ref.rgb8.rgb, ref.mask, ref.linear};
}

}  // namespace tp::host
