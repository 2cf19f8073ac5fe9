// Typed commands: validation, memory layout, and the draw pipeline (transform -> clip ->
// project -> cull -> rasterize -> shade -> depth test -> write).
#include "firmware/device.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>

#include "firmware/build.hpp"
#include "firmware/raster.hpp"
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

std::size_t bytes_per_pixel(PixelFormat f) { return f == PixelFormat::kRgb565 ? 2 : 3; }

// NDC z (Q.30, clamped to [-2, 2]) -> depth word: [-1, 1] -> [0, 2^32 - 1], saturating.
std::uint32_t depth_word(std::int64_t z_q30) {
  const std::int64_t d = (z_q30 + (std::int64_t{1} << 30)) * 2;
  return d <= 0 ? 0u : (d >= std::int64_t{kDepthFar} ? kDepthFar : static_cast<std::uint32_t>(d));
}
// Whether depth_word(z_q30) needs no saturation (monotonic in z: true at both ends of a linear
// run means true along it).
bool depth_in_range(std::int64_t z_q30) {
  const std::int64_t d = (z_q30 + (std::int64_t{1} << 30)) * 2;
  return d > 0 && d < std::int64_t{kDepthFar};
}
// depth_word where depth_in_range holds.
std::uint32_t depth_word_unsaturated(std::int64_t z_q30) {
  return static_cast<std::uint32_t>((z_q30 + (std::int64_t{1} << 30)) * 2);
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
// A normal the draw has not transformed yet: no unit normal has this raw x (|x| <= 2^30).
constexpr std::int32_t kNormalPending = std::numeric_limits<std::int32_t>::min();

}  // namespace

// The span target of a draw: asks the method for the span's colours, then depth-tests and
// writes them. Depth is interpolated linearly in screen space (NDC z is screen-affine).
//
// Everything that is fixed for the draw — the regions' addresses, the pixel format, the depth
// test, the write counts — is resolved once per draw, in the constructor, into base pointers
// and the two pixel loops (with and without depth saturation) for this state (a size build has
// one loop per colour source for every state, firmware/build.hpp); begin() takes each triangle's
// depth plane, and the counters are summed in members and added to the device's once, by
// flush_counters(). Per span there is then the method's call, the depth at the span's start, and
// one call of the chosen loop.
class PixelWriter final {
 public:
  explicit PixelWriter(Device& d) : dev_(d) {
    const DeviceState& st = d.state_;
    width_ = st.viewport.width;
    bytes_per_pixel_ = bytes_per_pixel(st.viewport.format);
    colours_ = d.region<Rgb8>(st.off_span);
    depth_ = d.region<std::uint32_t>(st.off_depth);
    colour_ = d.region<std::uint8_t>(st.off_colour);
    const bool counts = st.viewport.write_count;
    counts_ = counts ? d.region<std::uint8_t>(st.off_counts) : nullptr;
    // Without a depth buffer the depth test passes every pixel; the loops' depth stores go to one
    // row kept for them (Device::layout), the same row for every span.
    const bool depth_test = st.depth_test && st.viewport.depth_buffer;
    depth_row_stride_ = st.viewport.depth_buffer ? width_ : 0;
    state_ = DrawState{st.viewport.format == PixelFormat::kRgb565, depth_test, counts};
    // The method is the draw's: whether it takes early depth, and whether its colours are computed
    // in the pixel loop (not with the write counts: the linear loops leave them out), is decided
    // once.
    const MethodTraits traits = method_slot(st.method).traits;
    edges_ = traits.reads_edge_positions ? EdgeParameters::kWith : EdgeParameters::kWithout;
    early_depth_ = depth_test && traits.skips_hidden_pixels;
    linear_ = traits.colours_linear && !counts && !early_depth_;
    if constexpr (!kSizeBuild) choose_loops();
  }
  // Whether rasterize() steps the edges' parameters for the method's spans.
  EdgeParameters edge_parameters() const { return edges_; }
  // The next triangle, set up by method m.
  void begin(const Triangle& t, ShadingMethod& m) {
    tri_ = &t;
    method_ = &m;
    zplane_.setup(t, t.v[0].z, t.v[1].z, t.v[2].z);
    dz_ = zplane_.step_x();
  }
  // rasterize()'s target, called (and inlined) without a virtual call per span.
  void span(const Span& s) {
    ++spans_;
    const std::size_t row = static_cast<std::size_t>(s.y) * width_;
    std::uint32_t* const depth_row = depth_ + static_cast<std::size_t>(s.y) * depth_row_stride_;
    const Lambdas lam = lambdas_at(*tri_, 16 * std::int64_t{s.x0} + 8, 16 * std::int64_t{s.y} + 8);
    const std::int64_t z = zplane_.at(lam) << ScreenPlane::kStepFrac;
    if (linear_) {
      write_linear(row, depth_row, s, z, method_->linear_span(s));
      return;
    }
    if (!early_depth_) {
      method_->shade_span(s, colours_);
      write_run(row, depth_row, s.x0, s.x1, z, colours_);
      return;
    }
    Span visible = s;
    if (!visible_part(visible, z, depth_row)) {
      ++spans_hidden_;
      return;
    }
    method_->shade_span(visible, colours_);
    // The depth stepped from x0 to the first visible pixel, as the colours are: the same words as
    // without early depth.
    const std::int32_t skip = visible.first - visible.x0;
    write_run(row, depth_row, visible.first, visible.last, z + dz_ * skip, colours_ + skip);
  }
  void flush_counters() const {
    Counters& c = dev_.counters_;
    c.spans += spans_;
    c.spans_hidden += spans_hidden_;
    c.pixels_shaded += pixels_shaded_;
    c.pixels_written += pixels_written_;
  }

