// The shading methods implemented so far (docs/CONVENTIONS.md, "Methods"), one unit each. Each
// states what it handles exactly: all three take point lights, a finite eye and up to kMaxLights
// lights with the exact Blinn-Phong formula; they differ in where the formula is evaluated.
#pragma once

#include "firmware/interp.hpp"
#include "firmware/lighting.hpp"
#include "firmware/method.hpp"
#include "firmware/point_shader.hpp"

namespace tp::fw {

// 1. Flat (shade_flat.cpp): one evaluation per triangle, at the eye-space centroid with the
//    renormalised mean of the vertex normals; every pixel gets that colour.
class FlatMethod final : public ShadingMethod {
 public:
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
  void shade_span(const Span& s, Rgb8* out) override;
  bool colours_linear() const override { return true; }
  LinearColours linear_span(const Span& s) override;

 private:
  Rgb8 colour_{0, 0, 0};
};

// 2. Gouraud (shade_gouraud.cpp): lighting at the three vertices, clamped to [0, 1], then
//    interpolated linearly in SCREEN space (the 1980s assumption, not perspective-correct):
//    one addition per channel per row and per pixel.
class GouraudMethod final : public ShadingMethod {
 public:
  // Lights each vertex once per draw, through the triangle's VertexLevels cache.
  static constexpr bool kLightsVertices = true;
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
  void shade_span(const Span& s, Rgb8* out) override;
  bool colours_linear() const override { return true; }
  LinearColours linear_span(const Span& s) override;

 private:
  const Triangle* tri_ = nullptr;
  ScreenPlane plane_[3];
  // The colours at the previous span's start, stepped to the next span's: exact (at()) for the
  // triangle's first span, then per row and per pixel in x by the planes' steps, as along a span.
  std::int64_t start_[3] = {0, 0, 0};  // ScreenPlane::kStepFrac more fraction bits
  std::int64_t step_x_[3] = {0, 0, 0}, step_y_[3] = {0, 0, 0};
  std::int32_t x_ = 0, y_ = 0;  // the previous span's start
  bool stepping_ = false;       // start_ holds the previous span's start
  bool steps_exact_ = false;    // no step saturated: row steps allowed
};

// 3. Phong, exact (shade_phong.cpp): Blinn-Phong at every pixel, at the perspective-correct
//    point (normal and eye-space position interpolated with hyperbolic barycentrics, like the
//    double reference), the normal renormalised, L, the eye direction and H exact there, the
//    power by repeated squaring: PointShader (point_shader.hpp), with one reciprocal root per
//    direction instead of a normalised vector, and along a row by exact integer steps.
class PhongMethod final : public ShadingMethod {
 public:
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
  void shade_span(const Span& s, Rgb8* out) override;
  bool skips_hidden_pixels() const override { return true; }

 private:
  PointShader point_;
  Counters* counters_ = nullptr;
};

}  // namespace tp::fw
