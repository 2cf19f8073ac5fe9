// Vertex transform, homogeneous clipping and projection (docs/CONVENTIONS.md).
//
// Formats: matrices, positions, eye and clip coordinates are Q15.16 (int32); normals q1_30.
// Input bound (checked by the device): matrix entries and vertex coordinates below 2^14 in
// magnitude, so each raw product is below 2^60 and a four-term sum below 2^62. Transformed
// eye and clip coordinates that do not fit Q15.16 make transform_vertex fail (a draw that names
// the vertex is refused before any pixel is written).
#pragma once

#include <cstdint>

#include "firmware/method.hpp"
#include "firmware/types.hpp"

namespace tp::fw {

// A transformed vertex before projection (the per-draw vertex cache holds these).
struct ClipVertex {
  std::int32_t clip[4] = {0, 0, 0, 0};  // Q15.16 raw: x, y, z, w
  Vec3q16 eye;
  Vec3u normal;  // unit, eye space
};

// MV * position and P * (MV * position); the normal by MV's upper 3x3, renormalised
// (rigid motion + uniform scale assumed). False if a result does not fit Q15.16.
bool transform_vertex(const Mat4& mv, const Mat4& proj, const Vertex& in, ClipVertex& out);
// The position part alone (clip and eye; the normal untouched): whether transform_vertex
// succeeds. The draw transforms every position and only the normals that a drawn triangle uses.
bool transform_position(const Mat4& mv, const Mat4& proj, const Vertex& in, ClipVertex& out);
// The normal part: MV's upper 3x3 times the normal, renormalised.
Vec3u transform_normal(const Mat4& mv, const Vertex& in);
// True when transform_position succeeds for every vertex whose coordinates are at most
// coordinate_bound in magnitude (raw Q15.16): a bound through the matrices' absolute rows, so
// that a draw need not transform every position twice to be refused before it writes anything.
// False says nothing (the draw then checks vertex by vertex).
bool transform_cannot_fail(const Mat4& mv, const Mat4& proj, std::uint32_t coordinate_bound);

// Clip planes, in homogeneous space (before the divide): the near plane z >= -w, w >= 2^-12,
// and a guard band |x| <= 64 w, |y| <= 64 w that bounds screen coordinates (raster.hpp) without
// touching anything inside the viewport.
inline constexpr int kClipPlanes = 6;
inline constexpr int kMaxClipVertices = 3 + kClipPlanes;
inline constexpr std::int32_t kGuardBand = 64;

struct ClipResult {
  int count = 0;         // vertices of the clipped convex polygon (0: rejected)
  bool clipped = false;  // some plane cut the triangle
};
// Bit p set when v lies outside clip plane p. A triangle is rejected when its three vertices'
// masks share a bit (all outside one plane), and inside when their union is empty.
std::uint32_t outside_planes(const ClipVertex& v);
// Where a triangle lies against the clip planes: all three vertices inside every plane, all
// three outside one plane (rejected), or crossing (clipped by clip_crossing).
enum class ClipClass { kInside, kOutside, kCrossing };
ClipClass classify(const ClipVertex in[3]);
// The polygon of a crossing triangle (0 vertices when nothing is left of it).
int clip_crossing(const ClipVertex in[3], ClipVertex out[kMaxClipVertices]);
// Sutherland-Hodgman. An edge is always cut from its inside endpoint towards its outside one,
// so two triangles sharing an edge produce bit-identical new vertices (no cracks).
ClipResult clip_triangle(const ClipVertex in[3], ClipVertex out[kMaxClipVertices]);

// Exact sign of det[x y w] of the three clip-space vertices (-1, 0, 1): the orientation of
// the triangle's projection, valid whatever the signs of w (the volume of the tetrahedron
// eye-triangle). Used for triangles that need clipping, whose snapped pieces cannot decide
// facing or zero area reliably.
int homogeneous_orientation(const ClipVertex v[3]);

// Divide by w and map to the viewport, snapping to 1/16 pixel (round to nearest, ties away
// from zero): sx = (x/w + 1) / 2 * 16 W, sy = (1 - y/w) / 2 * 16 H.
ShadeVertex project(const ClipVertex& v, std::int32_t width, std::int32_t height);

// One vertex of a draw's vertex cache: transformed, its clip-plane mask, and, when it is inside
// every plane, projected (ShadeVertex's sx, sy and z, as project() gives them): a vertex shared
// by six triangles is projected once, and a triangle inside the view is classified from three
// masks. Vertices outside a plane are projected by the triangles that clip them.
struct CachedVertex {
  ClipVertex v;
  std::uint32_t outside = 0;  // outside_planes(v)
  std::int32_t sx = 0, sy = 0;
  std::int64_t z = 0;
};
// Transforms and, if it is inside every plane, projects one vertex (its normal left untouched).
void cache_vertex(const Mat4& mv, const Mat4& proj, const Vertex& in, std::int32_t width,
                  std::int32_t height, CachedVertex& out);

}  // namespace tp::fw
