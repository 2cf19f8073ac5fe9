// kb-adaptive end to end through the device, on every paper scene (1, 2, 4 and 8 lights) and on
// the near-light stress scenes of scenes/stress/ (docs/KUIJK-BLAKE.md, "kb-adaptive"):
//   - skipping changes nothing: kb-adaptive and kb-adaptive-noskip give the same image;
//   - the budget: every pixel within 1 level of kb-adaptive-exact (its exact evaluation);
//   - accuracy against the double Phong reference at least kb's (colour correctness no lower,
//     maximum error no larger) on the paper scenes, and on the stress scenes colour correctness
//     >= 0.995, maximum error <= 16 levels and never below Gouraud's (the targets);
//   - determinism: the same frame after other scenes have been drawn.
// The measured values are printed (one line per scene).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "host/device_renderer.hpp"
#include "host/metrics.hpp"
#include "host/scene.hpp"
#include "tests/kb/scene_frames.hpp"

namespace tp::host {
namespace {

using kbtest::counter;
using kbtest::render;
using kbtest::scene_named;

Comparison against_phong(DeviceRenderer& device, const DeviceFrame& f) {
  const ReferenceFrame ref = device.render_reference(0.0, Interpolation::Phong);
  return compare(ref.image(), ref.covered, f.image(), f.covered);
}

class KbAdaptiveScene : public ::testing::TestWithParam<const char*> {};

TEST_P(KbAdaptiveScene, SkippingBudgetAccuracy) {
  const std::string name = GetParam();
  const bool stress = name.rfind("stress/", 0) == 0;
  const Scene scene = scene_named(name);
  DeviceRenderer device(scene.width, scene.height);
  const DeviceFrame adaptive = render(device, scene, "kb-adaptive");
  const DeviceFrame no_skip = render(device, scene, "kb-adaptive-noskip");
  const DeviceFrame exact = render(device, scene, "kb-adaptive-exact");

  // Skipping: the same image, the same choices.
  EXPECT_TRUE(adaptive.rgb == no_skip.rgb);
  EXPECT_TRUE(adaptive.covered == no_skip.covered);
  for (const char* c : {"adaptive_constant", "adaptive_linear", "adaptive_quadratic",
                        "adaptive_subdivided", "adaptive_exact", "subtriangles"})
    EXPECT_EQ(counter(adaptive, c), counter(no_skip, c)) << c;

  // The budget, against the exact evaluation of the same triangles.
  const Comparison budget =
      compare(exact.image(), exact.covered, adaptive.image(), adaptive.covered);
  EXPECT_LE(budget.max_abs, 1);

  const Comparison a = against_phong(device, adaptive);
  std::printf(
      "%-24s cc %.5f max %3d | vs exact: max %d | constant %llu linear %llu quadratic %llu "
      "subdivided %llu (cells %llu, exact cells %llu, unchecked %llu) exact %llu\n",
      name.c_str(), a.color_correctness, a.max_abs, budget.max_abs,
      static_cast<unsigned long long>(counter(adaptive, "adaptive_constant")),
      static_cast<unsigned long long>(counter(adaptive, "adaptive_linear")),
      static_cast<unsigned long long>(counter(adaptive, "adaptive_quadratic")),
      static_cast<unsigned long long>(counter(adaptive, "adaptive_subdivided")),
      static_cast<unsigned long long>(counter(adaptive, "subtriangles")),
      static_cast<unsigned long long>(counter(adaptive, "subtriangles_exact")),
      static_cast<unsigned long long>(counter(adaptive, "subtriangles_unchecked")),
      static_cast<unsigned long long>(counter(adaptive, "adaptive_exact")));
  if (stress) {
    const Comparison g = against_phong(device, render(device, scene, "gouraud"));
    EXPECT_GE(a.color_correctness, 0.995);
    EXPECT_LE(a.max_abs, 16);
    EXPECT_GE(a.color_correctness, g.color_correctness);
    EXPECT_LE(a.max_abs, g.max_abs);
  } else {
    const Comparison k = against_phong(device, render(device, scene, "kb"));
    EXPECT_GE(a.color_correctness, k.color_correctness);
    EXPECT_LE(a.max_abs, k.max_abs);
    // Measured 2026-12-01 (the lines printed above): 0.99964 or better, max 9 levels (the
    // teapot with 8 lights; 5 on the teapot, 1 on the spheres and the triangle) — pinned with a
    // margin.
    EXPECT_GE(a.color_correctness, 0.9990);
    EXPECT_LE(a.max_abs, 11);
  }
}

INSTANTIATE_TEST_SUITE_P(PaperScenes, KbAdaptiveScene, ::testing::ValuesIn(kbtest::kPaperScenes),
                         [](const auto& info) { return kbtest::test_name_of(info.param); });
INSTANTIATE_TEST_SUITE_P(StressScenes, KbAdaptiveScene,
                         ::testing::Values("stress/triangle-near-1", "stress/triangle-near-2",
                                           "stress/triangle-near-5", "stress/triangle-near-16",
                                           "stress/sphere-512-near-1", "stress/sphere-512-near-2",
                                           "stress/sphere-512-near-5"),
                         [](const auto& info) { return kbtest::test_name_of(info.param); });

// A budget of B levels (set_budget, a scene's "budget"): every pixel within B levels of the exact
// evaluation, no more exact samples than at the budget below (fewer in all where no near light
// decides the refinement), and back to the 1-level image when the budget
// returns to 1 on the same device (the budget is part of the state each scene sets).
TEST(KbAdaptiveBudgetLevels, LargerBudgetsStayWithinThemAndSampleLess) {
  // Near a point light the refinement that makes the samples follow L (peak_level) does not
  // depend on the budget, and on stress/triangle-near-2 it decides every cell: the same samples
  // at every budget (measured 2026-12-03: 882 at B = 1, 2, 4, 16).
  struct Case {
    const char* name;
    bool samples_less;  // strictly fewer samples at B = 16 than at B = 1
  };
  for (const auto [name, samples_less] : {Case{"teapot-l4", true}, Case{"sphere-40-l8", true},
                                          Case{"stress/triangle-near-2", false}}) {
    Scene scene = scene_named(name);
    DeviceRenderer device(scene.width, scene.height);
    const DeviceFrame exact = render(device, scene, "kb-adaptive-exact");
    const DeviceFrame one = render(device, scene, "kb-adaptive");
    std::uint64_t previous = counter(one, "lattice_samples");
    for (const int budget : {2, 4, 16}) {
      scene.budget = budget;
      const DeviceFrame f = render(device, scene, "kb-adaptive");
      const Comparison c = compare(exact.image(), exact.covered, f.image(), f.covered);
      const std::uint64_t samples = counter(f, "lattice_samples");
      std::printf("%-24s budget %2d: max %2d levels from the exact evaluation, %llu samples\n",
                  name, budget, c.max_abs, static_cast<unsigned long long>(samples));
      EXPECT_LE(c.max_abs, budget) << name << " budget " << budget;
      EXPECT_LE(samples, previous) << name << " budget " << budget;
      previous = samples;
    }
    if (samples_less) {
      EXPECT_LT(previous, counter(one, "lattice_samples")) << name;
    }
    scene.budget = 1;
    EXPECT_TRUE(render(device, scene, "kb-adaptive").rgb == one.rgb) << name;
  }
}

// The method keeps per-frame state (its lattice stamps, the highlight guard's ω for the last
// exponent): a frame must not depend on what was drawn before it.
TEST(KbAdaptiveDeterminism, SameFrameAfterOtherScenes) {
  const Scene teapot = scene_named("teapot-l2");
  DeviceRenderer device(teapot.width, teapot.height);
  const DeviceFrame first = render(device, teapot, "kb-adaptive");
  for (const char* other : {"sphere-512-l8", "triangle", "stress/triangle-near-16"}) {
    Scene s = scene_named(other);
    s.width = teapot.width;
    s.height = teapot.height;
    (void)render(device, s, "kb-adaptive");
  }
  const DeviceFrame again = render(device, teapot, "kb-adaptive");
  EXPECT_TRUE(first.rgb == again.rgb);
  for (const auto& [name, value] : first.counters)
    if (name != "frames") {
      EXPECT_EQ(counter(again, name), value) << name;
    }
}

}  // namespace
}  // namespace tp::host
