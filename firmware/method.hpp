// The per-method interface (docs/CONVENTIONS.md, "Methods"): every shading method is one class
// behind this.
//
// The pipeline is setup -> traversal -> shading, kept apart:
//   1. geometry (geometry.cpp) transforms, clips and projects; each triangle that reaches the
//      rasterizer is handed to the method's setup() with its three ShadeVertex records;
//   2. the rasterizer (raster.hpp) walks the edges in y and cuts spans in x (top-left rule);
//   3. for each span the method's shade_span() writes one colour per pixel of [x0, x1).
// Depth test and framebuffer writes are the pipeline's, after shade_span. Early depth: with the
// depth test on, the pipeline first finds the span's visible pixels; a method that declares
// kSkipsHiddenPixels is asked for [first, last) only, and not called at all for a span with
// no visible pixel (docs/CONVENTIONS.md, "Early depth").
//
// Spans carry where their ends lie on the triangle's edges (which edge, parameter along it),
// so that a method may interpolate its own quantities along the edges in y and then along the
// span in x (Gouraud's colours, Kuijk-Blake's slerped vectors), or ignore them and use screen
// positions (Bishop-Weimer's polynomial in x, y) or barycentrics (Brown) from TriangleSetup.
#pragma once

#include <cstdint>

#include "firmware/build.hpp"
#include "firmware/counters.hpp"
#include "firmware/types.hpp"

