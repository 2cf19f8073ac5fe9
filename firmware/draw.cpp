// The draw pipeline: transform -> clip -> project -> cull -> rasterize -> shade -> depth test ->
// write. Device::draw and its triangles, and the PixelWriter their spans go through. The
// commands that set up what a draw reads are in device.cpp.
#include <cstdint>
#include <limits>

#include "firmware/build.hpp"
#include "firmware/device.hpp"
#include "firmware/raster.hpp"
#include "firmware/registry.hpp"

namespace tp::fw {
namespace {
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
    const MethodTraits traits = Device::method_traits(st.method);
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
Error Device::draw(const DrawCmd& cmd) {
  if (!state_.viewport_set) return fail(Error::kNoViewport);
  if (cmd.count % 3 != 0) return fail(Error::kBadArgument);
  if (std::uint64_t{cmd.first} + cmd.count > state_.index_count)
    return fail(Error::kIndexOutOfRange);
  const std::uint32_t* idx = region<std::uint32_t>(state_.off_indices) + cmd.first;
  for (std::uint32_t i = 0; i < cmd.count; ++i)
    if (idx[i] >= state_.vertex_count) return fail(Error::kIndexOutOfRange);
  // Every position the draw's indices name must transform before memory is touched (a failing
  // draw changes nothing): proven for all uploaded vertices at once from their coordinates' bound
  // where it can be, else checked index by index. Vertices the draw does not name are not its
  // concern: the driver keeps every mesh in one buffer, each drawn with its own model-view, and a
  // mesh far out refused the draw of a mesh near the origin (found by review, 2026-12-08). The
  // cache below transforms those too; what a failed transform leaves there is int32 values that
  // the clip test and projection take safely, and that no triangle of this draw reads.
  const Vertex* verts = region<Vertex>(state_.off_vertices);
  if (!transform_cannot_fail(state_.modelview, state_.projection, state_.coordinate_bound))
    for (std::uint32_t i = 0; i < cmd.count; ++i) {
      ClipVertex tmp;
      if (!transform_position(state_.modelview, state_.projection, verts[idx[i]], tmp))
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
  if (method_traits(state_.method).object_centre) set_object_centre(idx, cmd.count);
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

}  // namespace tp::fw
