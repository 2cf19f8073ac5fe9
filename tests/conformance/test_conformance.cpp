// The conformance test: what every registered shading method (firmware/registry.hpp) must do,
// whatever it computes in between. Instantiated over the registry, so a new row is tested
// without touching this file — except for its counting rule (kSites below), whose absence fails.
//
//   - coverage: the same pixels as Gouraud on every paper scene (a method may not skip a
//     triangle or a pixel the pipeline drew), the same geometry counters;
//   - an ambient-only material (kd = ks = 0) gives exactly the ambient colour on every covered
//     pixel of every paper scene;
//   - determinism: the same frame renders to the same bytes after another frame and in a fresh
//     device (no state from one frame leaks into the next), with the same counters in a fresh
//     device;
//   - skipping: a light of zero intensity changes no pixel; a verification variant (the same
//     method with its skips disabled) renders its method's image byte for byte;
//   - the counters mean what firmware/counters.hpp defines, in every method.
//
// Frames are 160x120 (the target suite's size): the test is about rules, not accuracy, and
// it renders every paper scene several times per method.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "firmware/registry.hpp"
#include "host/device_renderer.hpp"
#include "host/scene.hpp"
#include "tests/paper_scenes.hpp"

namespace tp::fw {
// gtest prints a failing parameter by its name.
void PrintTo(const MethodInfo& m, std::ostream* os) { *os << m.name; }
}  // namespace tp::fw

