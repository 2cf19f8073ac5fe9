// The double-precision reference renderer (docs/CONVENTIONS.md, "Shared contract"): same camera,
// clipping, snapping and coverage as the device (docs/CONVENTIONS.md), exact per-pixel Blinn-Phong.
//
// Two interpolation schemes for the normal:
//  - Phong: N, and the eye-space position P, interpolated perspective-correctly (hyperbolic
//    barycentrics from the snapped screen vertices), N renormalised per pixel; true per-pixel
//    L = normalize(light − P) and V = normalize(−P) (V = (0, 0, 1) for an orthographic eye).
//  - Angular: N by slerp, the way the Kuijk-Blake device interpolates directions
//  (docs/KUIJK-BLAKE.md).
//    Precisely: for the pixel centre (x, y), take the scanline through y; where it crosses the
//    triangle's edges, N_edge = slerp(N_a, N_b, t) with t = (y − y_a)/(y_b − y_a) the
//    screen-linear fraction along the edge (a, b its snapped screen vertices); of the crossings
//    take the leftmost (x_l, N_l) and the rightmost (x_r, N_r); then
//    N = slerp(N_l, N_r, (x − x_l)/(x_r − x_l)) (0 when x_r = x_l). Screen-linear, not
//    perspective-correct, as the 1980s methods assume. P, L and V are as in Phong, so only
//    the normal interpolation differs between the two references.
// All barycentrics come from the SNAPPED screen vertices (as on the device), so attributes are
// those of the snapped triangle: a vertex moved by snapping (at most 1/32 pixel) shifts P and N
// a little against an exact unprojection of the pixel centre.
// Vertices created by near-plane clipping get the linear blend of the two endpoint normals,
// renormalised, for Angular (for Phong the blend is kept unnormalised, which is exactly the
// original triangle's interpolation).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "host/image.hpp"
#include "host/meshes.hpp"
#include "host/scene.hpp"

namespace tp::host {

enum class Interpolation { Phong, Angular };

struct DrawMesh {
  const Mesh* mesh = nullptr;
  glm::dmat4 model_view{1.0};  // model -> eye; normals by its upper 3x3, renormalised
};

struct FrameSetup {
  int width = 512, height = 512;
  glm::dmat4 projection{1.0};
  bool eye_at_infinity = true;  // orthographic: V = (0, 0, 1)
  std::vector<EyeLight> lights;
  Material material;
  bool cull_backfaces = true;
  glm::dvec3 background{0, 0, 0};
};

struct ReferenceImage {
  FloatImage linear;                    // unclamped intensities
  FloatImage clamped;                   // clamped to [0, 1]
  Image8 rgb8;                          // round(255 · clamped)
  Mask mask;                            // 1 where some triangle wrote the pixel
  std::vector<double> depth;            // NDC z of the written pixel (1 = cleared)
  std::vector<std::uint16_t> coverage;  // how many triangles covered the pixel centre
};

// Frame setup of a scene (resolution overridable with width/height > 0) and its meshes.
FrameSetup frame_setup(const Scene& scene, int width = 0, int height = 0);
std::vector<DrawMesh> draw_list(const Scene& scene);

ReferenceImage render_reference(const FrameSetup& frame, const std::vector<DrawMesh>& meshes,
                                Interpolation interp = Interpolation::Phong);
ReferenceImage render_reference(const Scene& scene, Interpolation interp = Interpolation::Phong,
                                int width = 0, int height = 0);

// Blinn-Phong at one eye-space point with unit normal N (docs/CONVENTIONS.md, "Shared contract"):
// I_c = ka·O_c + Σ Il_c·[kd·O_c·max(0, N·L) + ks·max(0, N·H)^n], unclamped.
glm::dvec3 blinn_phong(const glm::dvec3& n, const glm::dvec3& p, const FrameSetup& frame);

// Screen coordinate snapped to 1/16 pixel, round to nearest, ties away from zero; in 1/16 units.
std::int64_t snap16(double screen_coordinate);

// Great-circle interpolation of unit vectors; falls back to normalised lerp when they are
// (anti)parallel to within 1e-9.
glm::dvec3 slerp(const glm::dvec3& a, const glm::dvec3& b, double t);

}  // namespace tp::host