 private:
  // Speed builds: the loop instances for the draw's state.
  void choose_loops() {
    const int variant =
        (state_.rgb565 ? 4 : 0) | (state_.depth_test ? 2 : 0) | (state_.counts ? 1 : 0);
    write_exact_ = kLoops[1][variant];
    write_saturating_ = kLoops[0][variant];
    if (linear_) {
      write_linear_exact_ = kLinearLoops[1][variant >> 1];
      write_linear_saturating_ = kLinearLoops[0][variant >> 1];
      write_constant_ = kConstantLoops[variant >> 1];
    }
  }
  // Early depth: narrows s to [first, last), its first and last pixel that pass the depth test
  // (the same test as the pixel loop's: the span's pixels are distinct, so none of its writes
  // changes another's outcome); false if none does. Only the hidden ends are scanned, so a
  // visible span costs two tests.
  bool visible_part(Span& s, std::int64_t z0, const std::uint32_t* depth) const {
    constexpr int f = ScreenPlane::kStepFrac;
    std::int32_t first = s.x0;
    for (std::int64_t z = z0; !(depth_word(z >> f) < depth[first]); z += dz_)
      if (++first == s.x1) return false;
    std::int32_t last = s.x1 - 1;
    for (std::int64_t z = z0 + dz_ * (last - s.x0); !(depth_word(z >> f) < depth[last]); z -= dz_)
      --last;
    s.first = first;
    s.last = last + 1;
    return true;
  }
  // Depth-tests and writes pixels [first, last) of a row: colours from `colours`, the depth z at
  // `first` stepped per pixel, the row's depth words at depth_row.
  void write_run(std::size_t row, std::uint32_t* depth_row, std::int32_t first, std::int32_t last,
                 std::int64_t z, const Rgb8* colours) {
    const std::int32_t n = last - first;
    pixels_shaded_ += static_cast<std::uint64_t>(n);
    const Run run{colours,
                  depth_row,
                  colour_ + row * bytes_per_pixel_,
                  counts_ != nullptr ? counts_ + row : nullptr,
                  z,
                  dz_,
                  first,
                  last};
    if constexpr (kSizeBuild) {
      pixels_written_ += pixels(run, state_, BufferColours{colours});
      return;
    }
    // The depth is linear along the span: when both ends' depth words need no saturation, none
    // does.
    const bool exact_depth = depth_in_range(z >> ScreenPlane::kStepFrac) &&
                             depth_in_range((z + dz_ * (n - 1)) >> ScreenPlane::kStepFrac);
    pixels_written_ += exact_depth ? write_exact_(run) : write_saturating_(run);
  }
  // The same for a whole span whose colours the pixel loop computes.
  void write_linear(std::size_t row, std::uint32_t* depth_row, const Span& s, std::int64_t z,
                    const LinearColours& colours) {
    const std::int32_t n = s.x1 - s.x0;
    pixels_shaded_ += static_cast<std::uint64_t>(n);
    const LinearRun run{
        {nullptr, depth_row, colour_ + row * bytes_per_pixel_, nullptr, z, dz_, s.x0, s.x1},
        colours};
    if constexpr (kSizeBuild) {
      // One loop: a span of one colour steps by zero.
      pixels_written_ += pixels(run.run, state_, steps_of(colours));
      return;
    }
    const bool exact_depth = depth_in_range(z >> ScreenPlane::kStepFrac) &&
                             depth_in_range((z + dz_ * (n - 1)) >> ScreenPlane::kStepFrac);
    // Flat's spans, and Gouraud's where the colour does not change along x: the colour is
    // computed once (the common case only: exact depth).
    if (exact_depth && (colours.dc[0] | colours.dc[1] | colours.dc[2]) == 0) {
      pixels_written_ += write_constant_(run);
      return;
    }
    pixels_written_ += exact_depth ? write_linear_exact_(run) : write_linear_saturating_(run);
  }
  // One span's pixels: colours from the method, the depth plane stepped per pixel.
  struct Run {
    const Rgb8* colours;
    std::uint32_t* depth;
    std::uint8_t* colour_row;
    std::uint8_t* counts;
    std::int64_t z, dz;  // depth plane, ScreenPlane::kStepFrac more fraction bits
    std::int32_t x0, x1;
  };
  struct LinearRun {
    Run run;  // its `colours` unused
    LinearColours colours;
  };
  // Where the pixel loop takes each pixel's colour from, in turn: the method's span buffer, or
  // a linear span's start and steps.
  struct BufferColours {
    const Rgb8* p;
    Rgb8 next() { return *p++; }
  };
  struct ConstantColour {
    Rgb8 c;
    Rgb8 next() const { return c; }
  };
  struct LinearSteps {
    std::int64_t c[3], dc[3];
    Rgb8 next() {
      constexpr int s = LinearColours::kShift;
      const Rgb8 px{static_cast<std::uint8_t>(c[0] >> s), static_cast<std::uint8_t>(c[1] >> s),
                    static_cast<std::uint8_t>(c[2] >> s)};
      c[0] += dc[0];  // Gouraud: one addition per channel per pixel
      c[1] += dc[1];
      c[2] += dc[2];
      return px;
    }
  };
  static LinearSteps steps_of(const LinearColours& c) {
    return {{c.c[0], c.c[1], c.c[2]}, {c.dc[0], c.dc[1], c.dc[2]}};
  }
  // The draw's pixel format, depth test and write counts, and whether the span's depth words need
  // saturation: constants of each loop instance in speed builds, read per pixel by the loops of
  // size builds (firmware/build.hpp), which always saturate: the same words.
  template <bool kRgb565, bool kDepthTest, bool kCounts, bool kExactDepth>
  struct FixedState {
    static constexpr bool rgb565 = kRgb565, depth_test = kDepthTest, counts = kCounts,
                          exact_depth = kExactDepth;
  };
  struct DrawState {
    bool rgb565 = false, depth_test = false, counts = false;
    static constexpr bool exact_depth = false;
  };
  using Loop = std::uint64_t (*)(const Run&);
  // Depth-tests and writes the span; returns the pixels written. kExactDepth: every pixel's depth
  // word is inside (0, kDepthFar), so depth_word's saturation is left out.
  template <bool kRgb565, bool kDepthTest, bool kCounts, bool kExactDepth>
  static std::uint64_t write(const Run& r) {
    return pixels(r, FixedState<kRgb565, kDepthTest, kCounts, kExactDepth>{},
                  BufferColours{r.colours});
  }
  template <bool kRgb565, bool kDepthTest, bool kExactDepth>
  static std::uint64_t write_linear(const LinearRun& r) {
    return pixels(r.run, FixedState<kRgb565, kDepthTest, false, kExactDepth>{},
                  steps_of(r.colours));
  }
  template <bool kRgb565, bool kDepthTest>
  static std::uint64_t write_constant(const LinearRun& r) {
    constexpr int s = LinearColours::kShift;
    const LinearColours& c = r.colours;
    return pixels(r.run, FixedState<kRgb565, kDepthTest, false, true>{},
                  ConstantColour{Rgb8{static_cast<std::uint8_t>(c.c[0] >> s),
                                      static_cast<std::uint8_t>(c.c[1] >> s),
                                      static_cast<std::uint8_t>(c.c[2] >> s)}});
  }
  template <class State, class Colours>
  static std::uint64_t pixels(const Run& r, State state, Colours colours) {
    constexpr int f = ScreenPlane::kStepFrac;
    // Locals, not r's fields: the byte stores below may alias anything, and would make the
    // compiler reload every field at every pixel.
    std::uint32_t* const depth = r.depth;
    std::uint8_t* const colour_row = r.colour_row;
    std::uint8_t* const counts = r.counts;
    const std::int64_t dz = r.dz;
    const std::int32_t x1 = r.x1;
    std::uint64_t rejected = 0;  // by the depth test (counted there: the rarer case)
    std::int64_t z = r.z;
    for (std::int32_t x = r.x0; x < x1; ++x, z += dz) {
      const auto i = static_cast<std::size_t>(x);
      const Rgb8 px = colours.next();
      const std::uint32_t d =
          state.exact_depth ? depth_word_unsaturated(z >> f) : depth_word(z >> f);
      if (state.depth_test && !(d < depth[i])) {
        ++rejected;
        continue;
      }
      depth[i] = d;
      if (state.rgb565) {
        // RGB565 keeps the top bits of the rounded 8-bit levels (docs/CONVENTIONS.md).
        const auto v =
            static_cast<std::uint16_t>(((px.r >> 3) << 11) | ((px.g >> 2) << 5) | (px.b >> 3));
        colour_row[2 * i] = static_cast<std::uint8_t>(v & 0xffu);
        colour_row[2 * i + 1] = static_cast<std::uint8_t>(v >> 8);
      } else {
        colour_row[3 * i] = px.r;
        colour_row[3 * i + 1] = px.g;
        colour_row[3 * i + 2] = px.b;
      }
      if (state.counts) {
        if (counts[i] != 0xff) ++counts[i];
      }
    }
    return static_cast<std::uint64_t>(x1 - r.x0) - rejected;
  }
  // The pixel loops, [exact depth][RGB565 · 4 + depth test · 2 + write counts]: one for each
  // combination, so that the pixel loop branches on none of them.
  static constexpr Loop kLoops[2][8] = {
      {write<false, false, false, false>, write<false, false, true, false>,
       write<false, true, false, false>, write<false, true, true, false>,
       write<true, false, false, false>, write<true, false, true, false>,
       write<true, true, false, false>, write<true, true, true, false>},
      {write<false, false, false, true>, write<false, false, true, true>,
       write<false, true, false, true>, write<false, true, true, true>,
       write<true, false, false, true>, write<true, false, true, true>,
       write<true, true, false, true>, write<true, true, true, true>}};
  // The linear loops, [exact depth][RGB565 · 2 + depth test], without write counts.
  using LinearLoop = std::uint64_t (*)(const LinearRun&);
  static constexpr LinearLoop kLinearLoops[2][4] = {
      {write_linear<false, false, false>, write_linear<false, true, false>,
       write_linear<true, false, false>, write_linear<true, true, false>},
      {write_linear<false, false, true>, write_linear<false, true, true>,
       write_linear<true, false, true>, write_linear<true, true, true>}};
  // A linear span of one colour with exact depth, [RGB565 · 2 + depth test].
  static constexpr LinearLoop kConstantLoops[4] = {
      write_constant<false, false>, write_constant<false, true>, write_constant<true, false>,
      write_constant<true, true>};

