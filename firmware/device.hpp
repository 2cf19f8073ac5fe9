// The emulated device: a tiny display GPU driven by typed calls or by a command stream.
//
// Every command is validated. A command that fails returns its Error (also kept in
// last_error()) and changes nothing: neither the DeviceState nor any byte of device memory.
// A command that succeeds sets last_error() to kOk.
//
// Memory: the device runs entirely in the caller's block (no heap). Layout, each region
// 8-byte aligned, in this order (so that a viewport change keeps the uploaded buffers):
//   vertices   max_vertices x Vertex          (uploaded data)
//   cache      max_vertices x CachedVertex    (per-draw transformed and projected vertices)
//   indices    max_indices  x uint32
//   colour     width x height x 3 (RGB888) or 2 (RGB565, little-endian 5:6:5)
//   depth      width x height x uint32        (see docs/CONVENTIONS.md for the mapping; one row
//                                              only when ViewportCmd::depth_buffer is false)
//   counts     width x height x uint8         (only if ViewportCmd::write_count)
//   span       width x Rgb8                   (a method's output for one span)
//   levels     max_vertices x VertexLevels    (per-draw lit colours, only for a method that
//                                              lights vertices: Gouraud)
//   method     method_bytes(method)           (the active method's state: constructed there by
//                                              set_method and by every layout change)
// memory_required() gives the size for a configuration: for one method, or enough for every
// method. The Device object itself holds only the state, the counters and a pointer to the
// method (static_assert below: at most 4 KiB).
//
// Why the method is last: its size depends on the method (from a few dozen bytes for Gouraud
// to a quarter of a MiB for kb-adaptive's sample lattice), and a method change must not move
// the buffers.
//
// Depth buffer: 32-bit. NDC z in [-1, 1] maps to [0, 2^32 - 1]; 16 bits would leave a
// perspective camera with far/near = 1000 less than one depth step per 1/1000 of the depth
// range near the far plane (z-fighting on the teapot), and the 4096^2 budget is dominated by
// the colour buffer anyway. Without it (ViewportCmd::depth_buffer false: a part whose RAM holds
// a colour buffer and little more) the depth test passes every pixel: the back-face culling of a
// closed convex mesh is enough, a mesh that hides parts of itself needs the buffer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "firmware/counters.hpp"
#include "firmware/geometry.hpp"
#include "firmware/method.hpp"
#include "firmware/types.hpp"

