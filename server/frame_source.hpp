// What the render loop drives: the emulated device (device_source.cpp) or, for transport tests,
// a synthetic pattern (pattern_source.cpp). The render loop owns the source and is the only
// thread that calls it, except for the closure returned by reference_task(), which is
// self-contained and runs on the reference worker thread.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "server/result.hpp"

namespace tp::server {

struct LightSetting {
  bool point = false;  // directional: unit direction TOWARD the light (eye space)
  std::array<double, 3> vector{0, 0, 1};  // point: position (eye space)
  std::array<double, 3> color{1, 1, 1};
};

// The user-editable part of the scene, as the control channel sees it.
struct ViewSettings {
  std::string scene;
  std::string method;
  int budget = 1;       // kb-adaptive's error budget in output levels (fw::kMaxBudgetLevels)
  bool use_ab = false;  // the material gives (a, b) instead of n (Kuijk-Blake's f(θ))
  double n = 20, a = 0, b = 0;
  double ka = 0.1, kd = 0.6, ks = 0.4;
  std::array<double, 3> color{1, 1, 1};
  std::vector<LightSetting> lights;
  int width = 320, height = 240;
  // Render the specular part alone (ka = kd = 0 for the device and the reference; ka and kd
  // above stay what the user set).
  bool specular_only = false;
};

// A shading method as the page lists it: the registry's row (firmware/registry.hpp) in words.
struct MethodEntry {
  std::string name, description, capabilities;
};

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;      // RGB888, row-major, top row first
  std::vector<std::uint8_t> covered;  // 1 where a triangle wrote the pixel
};

struct RenderedFrame {
  Image image;
  std::vector<std::pair<std::string, std::uint64_t>> counters;
  double render_ms = 0;
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual const ViewSettings& settings() const = 0;
  // Applies the settings as a whole; on failure nothing changed.
  virtual Result apply(const ViewSettings& s) = 0;
  // Loads a shipped scene by name; on failure nothing changed.
  virtual Result load_scene(const std::string& name) = 0;
  virtual std::vector<MethodEntry> methods() const = 0;
  virtual std::vector<std::string> scenes() const = 0;
  // Throws std::runtime_error, with what a client may be told, for a frame the device refuses.
  virtual RenderedFrame render(double rotation_radians) = 0;
  // A closure computing the double reference of the current scene at that rotation, safe to
  // run on another thread while the render loop keeps rendering.
  virtual std::function<Image()> reference_task(double rotation_radians) = 0;
};

}  // namespace tp::server
