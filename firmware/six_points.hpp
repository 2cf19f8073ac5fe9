// The six points of a quadratic triangle — its vertices and its edge midpoints — where Brown's
// Bézier triangle takes its cosines and Vlasic's quadratic shading and subdivided Gouraud their
// colours: the same points, normals and lit colours for all three, from one place.
#pragma once

#include "firmware/lighting.hpp"
#include "firmware/method.hpp"

namespace tp::fw {

// Points 0, 1, 2 are the vertices; 3, 4, 5 the midpoints of edges 0-1, 1-2 and 2-0.
inline constexpr int kSixEdge[3][2] = {{0, 1}, {1, 2}, {2, 0}};

// Vlasic's eq. 4.2 takes its six samples round the triangle from vertex 0: r0 vertex 0, r1 the
// midpoint of 0-1, r2 vertex 1, r3 the midpoint of 1-2, r4 vertex 2, r5 the midpoint of 2-0.
// Sample k of eq. 4.2 is point kEq42Order[k] here.
inline constexpr int kEq42Order[6] = {0, 3, 1, 4, 2, 5};

struct SixPoints {
  Vec3u normal[6];   // the vertices' normals; at a midpoint, the renormalised sum of its edge's
  Vec3q16 point[6];  // eye-space positions; a midpoint's rounded toward −inf
};
// Forms three unit normals (the caller counts them as normalizations).
SixPoints six_points(const Triangle& tri);

// A point's Blinn-Phong colour, each channel clamped to [0, 1] in Q.30.
VertexLevels lit_levels(const ShadeContext& ctx, const Vec3q16& point, const Vec3u& normal);
// Vertex i's, through the draw's lit-vertex cache (Triangle::levels) where the method has one:
// lit once per draw for a vertex of the vertex buffer, every time for one that clipping made.
VertexLevels vertex_levels(const Triangle& tri, int i, const ShadeContext& ctx);
// The six points' colours: the vertices' through the cache, the midpoints' lit here (three
// lighting evaluations and three normalizations per triangle, counted).
void six_levels(const Triangle& tri, const ShadeContext& ctx, VertexLevels out[6]);

}  // namespace tp::fw