namespace tp::fw {

// The depth word clear() stores: the far plane, which no write can store (a pixel is written
// only with a depth word below the stored one, when the depth test is on).
inline constexpr std::uint32_t kDepthFar = 0xffffffffu;

// Everything a command can change, apart from the memory block and the counters.
// Trivially copyable: tests byte-compare it across failing commands.
struct DeviceState {
  bool viewport_set = false;
  ViewportCmd viewport;
  BufferCapacityCmd capacity;
  Mat4 modelview;        // identity after construction
  Mat4 projection;       // identity after construction
  ShadeContext shading;  // material, lights, eye (counters pointer set by the device)
  Method method = Method::kGouraud;
  bool cull_back_faces = true;
  bool depth_test = true;
  std::uint32_t vertex_count = 0;  // vertices uploaded so far (high-water mark, no gaps)
  std::uint32_t index_count = 0;
  // The largest |coordinate| (raw Q15.16) uploaded since the capacity was set: lets a draw prove
  // that every position transforms (geometry.hpp, transform_cannot_fail).
  std::uint32_t coordinate_bound = 0;
  // Region offsets into the memory block (see the layout above).
  std::size_t off_vertices = 0, off_cache = 0, off_indices = 0, off_colour = 0, off_depth = 0,
              off_counts = 0, off_span = 0, off_levels = 0, off_method = 0, end = 0;
};

// The colour region's bytes per pixel.
constexpr std::size_t bytes_per_pixel(PixelFormat f) { return f == PixelFormat::kRgb565 ? 2 : 3; }

struct FramebufferView {
  const std::uint8_t* data = nullptr;  // row 0 first
  std::uint32_t width = 0, height = 0;
  std::uint32_t stride = 0;  // bytes per row
  PixelFormat format = PixelFormat::kRgb888;
};

// Row y of a framebuffer as RGB888, 3 * width bytes into `out`: RGB565 (little-endian 5:6:5)
// widened by bit replication, as a display shows it. For the frames that leave the device: the
// host's images and the replay image's PPM (target/replay.cpp).
inline void row_as_rgb888(const FramebufferView& fb, std::uint32_t y, std::uint8_t* out) {
  const std::uint8_t* row = fb.data + std::size_t{y} * fb.stride;
  if (fb.format == PixelFormat::kRgb888) {
    for (std::size_t i = 0; i < 3 * std::size_t{fb.width}; ++i) out[i] = row[i];
    return;
  }
  for (std::uint32_t x = 0; x < fb.width; ++x) {
    const unsigned v = unsigned{row[2 * x]} | (unsigned{row[2 * x + 1]} << 8);
    const unsigned r = (v >> 11) & 31u, g = (v >> 5) & 63u, b = v & 31u;
    out[3 * x] = static_cast<std::uint8_t>((r << 3) | (r >> 2));
    out[3 * x + 1] = static_cast<std::uint8_t>((g << 2) | (g >> 4));
    out[3 * x + 2] = static_cast<std::uint8_t>((b << 3) | (b >> 2));
  }
}

// Command stream (execute): a sequence of commands, each a header word
// (opcode | payload_words << 16) followed by its payload. Payload layouts (all words are
// uint32; Q values are their raw two's-complement bits):
enum class Opcode : std::uint16_t {
  kSetViewport = 1,        // width, height, format, flags (bit 0 counts, bit 1 no depth)  4
  kSetBufferCapacity = 2,  // max_vertices, max_indices                                  2
  kSetModelView = 3,       // 16 Q15.16, column-major m[col][row]                        16
  kSetProjection = 4,      // 16 Q15.16, column-major                                    16
  kSetEye = 5,             // EyeMode                                                    1
  kSetMaterial = 6,        // r g b ka kd ks (q1_30), n, a b (q2_29)                     9
  kSetLight = 7,           // index, type, r g b (Q15.16), dx dy dz (q1_30), px py pz    11
  kSetMethod = 8,          // Method                                                     1
  kSetCulling = 9,         // 0 / 1                                                      1
  kSetDepthTest = 10,      // 0 / 1                                                      1
  kUploadVertices = 11,    // first, count, count x (px py pz Q15.16, nx ny nz q1_30)    2 + 6 count
  kUploadIndices = 12,     // first, count, count x index                               2 + count
  kClear = 13,             // 0x00RRGGBB                                                 1
  kDraw = 14,              // first, count                                               2
  kEndFrame = 15,          //                                                            0
  kSetBudget = 16,         // error budget in output levels, 1 .. kMaxBudgetLevels      1
};

// The opcodes above, and each command's payload length in words (kVariablePayload for the
// uploads, whose count word gives theirs): execute's framing rules, which a host reading a stream
// ahead of the device (host/command_stream.cpp) follows too.
inline constexpr std::uint32_t kVariablePayload = 0xffff;
constexpr bool known_opcode(std::uint32_t op) { return op >= 1 && op <= 16; }
constexpr std::uint32_t payload_words(Opcode op) {
  switch (op) {
    case Opcode::kSetViewport: return 4;
    case Opcode::kSetBufferCapacity: return 2;
    case Opcode::kSetModelView:
    case Opcode::kSetProjection: return 16;
    case Opcode::kSetEye:
    case Opcode::kSetMethod:
    case Opcode::kSetCulling:
    case Opcode::kSetDepthTest:
    case Opcode::kSetBudget:
    case Opcode::kClear: return 1;
    case Opcode::kSetMaterial: return 9;
    case Opcode::kSetLight: return 11;
    case Opcode::kUploadVertices:
    case Opcode::kUploadIndices: return kVariablePayload;
    case Opcode::kDraw: return 2;
    case Opcode::kEndFrame: return 0;
  }
  return 0;
}
inline constexpr std::uint32_t command_header(Opcode op, std::uint32_t payload_length) {
  return static_cast<std::uint32_t>(op) | (payload_length << 16);
}

// The layout commands' values as the device accepts them (set_viewport, set_buffer_capacity and
// execute's decoding of them), rules that a host sizing a memory block for a stream ahead of the
// device (host/command_stream.cpp) applies too. Always inlined: a few comparisons each, which a
// size build would otherwise call. The tests are written as `if (...) return false;`, the form the
// device had inline: as one `return` expression GCC lays out the x86 -O2 code differently
// (docs/DECISIONS.md, "The layout commands' rules stated once"). set_viewport's flags word: bit 0
// write counts, bit 1 no depth buffer; any other bit is a malformed command (docs/CONVENTIONS.md).
inline constexpr std::uint32_t kViewportWriteCount = 1u, kViewportNoDepth = 2u;
inline constexpr std::uint32_t kViewportFlags = kViewportWriteCount | kViewportNoDepth;
// set_viewport's payload (width, height, format, flags) as the command; false if the flags word
// has another bit (kBadArgument).
[[gnu::always_inline]] constexpr bool decode_viewport(std::span<const std::uint32_t> p,
                                                      ViewportCmd& c) {
  c.width = p[0];
  c.height = p[1];
  c.format = static_cast<PixelFormat>(p[2]);
  c.write_count = (p[3] & kViewportWriteCount) != 0;
  c.depth_buffer = (p[3] & kViewportNoDepth) == 0;
  return (p[3] & ~kViewportFlags) == 0;
}
// Refused: kViewportTooLarge.
[[gnu::always_inline]] constexpr bool viewport_size_ok(const ViewportCmd& c) {
  if (c.width == 0 || c.height == 0 || c.width > kMaxDimension || c.height > kMaxDimension)
    return false;
  return true;
}
// Refused: kBadArgument, as a flags word with another bit is.
[[gnu::always_inline]] constexpr bool pixel_format_ok(PixelFormat f) {
  if (f != PixelFormat::kRgb888 && f != PixelFormat::kRgb565) return false;
  return true;
}
// Refused: kOutOfMemory (the layout's sizes would wrap).
[[gnu::always_inline]] constexpr bool capacity_ok(const BufferCapacityCmd& c) {
  if (c.max_vertices > kMaxVertexCapacity || c.max_indices > kMaxIndexCapacity) return false;
  return true;
}

class PixelWriter;    // draw.cpp: a draw's depth test and framebuffer writes
struct MethodTraits;  // registry.hpp

class Device {
 public:
  explicit Device(std::span<std::byte> memory);
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  // The block size for a configuration and method; without a method, enough for any method
  // (what a host that lets its user switch methods allocates).
  static std::size_t memory_required(const ViewportCmd& vp, const BufferCapacityCmd& cap, Method m);
  static std::size_t memory_required(const ViewportCmd& vp, const BufferCapacityCmd& cap);
  // The bytes of a method's state in the block; 0 for an id that no method implements.
  static std::size_t method_bytes(Method m);

