// The shipped frame source: the emulated device driven through host::DeviceRenderer, scenes
// from the shipped scenes/*.json (chosen by name from a list read at start: no path from a
// client ever reaches the file system).
#pragma once
#include <filesystem>
#include <memory>

#include "host/device_renderer.hpp"
#include "server/frame_source.hpp"

namespace tp::server {

class DeviceSource : public FrameSource {
 public:
  // Throws host::SceneError / std::runtime_error if the initial scene cannot be loaded.
  // method: the shading method to start with (empty: the scene file's own).
  DeviceSource(std::filesystem::path scenes_dir, const std::string& scene, int width, int height,
               const std::string& method = "");
  const ViewSettings& settings() const override { return settings_; }
  Result apply(const ViewSettings& s) override;
  Result load_scene(const std::string& name) override;
  std::vector<MethodEntry> methods() const override;
  std::vector<std::string> scenes() const override { return scene_names_; }
  RenderedFrame render(double rotation_radians) override;
  std::function<Image()> reference_task(double rotation_radians) override;

 private:
  Result install(host::Scene scene, const std::string& name, bool specular_only);

  std::filesystem::path dir_;
  std::vector<std::string> scene_names_;
  host::DeviceRenderer renderer_;
  std::shared_ptr<const host::Scene> scene_;  // what the device has; shared with reference tasks
  ViewSettings settings_;
};

}  // namespace tp::server
