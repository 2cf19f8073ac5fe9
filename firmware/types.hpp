// Public data types of the emulated device: formats, error codes, method ids and one struct
// per command payload. Everything the host glue needs to drive the device is here or in
// device.hpp; docs/CONVENTIONS.md states the rendering conventions these types follow.
#pragma once

#include <cstdint>

#include "fixedpoint/q.hpp"
#include "fixedpoint/vec3.hpp"

namespace tp::fw {

using fx::q15_16;
using fx::q1_30;
using fx::q2_29;

// Every command returns one of these; the device also keeps the last one (last_error()).
// A command that returns anything but kOk has changed nothing in the device state.
enum class Error : std::uint32_t {
  kOk = 0,
  kBadOpcode = 1,         // command stream: unknown opcode
  kBadLength = 2,         // command stream: payload length wrong for the opcode
  kBadArgument = 3,       // an enum or flag outside its documented values
  kOutOfMemory = 4,       // the layout (framebuffer, buffers) does not fit the memory block
  kViewportTooLarge = 5,  // width or height 0 or above kMaxDimension
  kIndexOutOfRange = 6,   // an index >= vertex count, a range outside a buffer
  kNotUnit = 7,           // a normal / direction whose squared length is not 1 within tolerance
  kOutOfRange = 8,        // a matrix entry, coordinate or transformed value not representable
  kTooManyLights = 9,     // light index >= 16, or a lit one >= kMaxLights (TP_MAX_LIGHTS)
  kUnknownMethod = 10,    // method id not implemented (reserved ids included) or not linked
  kNoViewport = 11,       // draw/clear before set_viewport
};

enum class PixelFormat : std::uint32_t { kRgb888 = 0, kRgb565 = 1 };

// Shading methods (their CLI names: host/device_renderer.cpp). Reserved ids are rejected by
// set_method until implemented.
enum class Method : std::uint32_t {
  kFlat = 1,
  kGouraud = 2,
  kPhong = 3,
  kDuff = 4,              // Duff's forward-differenced Phong (firmware/shade_duff.cpp)
  kBishopWeimer = 5,      // Bishop-Weimer fast Phong (firmware/shade_bishop_weimer.cpp)
  kKuijkBlake = 6,        // Kuijk-Blake one-vector, eq. 4 (firmware/kb/)
  kBrown = 7,             // Brown's Bézier-triangle highlights (firmware/shade_brown.cpp)
  kQuadratic = 8,         // Vlasic's quadratic shading (firmware/shade_quadratic.cpp)
  kKuijkBlakeNoSkip = 9,  // the same with every skip disabled (verification: identical image)
  // 10: unassigned (tests/firmware/command_test.cpp uses it as an id nothing implements).
  kKuijkBlakeDecomposition = 11,   // Kuijk-Blake decomposition, eq. 2
  kKuijkBlakeExact = 12,           // Kuijk-Blake exact angular interpolation, eq. 1
  kKuijkBlakeAdaptive = 13,        // per-triangle choice under an error budget (kb_adaptive.hpp)
  kKuijkBlakeAdaptiveNoSkip = 14,  // the same without skipping (verification: identical image)
  kKuijkBlakeAdaptiveExact = 15,   // its exact evaluation at every pixel (the budget's reference)
  // Bishop-Weimer's finite-eye extension (firmware/shade_bishop_weimer_finite.cpp).
  kBishopWeimerFinite = 16,
  kBrownNoSkip = 17,  // brown without its convex-hull culling (verification: identical image)
  // Gouraud on the triangle cut into four at its edge midpoints (shade_gouraud_subdivided.cpp).
  kGouraudSubdivided = 18,
  kQuadraticScreen = 19,  // quadratic with screen-linear (s, t) under perspective too
  // 20: unassigned (tests/firmware/command_test.cpp uses it as an id nothing implements).
  kEnvmap = 21,             // Vlasic's sphere environment map (firmware/shade_envmap.cpp)
  kBlinnMap = 22,           // Vlasic's Blinn map (firmware/shade_blinn_map.cpp)
  kQuadraticBlinnMap = 23,  // its coordinates interpolated quadratically (the same file)
};

enum class LightType : std::uint32_t { kOff = 0, kDirectional = 1, kPoint = 2 };
enum class EyeMode : std::uint32_t { kFinite = 0, kInfinite = 1 };

// Device limits. The bound arguments are in raster.hpp (coordinates) and device.cpp (inputs).
inline constexpr std::uint32_t kMaxDimension = 4096;  // largest width and height
// Largest buffer capacities (set_buffer_capacity): bounded so that the layout's sizes cannot wrap
// a 32-bit size_t.
inline constexpr std::uint32_t kMaxVertexCapacity = 1u << 24, kMaxIndexCapacity = 1u << 26;
// The command stream has 16 light slots (set_light's index, 0 .. 15). A build shades up to
// TP_MAX_LIGHTS of them (1 .. 16, default 16): a port for a part with little RAM sets fewer, and
// every per-light array of the methods' state shrinks with it (kb's from 83,680 bytes to 12,112
// at 2 lights on x86-64; docs/TARGET.md, "A small part"). The slots past it are always off:
// set_light accepts them off (a no-op) and refuses them lit (kTooManyLights).
inline constexpr std::uint32_t kProtocolLights = 16;
#ifndef TP_MAX_LIGHTS
#define TP_MAX_LIGHTS 16
#endif
inline constexpr std::uint32_t kMaxLights = TP_MAX_LIGHTS;
static_assert(kMaxLights >= 1 && kMaxLights <= kProtocolLights, "TP_MAX_LIGHTS: 1 .. 16");
inline constexpr std::uint32_t kMaxBudgetLevels = 16;  // largest error budget (set_budget)
// Blinn-Phong n: every method evaluates any exponent up to the (a, b) fits' range
// (cosn::kMaxN, checked in firmware/cosn.hpp); the power by repeated squaring takes 14 steps.
inline constexpr std::uint32_t kMaxExponent = 10000;
// Matrix entries and vertex coordinates must satisfy |v| < 2^14 (so that a 4-term dot product of
// raw Q15.16 values stays below 2^62 in 64-bit arithmetic).
inline constexpr std::int32_t kMaxCoordRaw = (std::int32_t{1} << 30) - 1;
// Light intensities per channel: 0 <= I <= 16.
inline constexpr std::int32_t kMaxIntensityRaw = std::int32_t{16} << 16;
// A unit vector is accepted if | |v|^2 - 1 | <= 2^-12.
inline constexpr std::int64_t kUnitToleranceRaw = std::int64_t{1} << (60 - 12);

// 4x4 matrix, column-major like OpenGL/GLM: m[col][row], Q15.16.
struct Mat4 {
  q15_16 m[4][4];
};

using Vec3q16 = fx::Vec3<q15_16>;  // a position
using Vec3u = fx::Vec3<q1_30>;     // a unit vector

// Payload structs, one per command.
struct ViewportCmd {
  std::uint32_t width = 0, height = 0;
  PixelFormat format = PixelFormat::kRgb888;
  bool write_count = false;  // keep a per-pixel count of writes this frame (tests, metrics)
  // false: no depth buffer in the memory block (4 bytes per pixel saved, one row kept for the
  // pixel loops' stores); the depth test then passes every pixel, as if it were off (OpenGL's
  // rule without a depth buffer), whatever set_depth_test says.
  bool depth_buffer = true;
};
struct BufferCapacityCmd {
  std::uint32_t max_vertices = 0, max_indices = 0;
};
struct MaterialCmd {
  q1_30 color[3];       // O_c in [0, 1]
  q1_30 ka, kd, ks;     // each in [0, 1]
  std::uint32_t n = 1;  // Blinn-Phong exponent, 1..kMaxExponent
  // Kuijk-Blake (a, b) in radians for the later methods: 0 <= a < b <= pi/2, or both 0 (unset).
  q2_29 a, b;
};
struct LightCmd {
  std::uint32_t index = 0;
  LightType type = LightType::kOff;
  q15_16 color[3];   // intensity per channel, 0..16
  Vec3u direction;   // directional: unit vector TOWARD the light, eye space
  Vec3q16 position;  // point: eye-space position
};
struct Vertex {
  Vec3q16 position;  // model space
  Vec3u normal;      // model space, unit
};
struct DrawCmd {
  std::uint32_t first = 0, count = 0;  // a range of the index buffer; count % 3 == 0
};

struct Rgb8 {
  std::uint8_t r, g, b;
};

}  // namespace tp::fw
