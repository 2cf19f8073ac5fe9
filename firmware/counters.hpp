// Performance counters, like a GPU's hardware counters. Reset by clear(), read by
// the host at any time. Geometry and raster counters are filled by the pipeline; the work
// counters are filled by the methods that define them (a method that does not use one leaves
// it at zero).
#pragma once

#include <cstdint>

namespace tp::fw {

struct Counters {
  // Geometry.
  std::uint64_t triangles_in = 0;          // triangles submitted by draw
  std::uint64_t triangles_culled = 0;      // removed by back-face culling
  std::uint64_t triangles_clipped = 0;     // touched by a clip plane (near plane or guard band)
  std::uint64_t triangles_rejected = 0;    // entirely outside a clip plane
  std::uint64_t triangles_degenerate = 0;  // zero area after snapping to 1/16 pixel
  std::uint64_t triangles_drawn = 0;       // rasterized (after clipping: one per fan triangle)
  std::uint64_t triangles_skipped = 0;     // a method's setup returned "skip"
  // Raster.
  std::uint64_t spans = 0;           // non-empty spans rasterized
  std::uint64_t spans_hidden = 0;    // of those, left out by early depth: no pixel visible
  std::uint64_t pixels_shaded = 0;   // pixels a method was asked for (early depth: visible part)
  std::uint64_t pixels_written = 0;  // pixels that passed the depth test
  // Per-method work. Every method counts these by the same definitions (tests/conformance):
  //   lighting_evaluations  points at which the exact Blinn-Phong sum over all lights was
  //                         evaluated — a vertex, a centroid, a sample, a pixel — one per point
  //                         whatever the number of lights;
  //   specular_evaluations  (point or pixel, light) pairs for which a specular factor — the exact
  //                         power or a method's stand-in for it (Kuijk-Blake's f, a table, a
  //                         polynomial) — was evaluated: per light, so it grows with the lights.
  //                         A light left out by a per-triangle or per-span test is not counted
  //                         (lights_skipped_*); pixels coloured from a fit of the summed colour
  //                         (Gouraud's interpolation, kb-adaptive's planes and quadratics) count
  //                         none;
  //   normalizations        unit vectors formed by a reciprocal root in a per-point evaluation
  //                         (blinn_phong: a point light's L, a finite eye's V, each H) or per
  //                         triangle (flat's mean normal); the per-pixel evaluation that takes
  //                         roots of dot products without forming unit vectors (PointShader)
  //                         counts none.
  std::uint64_t lighting_evaluations = 0;
  std::uint64_t specular_evaluations = 0;
  std::uint64_t normalizations = 0;
  std::uint64_t lights_skipped_triangle = 0;
  std::uint64_t lights_skipped_span = 0;
  std::uint64_t segments = 0;  // span segments (summed sections, Kuijk-Blake)
  // kb-adaptive: triangles per path (kb_adaptive.hpp), sub-triangles, exact lattice samples.
  std::uint64_t adaptive_constant = 0;       // one colour within the budget
  std::uint64_t adaptive_linear = 0;         // a plane per channel within the budget
  std::uint64_t adaptive_quadratic = 0;      // one quadratic per channel, all lights summed
  std::uint64_t adaptive_subdivided = 0;     // cut into 4^k sub-triangles with exact samples
  std::uint64_t adaptive_exact = 0;          // small and over budget: exact at every pixel
  std::uint64_t subtriangles = 0;            // sub-triangles of the subdivided triangles
  std::uint64_t subtriangles_exact = 0;      // of those, evaluated per pixel (over budget at 4^4)
  std::uint64_t subtriangles_unchecked = 0;  // of those, deepest cells taken without a check
  std::uint64_t terminator_cells = 0;        // cells (or triangles) clamping N·L per pixel
  std::uint64_t lattice_samples = 0;  // exact Blinn-Phong samples (vertices, midpoints, checks)
  // Overflow guards that fired: intermediate values clamped at the limit of their format where
  // the firmware does not prove that they fit (docs/STABILITY.md lists every site, counted or
  // proven). Not counted: the output colour's clamp to [0, 1] (over-exposure is the specified
  // result) and depth beyond the far plane (the far clip). Zero on every paper scene (tested).
  // A method counts at setup or span level, never per pixel: `++ctx.counters->saturations`.
  std::uint64_t saturations = 0;
  std::uint64_t frames = 0;  // end_frame calls since construction (not reset)
};

}  // namespace tp::fw