namespace tp::host {
namespace {

constexpr int kWidth = 160, kHeight = 120;

Scene paper_scene(const std::string& name) {
  Scene s = load_scene(std::string(TP_SCENES_DIR) + "/" + name + ".json");
  s.width = kWidth;
  s.height = kHeight;
  return s;
}

DeviceFrame draw(Scene scene, std::string_view method, double rotation = 0.0) {
  scene.method = std::string(method);
  DeviceRenderer renderer(kWidth, kHeight);
  renderer.set_scene(scene);
  return renderer.render(rotation);
}

std::uint64_t counter(const DeviceFrame& f, std::string_view name) {
  for (const auto& [n, v] : f.counters)
    if (n == name) return v;
  ADD_FAILURE() << "no counter " << name;
  return 0;
}

// The counters of one frame: all but `frames`, which counts frames since the device was made.
CounterSnapshot frame_counters(const DeviceFrame& f) {
  CounterSnapshot out;
  for (const auto& c : f.counters)
    if (c.first != "frames") out.push_back(c);
  return out;
}

// Gouraud's frame of each paper scene, rendered once for all methods.
const DeviceFrame& gouraud_frame(const std::string& scene) {
  static std::map<std::string, DeviceFrame> frames;
  auto it = frames.find(scene);
  if (it == frames.end()) it = frames.emplace(scene, draw(paper_scene(scene), "gouraud")).first;
  return it->second;
}

std::string test_name(const fw::MethodInfo& m) {
  std::string n(m.name);
  std::replace(n.begin(), n.end(), '-', '_');
  return n;
}

class Conformance : public ::testing::TestWithParam<fw::MethodInfo> {};

TEST_P(Conformance, CoversWhatGouraudCoversOnEveryPaperScene) {
  const fw::MethodInfo& m = GetParam();
  const auto scenes = paper_scenes();
  ASSERT_EQ(scenes.size(), 24u);
  for (const std::string& name : scenes) {
    SCOPED_TRACE(name);
    const DeviceFrame& g = gouraud_frame(name);
    const DeviceFrame f = draw(paper_scene(name), m.name);
    EXPECT_TRUE(f.covered == g.covered) << "coverage differs from Gouraud's";
    EXPECT_GT(std::count(f.covered.begin(), f.covered.end(), 1), 0);
    for (const char* c :
         {"triangles_in", "triangles_culled", "triangles_clipped", "triangles_rejected",
          "triangles_degenerate", "triangles_drawn", "pixels_written"})
      EXPECT_EQ(counter(f, c), counter(g, c)) << c;
    EXPECT_EQ(counter(f, "triangles_skipped"), 0u);
    EXPECT_EQ(counter(f, "saturations"), 0u);
  }
}

// ka = 0.25, O = (0.8, 0.6, 0.3): 255 ka O = 51, 38.25, 19.125, far from a rounding tie.
TEST_P(Conformance, AnAmbientOnlyMaterialGivesTheAmbientColour) {
  const fw::MethodInfo& m = GetParam();
  const std::uint8_t expected[3] = {51, 38, 19};
  for (const std::string& name : paper_scenes()) {
    SCOPED_TRACE(name);
    Scene s = paper_scene(name);
    s.material.ka = 0.25;
    s.material.kd = 0;
    s.material.ks = 0;
    s.material.colour = {0.8, 0.6, 0.3};
    s.background = {0, 0, 0};
    const DeviceFrame f = draw(s, m.name);
    std::size_t covered = 0, wrong = 0;
    for (std::size_t p = 0; p < f.covered.size(); ++p) {
      const std::uint8_t* px = &f.rgb[3 * p];
      const bool ok = f.covered[p] != 0
                          ? px[0] == expected[0] && px[1] == expected[1] && px[2] == expected[2]
                          : px[0] == 0 && px[1] == 0 && px[2] == 0;
      covered += f.covered[p] != 0 ? 1 : 0;
      wrong += ok ? 0 : 1;
    }
    EXPECT_GT(covered, 0u);
    EXPECT_EQ(wrong, 0u) << "pixels other than the ambient colour (or the background)";
  }
}

// The same frame after another one, and in a fresh device: the same bytes and counters.
TEST_P(Conformance, RendersAFrameTheSameWayEveryTime) {
  const fw::MethodInfo& m = GetParam();
  for (const char* name : {"teapot-l2", "sphere-40-l4", "triangle-l8"}) {
    SCOPED_TRACE(name);
    Scene s = paper_scene(name);
    s.method = std::string(m.name);
    DeviceRenderer renderer(kWidth, kHeight);
    renderer.set_scene(s);
    const DeviceFrame first = renderer.render(0.0);
    const DeviceFrame other = renderer.render(0.7);
    const DeviceFrame again = renderer.render(0.0);
    const DeviceFrame fresh = draw(s, m.name);
    EXPECT_FALSE(other.rgb == first.rgb) << "the rotation must show";
    EXPECT_TRUE(again.rgb == first.rgb);
    EXPECT_TRUE(fresh.rgb == first.rgb);
    EXPECT_EQ(frame_counters(fresh), frame_counters(first));
    // After another frame the pipeline's counters are the same; a method's work counters may be
    // lower where it keeps a content-addressed memo across frames (kb-adaptive's boundary
    // samples, kept while the shading state's revision is: the values are the same, fewer are
    // evaluated).
    for (const char* c : {"triangles_in", "triangles_culled", "triangles_drawn", "spans",
                          "spans_hidden", "pixels_shaded", "pixels_written"})
      EXPECT_EQ(counter(again, c), counter(first, c)) << c;
    EXPECT_LE(counter(again, "lighting_evaluations"), counter(first, "lighting_evaluations"));
  }
}

// A flat square, one normal everywhere, under a near point light and a coloured directional one.
// On it kb-decomposition took N's circle, which a span's arc of one normal does not fix, through
// the first light's direction for every light: a dark light put first, or the lights' order
// swapped, changed pixels by up to 54 levels (found by review, 2026-12-07).
Scene flat_square() {
  Scene s = parse_scene(R"({
    "camera": {"type": "orthographic", "extents": [-1.25, 1.25, -1.25, 1.25],
               "near": -10, "far": 10},
    "lights": [{"type": "point", "position": [0.3, 0.2, 0.4]},
               {"type": "directional", "direction": [-0.5, 0.3, 1], "colour": [0.6, 0.5, 0.4]}],
    "material": {"colour": [0.2, 0.4, 1.0], "ka": 0.1, "kd": 0.6, "ks": 0.4, "n": 20},
    "meshes": [{"obj": "quad.obj"}]})",
                        "flat-square.json", TP_SCENES_DIR);
  s.width = kWidth;
  s.height = kHeight;
  return s;
}

// The paper scenes named, then the flat square.
std::vector<Scene> with_flat_square(std::initializer_list<const char*> paper) {
  std::vector<Scene> scenes;
  for (const char* name : paper) scenes.push_back(paper_scene(name));
  scenes.push_back(flat_square());
  return scenes;
}

