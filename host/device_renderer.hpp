// The host's driver of the emulated device: turns a Scene (doubles, world space) into device
// commands (fixed point, eye space), renders frames, and reads them back. The CLI, the server,
// the scene-level tests and the benchmarks all drive the device through this one class.
//
// Float -> fixed conversion is checked (host/to_fixed.hpp): a scene whose numbers do not fit
// the device's formats is rejected with every offending quantity named, never wrapped.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "firmware/device.hpp"
#include "firmware/registry.hpp"
#include "host/image.hpp"
#include "host/reference.hpp"
#include "host/scene.hpp"

namespace tp::host {

class StreamError;

using CounterSnapshot = std::vector<std::pair<std::string, std::uint64_t>>;

// One frame rendered by the device.
struct DeviceFrame {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;      // RGB888, row-major, top row first, no padding
  std::vector<std::uint8_t> covered;  // 1 where a triangle wrote the pixel this frame
  CounterSnapshot counters;           // the device's performance counters, by name
  double render_ms = 0;               // wall time of clear + draws + end_frame
  Image8 image() const;
};

struct ReferenceFrame {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // round(255 · clamped double Blinn-Phong)
  std::vector<std::uint8_t> covered;
  FloatImage linear;  // the unclamped double intensities (as float)
  Image8 image() const;
};

// The shading methods as the CLI, scene files and the server spell them: the firmware's registry
// (firmware/registry.hpp), in its order.
std::span<const fw::MethodInfo> method_names();
// Throws std::invalid_argument naming the valid choices.
fw::Method method_from_name(std::string_view name);
// "exact" or "approximated" (firmware/registry.hpp, Fidelity).
std::string_view fidelity_name(fw::Fidelity f);
// What a method does with point lights, a finite eye and several lights, in words:
// "point lights exact, finite eye approximated, several lights exact".
std::string capabilities_text(const fw::MethodCapabilities& caps);
std::string_view method_name(fw::Method method);

// Names and values of every counter of the device, in a fixed order.
CounterSnapshot counter_snapshot(const fw::Counters& c);

class DeviceRenderer {
 public:
  // Allocates the device's memory block once, for frames up to max_width x max_height and
  // meshes up to max_vertices / max_indices; the device itself never allocates. Throws
  // std::invalid_argument, before allocating, for a side outside 1..fw::kMaxDimension.
  explicit DeviceRenderer(int max_width = 2048, int max_height = 2048,
                          std::uint32_t max_vertices = 1u << 17,
                          std::uint32_t max_indices = 3u << 18);

  // Converts and uploads the scene. Throws SceneError naming the problem if it does not fit the
  // device (range, size, a command the device rejects); the previous scene then stays loaded.
  void set_scene(const Scene& scene);
  const Scene& scene() const { return scene_; }

  // Renders with the scene's objects rotated by `model_rotation_radians` about the world y axis
  // (the lights stay put, so the highlights move: the server's animation). A frame the device
  // refuses (set_scene checks the model-views unturned; the vertices' transforms are checked by
  // each frame's draws) throws SceneError naming the scene and the rotation.
  DeviceFrame render(double model_rotation_radians = 0.0);
  // The double-precision reference of the same frame (host/reference.hpp).
  ReferenceFrame render_reference(double model_rotation_radians = 0.0,
                                  Interpolation interpolation = Interpolation::Phong) const;

  // The command words of one frame as a fresh device needs them: the scene's setup (viewport,
  // capacity, projection, eye, material, lights, method, budget, culling, uploads) then the frame's
  // (clear, model-view and draw per mesh, end_frame). set_scene and render run exactly these
  // words through Device::execute, so a recorded stream cannot drift from a render. Whether the
  // device takes the frame (a turn can take a vertex out of its range) is render's to say: the
  // CLI renders it before it records.
  std::vector<std::uint32_t> record(double model_rotation_radians = 0.0) const;

  const fw::Device& device() const { return device_; }

 private:
  struct MeshRange {
    std::uint32_t first_index = 0, index_count = 0;
    glm::dmat4 model{1.0};
  };
  // Everything set_scene derives from a scene, converted and validated before the device sees it.
  struct Prepared;
  Prepared prepare(const Scene& scene) const;
  std::vector<std::uint32_t> setup_commands(const Scene& scene, const Prepared& p) const;
  std::vector<std::uint32_t> frame_commands(double model_rotation_radians) const;
  void apply(const Scene& scene, const std::vector<std::uint32_t>& setup);
  fw::Mat4 modelview_for(const Scene& scene, const MeshRange& mesh, double rotation) const;
  [[noreturn]] void refused_frame(const StreamError& e, double rotation) const;

  std::vector<std::byte> memory_;
  fw::Device device_;
  Scene scene_;
  std::vector<MeshRange> meshes_;
  std::vector<std::uint32_t> setup_words_;  // the loaded scene's setup commands
  bool loaded_ = false;
};

// The device's current framebuffer as a DeviceFrame (RGB565 widened to RGB888; covered from the
// depth buffer); render_ms is left 0.
DeviceFrame read_frame(const fw::Device& device);

}  // namespace tp::host