  Device& dev_;
  const Triangle* tri_ = nullptr;
  ShadingMethod* method_ = nullptr;
  EdgeParameters edges_ = EdgeParameters::kWithout;  // the method's kReadsEdgePositions
  bool early_depth_ = false;  // depth test on and the method's kSkipsHiddenPixels
  ScreenPlane zplane_;
  std::int64_t dz_ = 0;
  std::size_t width_ = 0, bytes_per_pixel_ = 3;
  Rgb8* colours_ = nullptr;  // the method's span buffer
  std::uint32_t* depth_ = nullptr;
  std::size_t depth_row_stride_ = 0;  // the width, or 0 without a depth buffer (one row)
  std::uint8_t* colour_ = nullptr;
  std::uint8_t* counts_ = nullptr;  // null unless the write counts are on
  DrawState state_;                 // size builds' loops read it
  Loop write_exact_ = nullptr, write_saturating_ = nullptr;
  bool linear_ = false;  // the method's kColoursLinear, and no write counts
  LinearLoop write_linear_exact_ = nullptr, write_linear_saturating_ = nullptr;
  LinearLoop write_constant_ = nullptr;
  std::uint64_t spans_ = 0, spans_hidden_ = 0, pixels_shaded_ = 0, pixels_written_ = 0;
};

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
  // Capacities are bounded so that the sizes below cannot wrap a 32-bit size_t either.
  if (cap.max_vertices > (1u << 24) || cap.max_indices > (1u << 26)) return false;
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
  if (cmd.width == 0 || cmd.height == 0 || cmd.width > kMaxDimension || cmd.height > kMaxDimension)
    return fail(Error::kViewportTooLarge);
  if (cmd.format != PixelFormat::kRgb888 && cmd.format != PixelFormat::kRgb565)
    return fail(Error::kBadArgument);
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