// A light of zero intensity adds exactly nothing: whatever the method skips or evaluates for it,
// and wherever it stands in the list, no pixel may change.
TEST_P(Conformance, ADarkLightChangesNoPixel) {
  const fw::MethodInfo& m = GetParam();
  for (const Scene& s :
       with_flat_square({"teapot", "sphere-32-l2", "dodecahedron-30-l4", "triangle"})) {
    SCOPED_TRACE(s.file);
    const std::vector<std::uint8_t> image = draw(s, m.name).rgb;
    Scene dark = s;
    dark.lights.push_back({LightKind::Directional, {0.3, 0.4, 0.866}, {0, 0, 0}});
    dark.lights.push_back({LightKind::Point, {-1.0, 2.0, 3.0}, {0, 0, 0}});
    EXPECT_TRUE(draw(dark, m.name).rgb == image) << "dark lights last";
    dark = s;
    dark.lights.insert(dark.lights.begin(), {LightKind::Directional, {0, 1, 0}, {0, 0, 0}});
    EXPECT_TRUE(draw(dark, m.name).rgb == image) << "a dark light first";
  }
}

// The lights' contributions are summed: their order in the scene changes no pixel.
TEST_P(Conformance, TheLightsOrderChangesNoPixel) {
  const fw::MethodInfo& m = GetParam();
  for (const Scene& s :
       with_flat_square({"teapot-l4", "sphere-32-l4", "dodecahedron-30-l4", "triangle-l4"})) {
    SCOPED_TRACE(s.file);
    Scene reversed = s;
    std::reverse(reversed.lights.begin(), reversed.lights.end());
    EXPECT_TRUE(draw(reversed, m.name).rgb == draw(s, m.name).rgb);
  }
}

// Where each method evaluates, for the counting rules of firmware/counters.hpp. A new method
// states its own here (the test fails until it does).
enum class Sites {
  kTriangle,                // one exact evaluation per triangle (flat)
  kVertex,                  // one per vertex of the draw, colours interpolated (Gouraud)
  kPixel,                   // one per pixel shaded
  kPixelLightsSkipped,      // the same, with the lights a triangle faces away from left out
  kPolynomials,             // fitted polynomials per pixel, a specular factor per light and pixel
  kSpanTerms,               // per span, each light's specular term (Kuijk-Blake), some skipped
  kSpanTermsAll,            // the same with none skipped
  kSamplesAndPixels,        // exact samples and exact pixels, fits between (kb-adaptive)
  kVertexAndHighlights,     // diffuse at the vertices, highlights per pixel where not culled
  kVertexAndHighlightsAll,  // the same with none culled (brown-noskip)
  kSixSamples,              // the vertices (shared ones lit once) and three midpoints per triangle
  kVertexAndMap,            // diffuse at the vertices; each light's highlight per sample of the map
  kTexturesPerPixel,        // per pixel and light, a specular texture sample; nothing lit exactly
};
const std::map<std::string_view, Sites> kSites = {
    {"flat", Sites::kTriangle},
    {"gouraud", Sites::kVertex},
    {"phong", Sites::kPixel},
    {"duff", Sites::kPixelLightsSkipped},
    {"bishop-weimer", Sites::kPolynomials},
    {"bishop-weimer-finite", Sites::kPolynomials},
    {"brown", Sites::kVertexAndHighlights},
    {"brown-noskip", Sites::kVertexAndHighlightsAll},
    {"gouraud-subdivided", Sites::kSixSamples},
    {"quadratic", Sites::kSixSamples},
    {"quadratic-screen", Sites::kSixSamples},
    {"envmap", Sites::kVertexAndMap},
    {"blinn-map", Sites::kTexturesPerPixel},
    {"quadratic-blinn-map", Sites::kTexturesPerPixel},
    {"kb", Sites::kSpanTerms},
    {"kb-noskip", Sites::kSpanTermsAll},
    {"kb-decomposition", Sites::kSpanTerms},
    {"kb-exact", Sites::kSpanTermsAll},
    {"kb-adaptive", Sites::kSamplesAndPixels},
    {"kb-adaptive-noskip", Sites::kSamplesAndPixels},
    {"kb-adaptive-exact", Sites::kPixel},
};

