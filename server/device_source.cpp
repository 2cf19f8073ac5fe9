#include "server/device_source.hpp"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <system_error>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "firmware/types.hpp"
#include "host/quote_token.hpp"
#include "host/reference.hpp"
#include "host/scene.hpp"
#include "server/control.hpp"

namespace tp::server {

namespace {

ViewSettings to_settings(const host::Scene& sc, const std::string& name) {
  ViewSettings s;
  s.scene = name;
  s.method = sc.method;
  s.budget = sc.budget;
  const host::Material& m = sc.material;
  s.use_ab = m.a.has_value() && m.b.has_value();
  s.n = m.n;
  s.a = m.a.value_or(0);
  s.b = m.b.value_or(0);
  s.ka = m.ka;
  s.kd = m.kd;
  s.ks = m.ks;
  s.color = {m.colour.x, m.colour.y, m.colour.z};
  for (const auto& l : sc.lights)
    s.lights.push_back({l.kind == host::LightKind::Point,
                        {l.vector.x, l.vector.y, l.vector.z},
                        {l.colour.x, l.colour.y, l.colour.z}});
  s.width = sc.width;
  s.height = sc.height;
  return s;
}

// What a client is told of a problem: files named from the scenes folder `dir`, not by where
// the server keeps them (a SceneError's text names the scene's file, and a mesh's within it).
std::string client_text(const std::exception& e, const std::filesystem::path& dir) {
  std::string text = e.what();
  const std::string prefix = (dir / "").string();
  for (std::size_t at = text.find(prefix); at != std::string::npos; at = text.find(prefix, at))
    text.erase(at, prefix.size());
  return text;
}

host::Scene with_settings(host::Scene sc, const ViewSettings& s) {
  sc.method = s.method;
  sc.budget = s.budget;
  host::Material& m = sc.material;
  if (s.use_ab) {
    m.a = s.a;
    m.b = s.b;
  } else {
    m.n = s.n;
    m.a.reset();
    m.b.reset();
  }
  m.ka = s.ka;
  m.kd = s.kd;
  m.ks = s.ks;
  m.colour = {s.color[0], s.color[1], s.color[2]};
  sc.lights.clear();
  for (const auto& l : s.lights)
    sc.lights.push_back({l.point ? host::LightKind::Point : host::LightKind::Directional,
                         {l.vector[0], l.vector[1], l.vector[2]},
                         {l.color[0], l.color[1], l.color[2]}});
  sc.width = s.width;
  sc.height = s.height;
  return sc;
}

// A name a client can send back in set_scene: valid UTF-8 of 1 to kMaxNameBytes bytes
// (server/control.hpp).
// The page was offered longer names and names in another encoding (shown with U+FFFD), which
// the server then refused (found by review, 2026-12-07).
bool selectable(const std::string& name) {
  if (name.empty() || name.size() > kMaxNameBytes) return false;
  try {
    (void)nlohmann::json(name).dump();  // throws on invalid UTF-8
    return true;
  } catch (const nlohmann::json::type_error&) {
    return false;
  }
}

}  // namespace

DeviceSource::DeviceSource(std::filesystem::path scenes_dir, const std::string& scene, int width,
                           int height, const std::string& method)
    : dir_(std::move(scenes_dir)) {
  if (std::error_code ec; !std::filesystem::is_directory(dir_, ec))
    throw std::runtime_error("scenes folder " + dir_.string() + ": " +
                             (ec ? ec.message() : std::string("not a folder")));
  for (const auto& e : std::filesystem::directory_iterator(dir_)) {
    if (!e.is_regular_file() || e.path().extension() != ".json") continue;
    if (std::string name = e.path().stem().string(); selectable(name))
      scene_names_.push_back(std::move(name));
    else
      std::cerr << "tinyphong-server: " << host::quote_token(e.path().string(), 4096)
                << " not offered: a scene's name is 1 to " << kMaxNameBytes
                << " bytes of UTF-8 (set_scene)\n";
  }
  std::sort(scene_names_.begin(), scene_names_.end());
  if (std::find(scene_names_.begin(), scene_names_.end(), scene) == scene_names_.end())
    throw std::runtime_error("no scene '" + scene + "' in " + dir_.string());
  host::Scene sc = host::load_scene(dir_ / (scene + ".json"), host::Accept::regular_file);
  if (width > 0) sc.width = width;
  if (height > 0) sc.height = height;
  if (!method.empty()) sc.method = method;
  if (Result r = install(std::move(sc), scene, false); !r.ok())
    throw std::runtime_error(r.message());
}

std::vector<MethodEntry> DeviceSource::methods() const {
  std::vector<MethodEntry> out;
  for (const auto& m : host::method_names())
    out.push_back(
        {std::string(m.name), std::string(m.description), host::capabilities_text(m.caps)});
  return out;
}

// sc carries the user's material; what the device and the reference render is the specular
// part alone when specular_only.
Result DeviceSource::install(host::Scene sc, const std::string& name, bool specular_only) {
  host::Scene shown = sc;
  if (specular_only) host::keep_specular_only(shown);
  try {
    host::method_from_name(shown.method);  // names the valid choices if not one
    renderer_.set_scene(shown);            // on failure the device keeps the previous scene
  } catch (const std::exception& e) {
    return Result::failure(client_text(e, dir_));
  }
  settings_ = to_settings(sc, name);
  settings_.specular_only = specular_only;
  scene_ = std::make_shared<const host::Scene>(std::move(shown));
  return Result::success();
}

Result DeviceSource::apply(const ViewSettings& s) {
  if (s.lights.size() > fw::kMaxLights)
    return Result::failure("too many lights");  // the device's slots
  return install(with_settings(*scene_, s), s.scene, s.specular_only);
}

Result DeviceSource::load_scene(const std::string& name) {
  if (std::find(scene_names_.begin(), scene_names_.end(), name) == scene_names_.end())
    return Result::failure("unknown scene '" + name + "'");
  try {
    // The viewer keeps the method, budget and view it shows; the scene file's own method and
    // budget are for the CLI. A regular file only, as listed at start: a FIFO put in its place
    // blocked the render loop in the read, and with it every client and the server's stop (found
    // by review, 2026-12-07).
    host::Scene sc = host::load_scene(dir_ / (name + ".json"), host::Accept::regular_file);
    sc.method = settings_.method;
    sc.budget = settings_.budget;
    return install(std::move(sc), name, settings_.specular_only);
  } catch (const std::exception& e) {
    return Result::failure(client_text(e, dir_));
  }
}

RenderedFrame DeviceSource::render(double rotation) {
  host::DeviceFrame d;
  try {
    d = renderer_.render(rotation);
  } catch (const host::SceneError& e) {  // a frame the device refuses (host::DeviceRenderer)
    throw std::runtime_error(client_text(e, dir_));
  }
  RenderedFrame f;
  f.image.width = d.width;
  f.image.height = d.height;
  f.image.rgb = std::move(d.rgb);
  f.image.covered = std::move(d.covered);
  f.counters = std::move(d.counters);
  f.render_ms = d.render_ms;
  return f;
}

std::function<Image()> DeviceSource::reference_task(double rotation) {
  // Same as DeviceRenderer::render_reference, but on a scene snapshot, so that it can run on
  // the reference worker while the render loop keeps using the renderer.
  return [sc = scene_, rotation]() {
    const host::FrameSetup frame = host::frame_setup(*sc);
    const glm::dmat4 spin = glm::rotate(glm::dmat4(1.0), rotation, glm::dvec3(0, 1, 0));
    std::vector<host::DrawMesh> meshes;
    for (const auto& m : sc->meshes)
      meshes.push_back({&m.mesh, host::view_matrix(sc->camera) * spin * m.transform.matrix()});
    host::ReferenceImage ref = host::render_reference(frame, meshes);
    return Image{ref.rgb8.width, ref.rgb8.height, std::move(ref.rgb8.rgb), std::move(ref.mask)};
  };
}

}  // namespace tp::server
