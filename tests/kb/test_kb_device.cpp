// The Kuijk-Blake methods end to end through the device (host/device_renderer): skipping
// changes nothing, and the accuracy against the double Phong and angular references on every
// paper scene stays within the measured bounds (docs/KUIJK-BLAKE.md).
//
// Origin of the numbers: this test prints every measured value (`kb_device_test` with
// --gtest_filter as below); they were pinned on 2026-11-22 with margins: colour correctness
// −0.0005, mean |error| ×1.05 + 0.05 levels, max |error| +2 levels. The device is integer-only
// and deterministic, so the values reproduce exactly; the margins absorb deliberate changes.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>

#include "bench/kb_replay.hpp"
#include "host/device_renderer.hpp"
#include "host/metrics.hpp"
#include "host/scene.hpp"
#include "tests/kb/scene_frames.hpp"

namespace tp::host {
namespace {

using kbtest::counter;
using kbtest::render;
using kbtest::scene_named;

// --- Skipping: bit-identical images, on every paper scene with 1, 2, 4 and 8 lights ---------

class KbSkipping : public ::testing::TestWithParam<const char*> {};

TEST_P(KbSkipping, ImageIdenticalWithSkippingOff) {
  const Scene scene = scene_named(GetParam());
  DeviceRenderer device(scene.width, scene.height);
  const DeviceFrame on = render(device, scene, "kb");
  const DeviceFrame off = render(device, scene, "kb-noskip");
  ASSERT_EQ(on.rgb.size(), off.rgb.size());
  EXPECT_TRUE(on.rgb == off.rgb);
  EXPECT_TRUE(on.covered == off.covered);
  const std::uint64_t tri = counter(on, "lights_skipped_triangle");
  const std::uint64_t span = counter(on, "lights_skipped_span");
  const std::uint64_t evaluated_on = counter(on, "specular_evaluations");
  const std::uint64_t evaluated_off = counter(off, "specular_evaluations");
  std::printf(
      "%s: terms skipped per triangle %llu, per span %llu; specular evaluations %llu of %llu\n",
      GetParam(), static_cast<unsigned long long>(tri), static_cast<unsigned long long>(span),
      static_cast<unsigned long long>(evaluated_on),
      static_cast<unsigned long long>(evaluated_off));
  // The skip-free variant counts nothing as skipped; the skipping one must skip something on
  // every paper scene (a specular lobe with n = 20 never covers a whole sphere).
  EXPECT_EQ(counter(off, "lights_skipped_triangle") + counter(off, "lights_skipped_span"), 0u);
  EXPECT_GT(tri + span, 0u);
  EXPECT_LE(evaluated_on, evaluated_off);
}

INSTANTIATE_TEST_SUITE_P(PaperScenes, KbSkipping, ::testing::ValuesIn(kbtest::kPaperScenes),
                         [](const auto& info) { return kbtest::test_name_of(info.param); });

// --- Accuracy against the double references ---------------------------------------------

struct Measured {
  const char* scene;
  const char* method;
  double phong_cc;    // colour correctness against the Phong reference
  double phong_mean;  // levels
  int phong_max;
  double angular_cc;  // against the angular (slerped-normal) reference
  double angular_mean;
  int angular_max;
};

void print(const Measured& m, const Comparison& p, const Comparison& a) {
  std::printf("    {\"%s\", \"%s\", %.4f, %.3f, %d, %.4f, %.3f, %d},\n", m.scene, m.method,
              p.color_correctness, p.mean_abs, p.max_abs, a.color_correctness, a.mean_abs,
              a.max_abs);
}

// Measured with `kb_device_test --gtest_filter='*KbAccuracy*'` (the lines it prints).
constexpr Measured kMeasured[] = {
    {"sphere-32", "kb", 0.9919, 2.061, 20, 0.9919, 2.066, 20},
    {"sphere-512", "kb", 0.9964, 0.930, 5, 0.9964, 0.930, 5},
    {"sphere-40", "kb", 0.9894, 2.691, 20, 0.9914, 2.190, 17},
    {"dodecahedron-30", "kb", 0.9879, 3.090, 32, 0.9872, 3.265, 34},
    {"triangle", "kb", 0.9566, 11.077, 44, 0.9536, 11.822, 44},
    {"teapot", "kb", 0.9954, 1.180, 17, 0.9954, 1.177, 17},
    {"sphere-32", "kb-decomposition", 0.9954, 1.173, 11, 0.9961, 0.992, 6},
    {"sphere-512", "kb-decomposition", 0.9964, 0.912, 5, 0.9964, 0.912, 5},
    {"sphere-40", "kb-decomposition", 0.9942, 1.484, 13, 0.9953, 1.191, 7},
    {"dodecahedron-30", "kb-decomposition", 0.9940, 1.525, 16, 0.9957, 1.090, 8},
    {"triangle", "kb-decomposition", 0.9687, 7.994, 25, 0.9770, 5.877, 25},
    {"teapot", "kb-decomposition", 0.9951, 1.258, 11, 0.9951, 1.257, 8},
    // Exact (eq. 1) against the angular reference: what remains is L and H being slerped
    // between the vertices instead of recomputed per pixel (largest on the triangle, whose
    // point light is close) and the fixed-point rounding (1-2 levels on the spheres).
    {"sphere-32", "kb-exact", 0.9973, 0.679, 6, 0.9991, 0.238, 2},
    {"sphere-512", "kb-exact", 0.9996, 0.099, 1, 0.9996, 0.096, 1},
    {"sphere-40", "kb-exact", 0.9952, 1.217, 16, 0.9987, 0.336, 2},
    {"dodecahedron-30", "kb-exact", 0.9966, 0.863, 12, 0.9989, 0.284, 3},
    {"triangle", "kb-exact", 0.9803, 5.019, 16, 0.9886, 2.902, 10},
    {"teapot", "kb-exact", 0.9997, 0.080, 7, 0.9999, 0.032, 5},
};

class KbAccuracy : public ::testing::TestWithParam<Measured> {};

TEST_P(KbAccuracy, WithinMeasuredBounds) {
  const Measured& m = GetParam();
  const Scene scene = scene_named(m.scene);
  DeviceRenderer device(scene.width, scene.height);
  const DeviceFrame f = render(device, scene, m.method);
  const ReferenceFrame phong = device.render_reference(0.0, Interpolation::Phong);
  const ReferenceFrame angular = device.render_reference(0.0, Interpolation::Angular);
  const Comparison p = compare(phong.image(), phong.covered, f.image(), f.covered);
  const Comparison a = compare(angular.image(), angular.covered, f.image(), f.covered);
  print(m, p, a);
  EXPECT_GE(p.color_correctness, m.phong_cc - 0.0005);
  EXPECT_LE(p.mean_abs, m.phong_mean * 1.05 + 0.05);
  EXPECT_LE(p.max_abs, m.phong_max + 2);
  EXPECT_GE(a.color_correctness, m.angular_cc - 0.0005);
  EXPECT_LE(a.mean_abs, m.angular_mean * 1.05 + 0.05);
  EXPECT_LE(a.max_abs, m.angular_max + 2);
}

INSTANTIATE_TEST_SUITE_P(PaperScenes, KbAccuracy, ::testing::ValuesIn(kMeasured),
                         [](const auto& info) {
                           return kbtest::test_name_of(std::string(info.param.scene) + "_" +
                                                       info.param.method);
                         });

// The targets against the Phong reference (Vlasic's best: 0.9949 and 0.9311).
TEST(KbTargets, TeapotAndTriangle) {
  for (const auto& [name, target] : {std::pair{"teapot", 0.995}, std::pair{"triangle", 0.95}}) {
    const Scene scene = scene_named(name);
    DeviceRenderer device(scene.width, scene.height);
    const DeviceFrame f = render(device, scene, "kb");
    const ReferenceFrame ref = device.render_reference(0.0, Interpolation::Phong);
    const Comparison c = compare(ref.image(), ref.covered, f.image(), f.covered);
    std::printf("%s: colour correctness %.5f (target %.3f)\n", name, c.color_correctness, target);
    EXPECT_GE(c.color_correctness, target) << name;
  }
}

}  // namespace
}  // namespace tp::host