TEST_P(Conformance, CountsAsTheCountersAreDefined) {
  const fw::MethodInfo& m = GetParam();
  const auto site = kSites.find(m.name);
  ASSERT_NE(site, kSites.end()) << m.name << ": add its counting rule to kSites";
  for (const char* name : {"teapot", "sphere-40-l4", "triangle-l2", "dodecahedron-30-l8"}) {
    SCOPED_TRACE(name);
    const Scene s = paper_scene(name);
    const DeviceFrame f = draw(s, m.name);
    const std::uint64_t lights = s.lights.size();  // none of them dark
    const std::uint64_t lighting = counter(f, "lighting_evaluations");
    const std::uint64_t specular = counter(f, "specular_evaluations");
    const std::uint64_t shaded = counter(f, "pixels_shaded");
    const std::uint64_t triangles = counter(f, "triangles_drawn");
    EXPECT_LE(counter(f, "pixels_written"), shaded);
    EXPECT_LE(counter(f, "spans_hidden"), counter(f, "spans"));
    switch (site->second) {
      case Sites::kTriangle:
        EXPECT_EQ(lighting, triangles);
        EXPECT_EQ(specular, lighting * lights);
        break;
      case Sites::kVertex:
        EXPECT_GT(lighting, 0u);
        EXPECT_LE(lighting, 3 * triangles);  // shared vertices lit once
        EXPECT_EQ(specular, lighting * lights);
        break;
      case Sites::kPixel:
        EXPECT_EQ(lighting, shaded);
        EXPECT_EQ(specular, lighting * lights);
        break;
      case Sites::kPixelLightsSkipped:
        EXPECT_EQ(lighting, shaded);
        if (counter(f, "lights_skipped_triangle") == 0)
          EXPECT_EQ(specular, lighting * lights);
        else
          EXPECT_LT(specular, lighting * lights);
        break;
      case Sites::kPolynomials:  // skipped terms: diffuse or specular
        EXPECT_EQ(lighting, 0u);
        if (counter(f, "lights_skipped_triangle") == 0)
          EXPECT_EQ(specular, shaded * lights);
        else
          EXPECT_LE(specular, shaded * lights);
        break;
      case Sites::kSpanTerms:
        EXPECT_EQ(lighting, 0u);
        EXPECT_GT(specular, 0u);
        EXPECT_LT(specular, shaded * lights);  // something skipped on every paper scene
        break;
      case Sites::kSpanTermsAll:
        EXPECT_EQ(lighting, 0u);
        EXPECT_EQ(specular, shaded * lights);
        break;
      case Sites::kSamplesAndPixels:
        EXPECT_GE(lighting, counter(f, "lattice_samples"));
        EXPECT_LE(lighting, counter(f, "lattice_samples") + shaded);
        EXPECT_EQ(specular, lighting * lights);
        break;
      case Sites::kVertexAndHighlights:  // the vertices' diffuse evaluates no specular factor
        EXPECT_GT(lighting, 0u);
        EXPECT_LE(lighting, 3 * triangles);
        if (counter(f, "lights_skipped_triangle") == 0)  // the triangle: its highlight is on it
          EXPECT_EQ(specular, shaded * lights);
        else
          EXPECT_LT(specular, shaded * lights);
        break;
      case Sites::kVertexAndHighlightsAll:
        EXPECT_GT(lighting, 0u);
        EXPECT_LE(lighting, 3 * triangles);
        EXPECT_EQ(specular, shaded * lights);
        EXPECT_EQ(counter(f, "lights_skipped_triangle"), 0u);
        break;
      case Sites::kSixSamples:
        EXPECT_GE(lighting, 3 * triangles + 3);  // three midpoints each, and some vertices
        EXPECT_LE(lighting, 6 * triangles);
        EXPECT_EQ(specular, lighting * lights);
        EXPECT_GE(counter(f, "normalizations"), 3 * triangles);  // the midpoints' normals
        break;
      case Sites::kVertexAndMap: {  // a map of 65² samples, built once or more per frame
        const std::uint64_t map = 65 * 65 * lights;
        EXPECT_GT(lighting, 0u);
        EXPECT_LE(lighting, 3 * triangles);
        EXPECT_GE(specular, map);
        EXPECT_EQ(specular % map, 0u);
        break;
      }
      case Sites::kTexturesPerPixel:
        EXPECT_EQ(lighting, 0u);
        EXPECT_EQ(specular, shaded * lights);
        EXPECT_GE(counter(f, "normalizations"), 3 * triangles * lights);  // H at every vertex
        break;
    }
  }
}

