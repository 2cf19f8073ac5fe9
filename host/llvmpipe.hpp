// Mesa's llvmpipe, through OSMesa, as the peer a desktop user would pick instead of the device
// (docs/RESULTS.md, its opening on the `llvmpipe` rows): the same scene — camera, meshes, lights,
// material, culling, background — drawn by OpenGL 3.3 core with per-pixel float Blinn-Phong in
// GLSL, the formula of the double reference (docs/CONVENTIONS.md, "Shared contract"): N and the
// eye-space position interpolated perspective-correctly, N renormalised per pixel, true per-pixel
// L and H. Single-threaded (LP_NUM_THREADS=0, set before the first context), like the device.
//
// It is a benchmark peer and an independent oracle for the reference: its rasterizer, clipper
// and arithmetic share nothing with ours.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/image.hpp"
#include "host/scene.hpp"

namespace tp::host {

// OSMesa or the GL driver refused something (no context, a shader that does not compile, a
// renderer that is not llvmpipe); the message says what.
class PeerError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct PeerFrame {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;      // RGB888, row-major, top row first
  std::vector<std::uint8_t> covered;  // 1 where a fragment was written (alpha cleared to 0)
  double render_ms = 0;               // wall time of clear + draws + glFinish
  Image8 image() const;
};

class LlvmpipePeer {
 public:
  // A context with a width × height RGBA8 colour buffer and a 24-bit depth buffer.
  LlvmpipePeer(int width, int height);
  ~LlvmpipePeer();
  LlvmpipePeer(const LlvmpipePeer&) = delete;
  LlvmpipePeer& operator=(const LlvmpipePeer&) = delete;

  // Uploads the scene's meshes (model-space positions and normals, in vertex buffers) and its
  // lights and material (uniforms); not timed. The scene's resolution must be the peer's.
  void set_scene(const Scene& scene);
  // One frame, the objects rotated about the world y axis as DeviceRenderer::render does.
  PeerFrame render(double model_rotation_radians = 0.0);

  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  std::string renderer() const;

 private:
  struct Gl;
  std::unique_ptr<Gl> gl_;
};

}  // namespace tp::host