// --- Degenerate lighting (issue 4 item 7): a point light in the tangent plane of a vertex,
// and one almost touching the surface. Skipping must still change nothing, and the image stays
// within its measured distance of the Phong reference. Both are far from Phong for every
// angular method (L is slerped between the vertices, where it differs by more than 90°):
// kb-exact measures 0.8849 and 0.9568 on the same frames, so the loss is the interpolation of
// L, not the one-vector evaluation (docs/KUIJK-BLAKE.md, "Degenerate cases").

namespace tp::host {
namespace {

struct Degenerate {
  const char* name;
  glm::dvec3 light;
  double min_cc;  // colour correctness of kb against the Phong reference, measured − 0.002
};

class KbDegenerateLight : public ::testing::TestWithParam<Degenerate> {};

TEST_P(KbDegenerateLight, RendersAndSkipsExactly) {
  Scene scene = scene_named("triangle");
  scene.lights.at(0).vector = GetParam().light;
  DeviceRenderer device(scene.width, scene.height);
  const DeviceFrame kb = render(device, scene, "kb");
  const DeviceFrame noskip = render(device, scene, "kb-noskip");
  EXPECT_TRUE(kb.rgb == noskip.rgb);
  const ReferenceFrame ref = device.render_reference(0.0, Interpolation::Phong);
  const Comparison c = compare(ref.image(), ref.covered, kb.image(), kb.covered);
  std::printf("%s: kb vs Phong reference: colour correctness %.4f, mean %.3f, max %d\n",
              GetParam().name, c.color_correctness, c.mean_abs, c.max_abs);
  EXPECT_GE(c.color_correctness, GetParam().min_cc);
  EXPECT_GT(c.covered_both, 70000);
}

// The triangle's vertex (1, −0.9, 0) has normal ∝ 0.6 P + (0, 0, 1) = (0.6, −0.54, 1); a light at
// P + 0.5 t with t = normalize(n × y) ⟂ n lies exactly in its tangent plane. Measured
// (`kb_device_test --gtest_filter='*Degenerate*'`): 0.9016 and 0.9879; pinned 0.002 lower.
INSTANTIATE_TEST_SUITE_P(
    Triangle, KbDegenerateLight,
    ::testing::Values(Degenerate{"tangent_plane",
                                 glm::dvec3{1, -0.9, 0} +
                                     0.5 * glm::normalize(glm::cross(glm::dvec3{0.6, -0.54, 1},
                                                                     glm::dvec3{0, 1, 0})),
                                 0.8996},
                      Degenerate{"touching", glm::dvec3{0.1, -0.1, 0.002}, 0.9859}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace tp::host

// --- A light straight behind the object (found by review, 2026-12-07) --------------------------
// A directional light along −z with the eye at infinity: L + E = 0, so H is undefined, and
// halfway() gives the zero vector (firmware/lighting.hpp). Blinn-Phong takes N·H as 0 there, so the
// visible side has no highlight. The angular methods read the zero vectors' angle as 0, a full
// highlight over every triangle (the disc uniform grey: kb 107 levels off the Phong reference,
// kb-exact 102). They now leave such a term out. kb's and kb-adaptive's no-skip forms must still
// match them.

namespace tp::host {
namespace {

struct Backlit {
  const char* method;
  int max_abs;  // against the Phong reference: measured, pinned (below)
};

class KbBacklight : public ::testing::TestWithParam<Backlit> {};

TEST_P(KbBacklight, NoHighlightWhereTheHalfwayVectorIsUndefined) {
  Scene scene = scene_named("sphere-512");
  scene.width = 201;
  scene.height = 157;
  scene.lights.assign(1, Light{LightKind::Directional, glm::dvec3{0, 0, -1}, glm::dvec3{1, 1, 1}});
  DeviceRenderer device(scene.width, scene.height);
  const DeviceFrame frame = render(device, scene, GetParam().method);
  const ReferenceFrame ref = device.render_reference(0.0, Interpolation::Phong);
  const Comparison c = compare(ref.image(), ref.covered, frame.image(), frame.covered);
  std::printf("%s, backlit: colour correctness %.4f, mean %.3f, max %d\n", GetParam().method,
              c.color_correctness, c.mean_abs, c.max_abs);
  EXPECT_LE(c.max_abs, GetParam().max_abs);
  EXPECT_GT(c.covered_both, 10000);
  const std::string name = GetParam().method;
  if (name == "kb" || name == "kb-adaptive") {
    EXPECT_TRUE(frame.rgb == render(device, scene, name + "-noskip").rgb);
  }
}

// Measured (`kb_device_test --gtest_filter='*KbBacklight*'`, 2026-12-07): kb, kb-decomposition 5,
// kb-exact 1, kb-adaptive 0 levels; pinned 1 higher.
INSTANTIATE_TEST_SUITE_P(Sphere512, KbBacklight,
                         ::testing::Values(Backlit{"kb", 6}, Backlit{"kb-decomposition", 6},
                                           Backlit{"kb-exact", 2}, Backlit{"kb-adaptive", 1}),
                         [](const auto& info) { return kbtest::test_name_of(info.param.method); });

}  // namespace
}  // namespace tp::host

// --- Coherent span setup (kb_coherence.hpp) against the exact setup of every span ----------

namespace tp::host {
namespace {

class KbCoherence : public ::testing::TestWithParam<const char*> {};

// Measured (`kb_device_test --gtest_filter='*KbCoherence*'`, the same numbers as the table of
// docs/KUIJK-BLAKE.md): at most 1 level on any pixel, at most 2.2 % of the pixels differ (the
// triangle: 1,755 of 79,560). Pinned: max 1 level, at most 3 % of pixels.
TEST_P(KbCoherence, WithinOneLevelOfExactSetup) {
  Scene scene = scene_named(GetParam());
  scene.method = "kb";
  DeviceRenderer device(scene.width, scene.height);
  device.set_scene(scene);
  (void)device.render(0.0);
  kbbench::Frame f = kbbench::replay_frame(device, scene);
  const kbbench::CoherenceDiff d = kbbench::compare_coherent_with_exact(f);
  std::printf("%s: %lld pixels, %lld differ, max %d\n", GetParam(), d.pixels, d.differing, d.max);
  EXPECT_GT(d.pixels, 50000);
  EXPECT_LE(d.max, 1);
  EXPECT_LE(static_cast<double>(d.differing), 0.03 * static_cast<double>(d.pixels));
}

INSTANTIATE_TEST_SUITE_P(PaperScenes, KbCoherence,
                         ::testing::Values("sphere-32", "sphere-40", "sphere-512",
                                           "dodecahedron-30", "triangle", "teapot"),
                         [](const auto& info) { return kbtest::test_name_of(info.param); });

}  // namespace
}  // namespace tp::host