// The registry's reads_budget is what the images say: a method that reads no error budget draws
// every paper scene the same at budgets 1 and 16, the largest (the CLI tells a user that --budget
// has no effect on it); one that reads it draws some paper scene otherwise.
TEST_P(Conformance, ReadsTheErrorBudgetWhereTheRegistrySays) {
  const fw::MethodInfo& m = GetParam();
  int differing = 0;
  for (const std::string& name : paper_scenes()) {
    SCOPED_TRACE(name);
    Scene s = paper_scene(name);
    s.budget = 1;
    const DeviceFrame tight = draw(s, m.name);
    s.budget = static_cast<int>(fw::kMaxBudgetLevels);
    const bool same = draw(s, m.name).rgb == tight.rgb;
    if (!m.reads_budget) {
      EXPECT_TRUE(same);
    }
    differing += same ? 0 : 1;
    if (m.reads_budget && differing > 0) break;
  }
  EXPECT_EQ(differing > 0, m.reads_budget);
}

INSTANTIATE_TEST_SUITE_P(Registry, Conformance, ::testing::ValuesIn(fw::kMethodTable),
                         [](const auto& info) { return test_name(info.param); });

// The verification variants render their method's image on every paper scene.
TEST(Registry, VerificationVariantsRenderTheirMethodsImage) {
  int variants = 0;
  for (const fw::MethodInfo& m : fw::kMethodTable) {
    if (m.same_image_as == fw::Method{}) continue;
    ++variants;
    const fw::MethodInfo* original = fw::find_method(m.same_image_as);
    ASSERT_NE(original, nullptr);
    for (const std::string& name : paper_scenes()) {
      SCOPED_TRACE(std::string(m.name) + " / " + name);
      const Scene s = paper_scene(name);
      EXPECT_TRUE(draw(s, m.name).rgb == draw(s, original->name).rgb);
    }
  }
  EXPECT_EQ(variants, 3);  // kb-noskip, kb-adaptive-noskip, brown-noskip
}

// quadratic-screen differs from quadratic only where (s, t) are not affine in screen space: its
// image is quadratic's, byte for byte, on every orthographic paper scene, and not on the teapot.
TEST(Registry, QuadraticScreenIsQuadraticInOrthographicViews) {
  int same = 0;
  for (const std::string& name : paper_scenes()) {
    SCOPED_TRACE(name);
    const Scene s = paper_scene(name);
    const bool equal = draw(s, "quadratic-screen").rgb == draw(s, "quadratic").rgb;
    EXPECT_EQ(equal, s.camera.kind == CameraKind::Orthographic);
    same += equal ? 1 : 0;
  }
  EXPECT_EQ(same, 20);  // the teapot's four are perspective
}

// Bishop-Weimer's finite-eye extension changes only what varies: with the eye at infinity and
// every light directional, H and L are the same at the three vertices and its image is
// bishop-weimer's, byte for byte, on every orthographic paper scene (each point light replaced
// by a directional one from the same side); under perspective (the teapot) it is not.
TEST(Registry, BishopWeimerFiniteIsBishopWeimerWithEverythingAtInfinity) {
  int compared = 0;
  for (const std::string& name : paper_scenes()) {
    SCOPED_TRACE(name);
    Scene s = paper_scene(name);
    if (s.camera.kind != CameraKind::Orthographic) {
      EXPECT_FALSE(draw(s, "bishop-weimer-finite").rgb == draw(s, "bishop-weimer").rgb);
      continue;
    }
    // The point lights as they are: the extension must show.
    EXPECT_FALSE(draw(s, "bishop-weimer-finite").rgb == draw(s, "bishop-weimer").rgb);
    for (Light& l : s.lights) l.kind = LightKind::Directional;  // toward the old position
    EXPECT_TRUE(draw(s, "bishop-weimer-finite").rgb == draw(s, "bishop-weimer").rgb);
    ++compared;
  }
  EXPECT_EQ(compared, 20);  // the teapot's four are perspective
}