Error Device::upload_vertices(std::uint32_t first, std::span<const Vertex> vertices) {
  const std::uint64_t end = std::uint64_t{first} + vertices.size();
  if (end > state_.capacity.max_vertices) return fail(Error::kIndexOutOfRange);
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
  if (end > state_.capacity.max_indices) return fail(Error::kIndexOutOfRange);
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

Error Device::draw(const DrawCmd& cmd) {
  if (!state_.viewport_set) return fail(Error::kNoViewport);
  if (cmd.count % 3 != 0) return fail(Error::kBadArgument);
  if (std::uint64_t{cmd.first} + cmd.count > state_.index_count)
    return fail(Error::kIndexOutOfRange);
  const std::uint32_t* idx = region<std::uint32_t>(state_.off_indices) + cmd.first;
  for (std::uint32_t i = 0; i < cmd.count; ++i)
    if (idx[i] >= state_.vertex_count) return fail(Error::kIndexOutOfRange);
  // Every position must transform before memory is touched (a failing draw changes nothing):
  // proven for all of them at once from the uploaded coordinates' bound where it can be, else
  // checked vertex by vertex.
  const Vertex* verts = region<Vertex>(state_.off_vertices);
  if (!transform_cannot_fail(state_.modelview, state_.projection, state_.coordinate_bound))
    for (std::uint32_t i = 0; i < state_.vertex_count; ++i) {
      ClipVertex tmp;
      if (!transform_position(state_.modelview, state_.projection, verts[i], tmp))
        return fail(Error::kOutOfRange);
    }
  // The vertex cache: every position, clip mask and (inside the view) projection now, each
  // normal when a triangle that is drawn first needs it (vertex_normal), each vertex's colour
  // when a method that lights vertices first needs it (Triangle::levels). A back face or a
  // clipped-away triangle costs no normal.
  CachedVertex* cache = region<CachedVertex>(state_.off_cache);
  VertexLevels* levels =
      state_.off_method > state_.off_levels ? region<VertexLevels>(state_.off_levels) : nullptr;
  const auto width = static_cast<std::int32_t>(state_.viewport.width);
  const auto height = static_cast<std::int32_t>(state_.viewport.height);
  for (std::uint32_t i = 0; i < state_.vertex_count; ++i) {
    cache_vertex(state_.modelview, state_.projection, verts[i], width, height, cache[i]);
    cache[i].v.normal.x = q1_30::from_raw(kNormalPending);
    if (levels != nullptr) levels[i].c[0] = -1;
  }
  if (method_slot(state_.method).traits.object_centre) set_object_centre(idx, cmd.count);
  PixelWriter writer(*this);
  for (std::uint32_t t = 0; t < cmd.count; t += 3) draw_triangle(idx + t, levels, writer);
  writer.flush_counters();
  return ok();
}

// The centre of the eye-space bounding box of the vertices that the draw's indices name (each
// coordinate (lo + hi) / 2 rounded toward -inf).
void Device::set_object_centre(const std::uint32_t* idx, std::uint32_t count) {
  const CachedVertex* cache = region<CachedVertex>(state_.off_cache);
  std::int32_t lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (std::uint32_t i = 0; i < count; ++i) {
    const Vec3q16& p = cache[idx[i]].v.eye;
    const std::int32_t c[3] = {p.x.raw(), p.y.raw(), p.z.raw()};
    for (int k = 0; k < 3; ++k) {
      lo[k] = i == 0 || c[k] < lo[k] ? c[k] : lo[k];
      hi[k] = i == 0 || c[k] > hi[k] ? c[k] : hi[k];
    }
  }
  const auto mid = [&](int k) {
    return q15_16::from_raw(static_cast<std::int32_t>((std::int64_t{lo[k]} + hi[k]) >> 1));
  };
  state_.shading.object_centre = Vec3q16{mid(0), mid(1), mid(2)};
}

const Vec3u& Device::vertex_normal(std::uint32_t id) {
  ClipVertex& v = region<CachedVertex>(state_.off_cache)[id].v;
  if (v.normal.x.raw() == kNormalPending)
    v.normal = transform_normal(state_.modelview, region<Vertex>(state_.off_vertices)[id]);
  return v.normal;
}

void Device::draw_triangle(const std::uint32_t id[3], VertexLevels* levels, PixelWriter& writer) {
  ++counters_.triangles_in;
  const CachedVertex* cache = region<CachedVertex>(state_.off_cache);
  const CachedVertex& a = cache[id[0]];
  const CachedVertex& b = cache[id[1]];
  const CachedVertex& c = cache[id[2]];
  if ((a.outside & b.outside & c.outside) != 0) {  // all three outside one plane
    ++counters_.triangles_rejected;
    return;
  }
  if ((a.outside | b.outside | c.outside) != 0) {
    draw_crossing_triangle(id, levels, writer);
    return;
  }
  // Inside every plane: the cached projections. Facing by the snapped screen area, front =
  // clockwise on screen (y down) = negative edge function here.
  const std::int64_t area2 = (std::int64_t{b.sx} - a.sx) * (std::int64_t{c.sy} - a.sy) -
                             (std::int64_t{b.sy} - a.sy) * (std::int64_t{c.sx} - a.sx);
  if (area2 == 0) {
    ++counters_.triangles_degenerate;
    return;
  }
  const bool front = area2 < 0;
  if (!front && state_.cull_back_faces) {
    ++counters_.triangles_culled;
    return;
  }
  draw_fan_triangle(shade_vertex(id[0]), shade_vertex(id[1]), shade_vertex(id[2]), front, levels,
                    writer);
}

ShadeVertex Device::shade_vertex(std::uint32_t id) {
  const CachedVertex& c = region<CachedVertex>(state_.off_cache)[id];
  ShadeVertex s;
  s.eye = c.v.eye;
  s.normal = vertex_normal(id);
  s.sx = c.sx;
  s.sy = c.sy;
  s.z = c.z;
  s.w = q15_16::from_raw(c.v.clip[3]);
  s.id = static_cast<std::int32_t>(id);  // < 2^24 (layout's capacity bound)
  return s;
}

void Device::draw_crossing_triangle(const std::uint32_t id[3], VertexLevels* levels,
                                    PixelWriter& writer) {
  const CachedVertex* cache = region<CachedVertex>(state_.off_cache);
  ClipVertex tri[3] = {cache[id[0]].v, cache[id[1]].v, cache[id[2]].v};
  // Clipping interpolates the normals: the three are needed before it.
  for (int i = 0; i < 3; ++i) tri[i].normal = vertex_normal(id[i]);
  ClipVertex poly[kMaxClipVertices];
  const int count = clip_crossing(tri, poly);
  if (count == 0) {
    ++counters_.triangles_rejected;
    return;
  }
  ++counters_.triangles_clipped;
  // Facing by the exact sign of the homogeneous determinant: the snapped pieces of a zero-area or
  // sliver triangle could otherwise come out with either orientation. det[x y w] > 0 is
  // counter-clockwise in NDC (y up), i.e. clockwise on screen: front.
  const int o = homogeneous_orientation(tri);
  if (o == 0) {
    ++counters_.triangles_degenerate;
    return;
  }
  const bool front = o > 0;
  if (!front && state_.cull_back_faces) {
    ++counters_.triangles_culled;
    return;
  }
  const auto w = static_cast<std::int32_t>(state_.viewport.width);
  const auto h = static_cast<std::int32_t>(state_.viewport.height);
  ShadeVertex sv[kMaxClipVertices];
  for (int i = 0; i < count; ++i) sv[i] = project(poly[i], w, h);
  for (int i = 1; i + 1 < count; ++i)
    draw_fan_triangle(sv[0], sv[i], sv[i + 1], front, levels, writer);
}

void Device::draw_fan_triangle(const ShadeVertex& a, const ShadeVertex& b, const ShadeVertex& c,
                               bool front, VertexLevels* levels, PixelWriter& writer) {
  const std::int64_t area2 = edge_function(a, b, c.sx, c.sy);
  // A fan piece whose orientation disagrees with the polygon's is a snapping artefact.
  if (area2 == 0 || (area2 < 0) != front) {
    ++counters_.triangles_degenerate;
    return;
  }
  // The rasterizer and the methods work with area2 > 0: order the vertices accordingly.
  Triangle t;
  t.front_facing = front;
  t.v[0] = a;
  t.v[1] = area2 > 0 ? b : c;
  t.v[2] = area2 > 0 ? c : b;
  t.area2 = area2 > 0 ? area2 : -area2;
  t.levels = levels;
  ShadingMethod& m = method();
  if (!m.setup(t, state_.shading)) {
    ++counters_.triangles_skipped;
    return;
  }
  ++counters_.triangles_drawn;
  writer.begin(t, m);
  (void)rasterize(t, static_cast<std::int32_t>(state_.viewport.width),
                  static_cast<std::int32_t>(state_.viewport.height), writer,
                  writer.edge_parameters());
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