  // Typed commands.
  Error set_viewport(const ViewportCmd& cmd);
  Error set_buffer_capacity(const BufferCapacityCmd& cmd);  // empties both buffers
  Error set_modelview(const Mat4& m);
  Error set_projection(const Mat4& m);
  Error set_eye(EyeMode mode);
  Error set_material(const MaterialCmd& cmd);
  Error set_light(const LightCmd& cmd);
  Error set_method(Method m);
  Error set_culling(bool on);
  Error set_depth_test(bool on);
  // The error budget (ShadeContext::budget_levels): kBadArgument outside 1 .. kMaxBudgetLevels.
  Error set_budget(std::uint32_t levels);
  // Uploads into the buffers laid out by set_buffer_capacity. kIndexOutOfRange when the range
  // ends beyond the capacity or starts beyond the count uploaded so far (no gaps: every slot a
  // draw may use was written by an upload); an empty upload within those bounds changes nothing.
  Error upload_vertices(std::uint32_t first, std::span<const Vertex> vertices);
  Error upload_indices(std::uint32_t first, std::span<const std::uint32_t> indices);
  Error clear(Rgb8 colour);  // colour, depth = far, counts = 0, counters reset (not frames)
  // kOutOfRange when a vertex its indices name leaves Q15.16 under the model-view and projection
  // (vertices it does not name are not its concern, though the vertex cache transforms them).
  Error draw(const DrawCmd& cmd);
  Error end_frame();

  // Decodes and runs commands in order; stops at the first failing command (earlier ones stay
  // applied) and returns its error. words_consumed() tells how far it got.
  Error execute(std::span<const std::uint32_t> words);
  std::size_t words_consumed() const { return consumed_; }

  // Read-back.
  Error last_error() const { return last_error_; }
  const DeviceState& state() const { return state_; }
  const Counters& counters() const { return counters_; }
  FramebufferView framebuffer() const;
  const std::uint32_t* depth_buffer() const;  // nullptr before set_viewport, or without one
  const std::uint8_t* write_counts() const;   // nullptr unless enabled: writes per pixel
                                              // since clear, saturating at 255

 private:
  friend class PixelWriter;
  Error fail(Error e) { return last_error_ = e; }
  Error ok() { return last_error_ = Error::kOk; }
  bool layout(const ViewportCmd& vp, const BufferCapacityCmd& cap, DeviceState& s) const;
  void clear_regions(Rgb8 colour);
  ShadingMethod& method() { return *method_; }
  static MethodTraits method_traits(Method m);  // its registry row's; none for an unlinked id
  void construct_method();
  void release_method();
  template <class T>
  T* region(std::size_t off) const {
    return reinterpret_cast<T*>(mem_.data() + off);
  }
  void set_object_centre(const std::uint32_t* idx, std::uint32_t count);
  void draw_triangle(const std::uint32_t id[3], VertexLevels* levels, PixelWriter& writer);
  // A triangle that crosses a clip plane: clipped, projected and drawn as a fan.
  void draw_crossing_triangle(const std::uint32_t id[3], VertexLevels* levels, PixelWriter& writer);
  ShadeVertex shade_vertex(std::uint32_t id);  // an inside vertex from the cache, with its normal
  void draw_fan_triangle(const ShadeVertex& a, const ShadeVertex& b, const ShadeVertex& c,
                         bool front, VertexLevels* levels, PixelWriter& writer);
  const Vec3u& vertex_normal(std::uint32_t id);  // transformed on first use in a draw
  Error execute_one(Opcode op, std::span<const std::uint32_t> p);
  static Error validate_vertex(const Vertex& v);

  std::span<std::byte> mem_;
  DeviceState state_;
  Counters counters_;
  Error last_error_ = Error::kOk;
  std::size_t consumed_ = 0;
  ShadingMethod* method_ = nullptr;  // in the block's method region; set while viewport_set
};

// Everything that grows with the resolution, the buffers or the method is in the caller's block;
// the object itself must fit a small part's RAM beside it (docs/TARGET.md, "Memory").
static_assert(sizeof(Device) <= 4096);

}  // namespace tp::fw