// Subdivided Gouraud interpolates its sub-triangles' lit corners, so no pixel may fall below the
// ambient floor that every lit colour has. A pixel just outside its sub-triangle (the midpoints
// rounded to 1/16 pixel off the outer edges) took a sliver's plane extrapolated to black (found by
// review, 2026-12-07: a small teapot turned by 3 degrees, pixel (144, 94)).
TEST(Registry, SubdividedGouraudStaysAboveTheAmbientFloor) {
  Scene s = parse_scene(R"({
    "camera": {"type": "perspective", "position": [0.5, 0.7, 7], "target": [0, 0, 0],
               "fov_y": 70, "near": 0.1, "far": 100},
    "lights": [{"type": "directional", "direction": [1, 1.5, 1]},
               {"type": "point", "position": [0, 0, 3], "colour": [0.5, 0.5, 0.5]}],
    "material": {"colour": [0.2, 0.4, 1.0], "ka": 0.1, "kd": 0.6, "ks": 0.4, "n": 20},
    "meshes": [{"generator": "teapot", "params": {"tessellation": 3},
                "transform": {"translate": [-1.5, 1.5, -0.3], "scale": 0.25,
                              "rotate": {"axis": [1, 2, 3], "degrees": 79}}}]})",
                        "small-teapot.json", TP_SCENES_DIR);
  s.width = 400;
  s.height = 300;
  Scene ambient = s;
  ambient.material.kd = ambient.material.ks = 0;
  int checked = 0;
  for (const double degrees : {0.0, 3.0, 100.0, 211.0}) {
    SCOPED_TRACE(degrees);
    const double radians = degrees * 3.14159265358979323846 / 180;
    s.method = "gouraud-subdivided";
    ambient.method = "gouraud";
    DeviceRenderer device(s.width, s.height), floor_device(s.width, s.height);
    device.set_scene(s);
    floor_device.set_scene(ambient);
    const DeviceFrame f = device.render(radians), floor = floor_device.render(radians);
    ASSERT_EQ(f.covered, floor.covered);
    for (std::size_t i = 0; i < f.covered.size(); ++i) {
      if (!f.covered[i]) continue;
      ++checked;
      for (std::size_t ch = 0; ch < 3; ++ch)
        ASSERT_GE(f.rgb[3 * i + ch], floor.rgb[3 * i + ch])
            << "pixel " << i % 400 << ", " << i / 400;
    }
  }
  EXPECT_GT(checked, 1000);
}

// The host's list is the registry's, and every row's name parses back to its id.
TEST(Registry, TheHostListsEveryRow) {
  ASSERT_EQ(method_names().size(), std::size(fw::kMethodTable));
  for (const fw::MethodInfo& m : fw::kMethodTable) {
    EXPECT_EQ(method_from_name(m.name), m.id);
    EXPECT_EQ(method_name(m.id), m.name);
    EXPECT_GT(fw::Device::method_bytes(m.id), 0u) << m.name;
  }
  EXPECT_THROW(method_from_name("no-such-method"), std::invalid_argument);
  // A name with a NUL in it (a client's "phong\u0000x") is quoted whole, its control bytes as
  // \xNN: the message ended at the NUL, without its list of valid names (found by review,
  // 2026-12-07).
  try {
    (void)method_from_name(std::string_view("phong\0x\x1b", 8));
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(
        std::string(e.what()).find("unknown shading method 'phong\\x00x\\x1b' (valid: flat, "),
        std::string::npos)
        << e.what();
  }
  // Reserved ids have no row and no state: set_method refuses them.
  for (const fw::Method reserved : {static_cast<fw::Method>(10), static_cast<fw::Method>(20)}) {
    EXPECT_EQ(fw::find_method(reserved), nullptr);
    EXPECT_EQ(fw::Device::method_bytes(reserved), 0u);
  }
}

}  // namespace
}  // namespace tp::host
