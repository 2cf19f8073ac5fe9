// Typed commands: validation, memory layout and the active method's region. The draw pipeline
// that runs on this state is in draw.cpp.
#include "firmware/device.hpp"

#include <algorithm>
#include <array>
#include <cstring>

#include "firmware/registry.hpp"
#include "fixedpoint/cordic.hpp"

namespace tp::fw {
namespace {

constexpr std::size_t align8(std::size_t v) { return (v + 7) & ~std::size_t{7}; }

// The depth region's words: one per pixel, or without a depth buffer one row, where the pixel
// loops store the depth words that no test reads.
constexpr std::size_t depth_words(const ViewportCmd& vp) {
  return vp.depth_buffer ? std::size_t{vp.width} * vp.height : std::size_t{vp.width};
}

bool coord_ok(q15_16 v) { return v.raw() >= -kMaxCoordRaw && v.raw() <= kMaxCoordRaw; }
// A raw component is any int32 (|raw| <= 2^31), not only a unit vector's: each square is at most
// 2^62 and the sum of three at most 3 * 2^62, which fits an unsigned 64-bit integer but not a
// signed one (the signed sum overflowed; found by fuzzing the command stream, tests/fuzz).
std::uint64_t square(std::int32_t raw) {
  const std::int64_t wide = raw;
  const auto magnitude = static_cast<std::uint64_t>(wide < 0 ? -wide : wide);
  return magnitude * magnitude;
}
bool unit_ok(const Vec3u& v) {
  const std::uint64_t sum = square(v.x.raw()) + square(v.y.raw()) + square(v.z.raw());
  constexpr std::uint64_t kOne = std::uint64_t{1} << 60;
  const std::uint64_t distance = sum >= kOne ? sum - kOne : kOne - sum;
  return distance <= static_cast<std::uint64_t>(kUnitToleranceRaw);
}
bool in_unit_interval(q1_30 v) { return v.raw() >= 0 && v.raw() <= q1_30::one().raw(); }

Mat4 identity() {
  Mat4 m{};
  for (int i = 0; i < 4; ++i) m.m[i][i] = q15_16::one();
  return m;
}

// The methods linked into this build: bit id of TP_FIRMWARE_METHODS for Method id (types.hpp).
// Every method by default; a port to a small part links the few it ships (docs/TARGET.md,
// "Footprint": the others' code then drops out at link time, since only their slot refers to
// it), and set_method refuses the rest as it refuses an unassigned id.
#ifndef TP_FIRMWARE_METHODS
#define TP_FIRMWARE_METHODS (~0ull)
#endif
constexpr bool linked(Method m) {
  return ((std::uint64_t{TP_FIRMWARE_METHODS} >> static_cast<std::uint32_t>(m)) & 1u) != 0;
}

// The registry's slots by id (firmware/registry.hpp), derived at compile time: the table's names
// and descriptions stay out of the firmware's image. An id without a row (a reserved one of
// types.hpp, or a method this build leaves out) has none: set_method refuses it.
// A row is 12 bytes on a 32-bit part: the registry's MethodSlot beside its id would pad to 16.
struct SlotRow {
  std::uint32_t bytes;
  ShadingMethod* (*construct)(void* where);
  std::uint8_t id;  // the Method (TP_FIRMWARE_METHODS's mask keeps ids below 64)
  MethodTraits traits;
};
constexpr std::size_t kLinkedMethods = [] {
  std::size_t n = 0;
  for (const MethodInfo& m : kMethodTable) n += linked(m.id) ? 1u : 0u;
  return n;
}();
static_assert(linked(Method::kGouraud),
              "a device starts with Gouraud: TP_FIRMWARE_METHODS needs it");
constexpr auto kSlots = [] {
  std::array<SlotRow, kLinkedMethods> rows{};
  std::size_t i = 0;
  for (const MethodInfo& m : kMethodTable)
    if (linked(m.id))
      rows[i++] = {static_cast<std::uint32_t>(m.slot.bytes), m.slot.construct,
                   static_cast<std::uint8_t>(m.id), m.slot.traits};
  return rows;
}();
static_assert(sizeof(void*) != 4 || sizeof(SlotRow) == 12);
static_assert(
    [] {
      for (const MethodInfo& m : kMethodTable)
        if (m.slot.bytes > 0xffffffffu || static_cast<std::uint32_t>(m.id) > 0xffu) return false;
      return true;
    }(),
    "a row holds a method's size in 32 bits and its id in 8");
MethodSlot method_slot(Method m) {
  for (const SlotRow& row : kSlots)
    if (row.id == static_cast<std::uint32_t>(m))
      return MethodSlot{row.bytes, row.construct, row.traits};
  return MethodSlot{};
}
// The lit-vertex cache's bytes for method m (0 for a method that does not light vertices).
std::size_t levels_bytes(Method m, const BufferCapacityCmd& cap) {
  return method_slot(m).traits.lights_vertices
             ? std::size_t{cap.max_vertices} * sizeof(VertexLevels)
             : 0;
}

}  // namespace

Device::Device(std::span<std::byte> memory) {
  // Align the block's start to 8 bytes; the layout offsets are relative to it.
  const auto addr = reinterpret_cast<std::uintptr_t>(memory.data());
  const std::size_t skip = std::min<std::size_t>((8 - (addr & 7)) & 7, memory.size());
  mem_ = memory.subspan(skip);
  state_.modelview = identity();
  state_.projection = identity();
  state_.shading.material.color[0] = state_.shading.material.color[1] =
      state_.shading.material.color[2] = q1_30::one();
  state_.shading.material.kd = q1_30::one();
  state_.shading.counters = &counters_;
  DeviceState s = state_;
  if (layout(state_.viewport, state_.capacity, s)) {
    state_ = s;
    construct_method();
  }
}

std::size_t Device::method_bytes(Method m) { return method_slot(m).bytes; }

MethodTraits Device::method_traits(Method m) { return method_slot(m).traits; }

// Not in a header, nor in draw.cpp beside the pipeline's call: where this body is visible and no
// method class is, GCC guesses that the call comes here, and that guess, tested at every span,
// cost PixelWriter::span some twenty more loads and stores of spilled registers on the Cortex-M3.
LinearColours ShadingMethod::linear_span(const Span& s) {
  static_cast<void>(s);
  return LinearColours{};
}

std::size_t Device::memory_required(const ViewportCmd& vp, const BufferCapacityCmd& cap, Method m) {
  const std::size_t pixels = std::size_t{vp.width} * vp.height;
  std::size_t n = align8(std::size_t{cap.max_vertices} * sizeof(Vertex));
  n += align8(std::size_t{cap.max_vertices} * sizeof(CachedVertex));
  n += align8(std::size_t{cap.max_indices} * sizeof(std::uint32_t));
  n += align8(pixels * bytes_per_pixel(vp.format));
  n += align8(depth_words(vp) * sizeof(std::uint32_t));
  if (vp.write_count) n += align8(pixels);
  n += align8(std::size_t{vp.width} * sizeof(Rgb8));  // one span: at most the viewport's width
  n += align8(levels_bytes(m, cap));
  n += align8(method_bytes(m));
  return n;
}

std::size_t Device::memory_required(const ViewportCmd& vp, const BufferCapacityCmd& cap) {
  std::size_t largest = 0;
  for (const SlotRow& row : kSlots)
    largest = std::max(largest, memory_required(vp, cap, static_cast<Method>(row.id)));
  return largest;
}

bool Device::layout(const ViewportCmd& vp, const BufferCapacityCmd& cap, DeviceState& s) const {
  if (!capacity_ok(cap)) return false;  // so that the sizes below cannot wrap
  if (memory_required(vp, cap, s.method) > mem_.size()) return false;
  const std::size_t pixels = std::size_t{vp.width} * vp.height;
  std::size_t o = 0;
  s.off_vertices = o;
  o += align8(std::size_t{cap.max_vertices} * sizeof(Vertex));
  s.off_cache = o;
  o += align8(std::size_t{cap.max_vertices} * sizeof(CachedVertex));
  s.off_indices = o;
  o += align8(std::size_t{cap.max_indices} * sizeof(std::uint32_t));
  s.off_colour = o;
  o += align8(pixels * bytes_per_pixel(vp.format));
  s.off_depth = o;
  o += align8(depth_words(vp) * sizeof(std::uint32_t));
  s.off_counts = o;
  if (vp.write_count) o += align8(pixels);
  s.off_span = o;
  o += align8(std::size_t{vp.width} * sizeof(Rgb8));
  s.off_levels = o;
  o += align8(levels_bytes(s.method, cap));
  s.off_method = o;
  o += align8(method_bytes(s.method));
  s.end = o;
  s.viewport = vp;
  s.capacity = cap;
  return true;
}

Error Device::set_viewport(const ViewportCmd& cmd) {
  if (!viewport_size_ok(cmd)) return fail(Error::kViewportTooLarge);
  if (!pixel_format_ok(cmd.format)) return fail(Error::kBadArgument);
  DeviceState s = state_;
  if (!layout(cmd, state_.capacity, s)) return fail(Error::kOutOfMemory);
  release_method();
  state_ = s;
  state_.viewport_set = true;
  construct_method();  // its region may have moved
  clear_regions(Rgb8{0, 0, 0});
  return ok();
}

Error Device::set_buffer_capacity(const BufferCapacityCmd& cmd) {
  DeviceState s = state_;
  if (!layout(state_.viewport, cmd, s)) return fail(Error::kOutOfMemory);
  s.vertex_count = 0;
  s.index_count = 0;
  s.coordinate_bound = 0;
  release_method();
  state_ = s;
  construct_method();                                     // its region may have moved
  if (state_.viewport_set) clear_regions(Rgb8{0, 0, 0});  // the framebuffer moved
  return ok();
}

Error Device::set_modelview(const Mat4& m) {
  for (const auto& col : m.m)
    for (const q15_16 v : col)
      if (!coord_ok(v)) return fail(Error::kOutOfRange);
  state_.modelview = m;
  return ok();
}

Error Device::set_projection(const Mat4& m) {
  for (const auto& col : m.m)
    for (const q15_16 v : col)
      if (!coord_ok(v)) return fail(Error::kOutOfRange);
  state_.projection = m;
  return ok();
}

Error Device::set_eye(EyeMode mode) {
  if (mode != EyeMode::kFinite && mode != EyeMode::kInfinite) return fail(Error::kBadArgument);
  state_.shading.eye = mode;
  ++state_.shading.revision;
  return ok();
}

Error Device::set_material(const MaterialCmd& cmd) {
  for (const q1_30 c : cmd.color)
    if (!in_unit_interval(c)) return fail(Error::kOutOfRange);
  if (!in_unit_interval(cmd.ka) || !in_unit_interval(cmd.kd) || !in_unit_interval(cmd.ks))
    return fail(Error::kOutOfRange);
  if (cmd.n < 1 || cmd.n > kMaxExponent) return fail(Error::kOutOfRange);
  // (a, b): both unset (0), or 0 <= a < b <= π/2 (rounded to the angle format).
  const bool unset = cmd.a.raw() == 0 && cmd.b.raw() == 0;
  if (!unset && !(cmd.a.raw() >= 0 && cmd.a < cmd.b && cmd.b <= fx::half_pi()))
    return fail(Error::kOutOfRange);
  state_.shading.material = cmd;
  ++state_.shading.revision;
  return ok();
}

Error Device::set_light(const LightCmd& cmd) {
  if (cmd.index >= kProtocolLights) return fail(Error::kTooManyLights);
  if (cmd.type != LightType::kOff && cmd.type != LightType::kDirectional &&
      cmd.type != LightType::kPoint)
    return fail(Error::kBadArgument);
  // A slot past the build's lights (TP_MAX_LIGHTS) is off and stays off: a stream recorded for
  // 16 slots runs unchanged where its lit ones fit.
  if (cmd.index >= kMaxLights) {
    if (cmd.type != LightType::kOff) return fail(Error::kTooManyLights);
    ++state_.shading.revision;  // as for any set_light: the same revisions as a full build
    return ok();
  }
  LightState l;
  l.type = cmd.type;
  if (cmd.type != LightType::kOff) {
    for (const q15_16 c : cmd.color)
      if (c.raw() < 0 || c.raw() > kMaxIntensityRaw) return fail(Error::kOutOfRange);
    for (int c = 0; c < 3; ++c) l.color[c] = cmd.color[c];
  }
  if (cmd.type == LightType::kDirectional) {
    if (!unit_ok(cmd.direction)) return fail(Error::kNotUnit);
    l.direction = cmd.direction;
  }
  if (cmd.type == LightType::kPoint) {
    if (!coord_ok(cmd.position.x) || !coord_ok(cmd.position.y) || !coord_ok(cmd.position.z))
      return fail(Error::kOutOfRange);
    l.position = cmd.position;
  }
  state_.shading.lights[cmd.index] = l;
  ++state_.shading.revision;
  return ok();
}

Error Device::set_method(Method m) {
  // Only implemented methods; the reserved ids of types.hpp are refused until they exist.
  if (method_bytes(m) == 0) return fail(Error::kUnknownMethod);
  if (m == state_.method && method_ != nullptr) return ok();
  DeviceState s = state_;
  s.method = m;
  if (!layout(s.viewport, s.capacity, s)) return fail(Error::kOutOfMemory);
  release_method();
  state_ = s;
  construct_method();
  return ok();
}

// Zeroes the active method's region before the layout or the method changes: the object holds
// pointers to this device's state, which must not outlive it in bytes that the next layout
// gives to a buffer (the block stays a function of the commands alone).
void Device::release_method() {
  if (method_ == nullptr) return;
  std::memset(mem_.data() + state_.off_method, 0, state_.end - state_.off_method);
  method_ = nullptr;
}

// A fresh object of the state's method in its region: the region is zeroed first, so that no
// byte of an earlier method (or of the caller's block) can reach the new one.
void Device::construct_method() {
  std::byte* where = mem_.data() + state_.off_method;
  std::memset(where, 0, state_.end - state_.off_method);
  method_ = method_slot(state_.method).construct(where);
}

Error Device::set_culling(bool on) {
  state_.cull_back_faces = on;
  return ok();
}

Error Device::set_depth_test(bool on) {
  state_.depth_test = on;
  return ok();
}

// Not a revision of the shading state: what the methods cache from it (kb-adaptive's boundary
// samples, PointShader's lights) does not depend on the budget.
Error Device::set_budget(std::uint32_t levels) {
  if (levels < 1 || levels > kMaxBudgetLevels) return fail(Error::kBadArgument);
  state_.shading.budget_levels = levels;
  return ok();
}

Error Device::validate_vertex(const Vertex& v) {
  if (!coord_ok(v.position.x) || !coord_ok(v.position.y) || !coord_ok(v.position.z))
    return Error::kOutOfRange;
  return unit_ok(v.normal) ? Error::kOk : Error::kNotUnit;
}

// An upload starts at or below the count so far: the slots below the count are then exactly the
// ones uploaded (and validated) since the buffers were laid out. A gap would make slots the draw
// may index, and whose transform it trusts to coordinate_bound, of bytes no command wrote.
Error Device::upload_vertices(std::uint32_t first, std::span<const Vertex> vertices) {
  const std::uint64_t end = std::uint64_t{first} + vertices.size();
  if (end > state_.capacity.max_vertices || first > state_.vertex_count)
    return fail(Error::kIndexOutOfRange);
  for (const Vertex& v : vertices) {
    const Error e = validate_vertex(v);
    if (e != Error::kOk) return fail(e);
  }
  if (!vertices.empty())
    std::memcpy(region<Vertex>(state_.off_vertices) + first, vertices.data(),
                vertices.size_bytes());
  if (end > state_.vertex_count) state_.vertex_count = static_cast<std::uint32_t>(end);
  const auto magnitude = [](q15_16 c) {
    return static_cast<std::uint32_t>(c.raw() < 0 ? -c.raw() : c.raw());  // |raw| <= 2^14·2^16
  };
  for (const Vertex& v : vertices)
    state_.coordinate_bound = std::max({state_.coordinate_bound, magnitude(v.position.x),
                                        magnitude(v.position.y), magnitude(v.position.z)});
  return ok();
}

Error Device::upload_indices(std::uint32_t first, std::span<const std::uint32_t> indices) {
  const std::uint64_t end = std::uint64_t{first} + indices.size();
  if (end > state_.capacity.max_indices || first > state_.index_count)
    return fail(Error::kIndexOutOfRange);
  if (!indices.empty())
    std::memcpy(region<std::uint32_t>(state_.off_indices) + first, indices.data(),
                indices.size_bytes());
  if (end > state_.index_count) state_.index_count = static_cast<std::uint32_t>(end);
  return ok();
}

void Device::clear_regions(Rgb8 colour) {
  const DeviceState& s = state_;
  const std::size_t width = s.viewport.width, pixels = width * s.viewport.height;
  if (pixels == 0) return;
  // The first row pixel by pixel, then every other row copied from it: the copies and the
  // depth fill are the library's block moves, not a byte store per channel and pixel (a clear of
  // 640x480 took 2.7 million instructions, a quarter of the teapot's draw with Gouraud).
  std::uint8_t* c = region<std::uint8_t>(s.off_colour);
  const std::size_t row = width * bytes_per_pixel(s.viewport.format);
  if (s.viewport.format == PixelFormat::kRgb565) {
    const auto v = static_cast<std::uint16_t>(((colour.r >> 3) << 11) | ((colour.g >> 2) << 5) |
                                              (colour.b >> 3));
    for (std::size_t i = 0; i < width; ++i) {
      c[2 * i] = static_cast<std::uint8_t>(v & 0xffu);
      c[2 * i + 1] = static_cast<std::uint8_t>(v >> 8);
    }
  } else {
    for (std::size_t i = 0; i < width; ++i) {
      c[3 * i] = colour.r;
      c[3 * i + 1] = colour.g;
      c[3 * i + 2] = colour.b;
    }
  }
  for (std::size_t y = 1; y < s.viewport.height; ++y) std::memcpy(c + y * row, c, row);
  static_assert(kDepthFar == 0xffffffffu, "the depth fill sets every byte");
  std::memset(region<std::uint32_t>(s.off_depth), 0xff,
              depth_words(s.viewport) * sizeof(std::uint32_t));
  if (s.viewport.write_count) std::memset(region<std::uint8_t>(s.off_counts), 0, pixels);
}

Error Device::clear(Rgb8 colour) {
  if (!state_.viewport_set) return fail(Error::kNoViewport);
  clear_regions(colour);
  const std::uint64_t frames = counters_.frames;
  counters_ = Counters{};
  counters_.frames = frames;
  return ok();
}

Error Device::end_frame() {
  ++counters_.frames;
  return ok();
}

FramebufferView Device::framebuffer() const {
  if (!state_.viewport_set) return FramebufferView{};
  const auto bpp = static_cast<std::uint32_t>(bytes_per_pixel(state_.viewport.format));
  return FramebufferView{region<std::uint8_t>(state_.off_colour), state_.viewport.width,
                         state_.viewport.height, state_.viewport.width * bpp,
                         state_.viewport.format};
}

const std::uint32_t* Device::depth_buffer() const {
  return state_.viewport_set && state_.viewport.depth_buffer
             ? region<std::uint32_t>(state_.off_depth)
             : nullptr;
}

const std::uint8_t* Device::write_counts() const {
  return state_.viewport_set && state_.viewport.write_count
             ? region<std::uint8_t>(state_.off_counts)
             : nullptr;
}

}  // namespace tp::fw