namespace tp::fw {

// One transformed vertex, as every method sees it.
struct ShadeVertex {
  Vec3q16 eye;          // eye-space position
  Vec3u normal;         // eye-space unit normal
  std::int32_t sx = 0;  // screen x in 1/16 pixel (pixel i's centre is 16 i + 8)
  std::int32_t sy = 0;  // screen y in 1/16 pixel, row 0 at the top
  std::int64_t z = 0;   // NDC z = z_clip / w, 30 fraction bits, clamped to [-2, 2]
  q15_16 w;             // clip w (> 0 after clipping)
  // The vertex's index in the draw's vertex buffer, for the per-vertex caches; -1 for a vertex
  // that clipping made (it belongs to no other triangle).
  std::int32_t id = -1;
};

// A vertex's lit colour, cached for the draw by the methods that light vertices (Gouraud): each
// channel's Blinn-Phong radiance clamped to [0, 1] in Q.30; c[0] < 0 while not yet lit.
struct VertexLevels {
  std::int32_t c[3];
};

// A triangle ready for rasterization: area2 > 0 (vertex order fixed up by the pipeline, so the
// edge functions below are >= 0 inside), plus the exact edge functions in subpixel units.
struct Triangle {
  ShadeVertex v[3];
  std::int64_t area2 = 0;  // twice the signed screen area in (1/16 pixel)^2, > 0
  bool front_facing = true;
  // The draw's lit-vertex cache, indexed by ShadeVertex::id, for the methods whose
  // kLightsVertices is true (device.cpp gives them a region; null for the others).
  VertexLevels* levels = nullptr;
};

// Edge function of the directed edge a->b at subpixel point (px, py): exact, and for a triangle
// with area2 > 0 it is the barycentric weight of the opposite vertex times area2.
TP_SIZE_OUTLINE constexpr std::int64_t edge_function(const ShadeVertex& a, const ShadeVertex& b,
                                                     std::int64_t px, std::int64_t py) {
  return (std::int64_t{b.sx} - a.sx) * (py - a.sy) - (std::int64_t{b.sy} - a.sy) * (px - a.sx);
}

// Where one end of a span lies: on the edge from vertex `from` to vertex `to` (from above to),
// at parameter t in [0, 1] (Q1.30) measured from `from`, at the row's centre line. t costs a
// division per end and row: the rasterizer fills it only for the methods that read it
// (kReadsEdgePositions); for the others it stays 0.
struct EdgePos {
  std::uint8_t from = 0, to = 0;
  q1_30 t;
};

struct Span {
  std::int32_t y = 0;           // pixel row
  std::int32_t x0 = 0, x1 = 0;  // pixels [x0, x1), x1 > x0, already inside the viewport
  EdgePos left, right;          // the span's ends on the triangle's edges (before the scissor)
  // The pixels the pipeline needs, x0 <= first < last <= x1: those outside fail the depth test.
  // The rasterizer sets [x0, x1); early depth narrows it for the methods that declare
  // kSkipsHiddenPixels, which then need fill only out[first − x0 .. last − x0).
  std::int32_t first = 0, last = 0;
};

// What a method may read besides the triangle: material, lights, eye, and the counters.
struct LightState {
  LightType type = LightType::kOff;
  q15_16 color[3];
  Vec3u direction;
  Vec3q16 position;
};
struct ShadeContext {
  MaterialCmd material;
  LightState lights[kMaxLights];
  EyeMode eye = EyeMode::kInfinite;
  // The error budget of the methods that choose their evaluation under one (kb-adaptive): every
  // pixel within this many output levels of their exact evaluation; 1 to kMaxBudgetLevels.
  std::uint32_t budget_levels = 1;
  Counters* counters = nullptr;
  // Raised by every successful set_material, set_light and set_eye: a method that caches values
  // of the shading state across triangles and draws compares this, not the state's bytes
  // (64 bits: it does not wrap).
  std::uint64_t revision = 0;
  // The centre of the current draw's bounding box in eye space, set by the draw for the methods
  // that ask for it (MethodSlot::object_centre: envmap, whose map holds a point light as the
  // direction to it from there); not kept up to date for the others.
  Vec3q16 object_centre;
};

// A span whose colours are linear in x, for the pipeline to compute in its write loop: pixel k of
// the span (from Span::x0) has channel ch's level c[ch] + k dc[ch] >> kShift, inside [0, 255]
// at every pixel (the method's promise).
struct LinearColours {
  static constexpr int kShift = 46;
  std::int64_t c[3], dc[3];
};

// What a method class declares of itself, as static constants the registry reads at compile time
// (firmware/registry.hpp, MethodTraits; constants, not virtual functions: no vtable entry and no
// call per triangle). Each is false where the class does not declare it:
//   kReadsEdgePositions  shade_span reads Span::left.t and right.t (see EdgePos).
//   kSkipsHiddenPixels   shade_span shades only Span [first, last), each pixel exactly as it would
//                        in the whole span (state stepped from x0 is advanced, not restarted), and
//                        keeps nothing from one span for the next — so that early depth may narrow
//                        a span and leave out one whose pixels are all hidden without changing any
//                        pixel — and its pixels cost more than the depth tests that find the
//                        visible ones (two per span). Flat and Gouraud do not: Gouraud with early
//                        depth cost 180 instead of 169 instructions per pixel on the teapot
//                        (docs/DECISIONS.md, "Early depth"). The methods that set up state across
//                        spans (kb's y-coherent chunks) get every span whole too.
//   kColoursLinear       every span's colours are linear in x (flat's constant, Gouraud's one
//                        addition per channel per pixel): the pipeline asks linear_span() for them
//                        instead of shade_span(), and computes them in its own pixel loop, with no
//                        span buffer between.
//   kLightsVertices      the method gets the draw's lit-vertex cache (Triangle::levels).
//   kNeedsObjectCentre   the draw sets ShadeContext::object_centre for it.
class ShadingMethod {
 public:
  // Per-triangle setup. Returns false to skip the triangle (counted as triangles_skipped).
  virtual bool setup(const Triangle& tri, const ShadeContext& ctx) = 0;
  // Colours of pixels [s.x0, s.x1) of row s.y, into out[0 .. x1 - x0); for a method that
  // declares kSkipsHiddenPixels, of [s.first, s.last) only (the other entries are not read).
  virtual void shade_span(const Span& s, Rgb8* out) = 0;
  // For a method whose class declares kColoursLinear (above): the span's colours. The default,
  // for the others, is never called (device.cpp).
  virtual LinearColours linear_span(const Span& s);

 protected:
  ~ShadingMethod() = default;
};

}  // namespace tp::fw
