// What the device-level Kuijk-Blake tests share: a shipped scene by name, one frame of it with a
// given method, and a counter of that frame.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "host/device_renderer.hpp"
#include "host/scene.hpp"

namespace tp::host::kbtest {

// The paper scenes with 1, 2, 4 and 8 lights (scenes/README.md).
inline constexpr const char* kPaperScenes[] = {
    "sphere-32",       "sphere-32-l2",       "sphere-32-l4",       "sphere-32-l8",
    "sphere-512",      "sphere-512-l2",      "sphere-512-l4",      "sphere-512-l8",
    "sphere-40",       "sphere-40-l2",       "sphere-40-l4",       "sphere-40-l8",
    "dodecahedron-30", "dodecahedron-30-l2", "dodecahedron-30-l4", "dodecahedron-30-l8",
    "triangle",        "triangle-l2",        "triangle-l4",        "triangle-l8",
    "teapot",          "teapot-l2",          "teapot-l4",          "teapot-l8"};

// A test-name suffix for a scene name ("stress/triangle-near-1" -> "stress_triangle_near_1").
inline std::string test_name_of(std::string n) {
  for (char& c : n)
    if (c == '-' || c == '/') c = '_';
  return n;
}

// scenes/<name>.json (name may hold a sub-folder: "stress/triangle-near-1").
inline Scene scene_named(const std::string& name) {
  return load_scene(std::string(TP_SCENES_DIR) + "/" + name + ".json");
}

inline DeviceFrame render(DeviceRenderer& device, Scene scene, const std::string& method) {
  scene.method = method;
  device.set_scene(scene);
  return device.render(0.0);
}

inline std::uint64_t counter(const DeviceFrame& f, const std::string& name) {
  for (const auto& [n, v] : f.counters)
    if (n == name) return v;
  ADD_FAILURE() << "no counter " << name;
  return 0;
}

}  // namespace tp::host::kbtest
