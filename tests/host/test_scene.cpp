// Scene files: every shipped scene loads with the parameters of scenes/README.md; every malformed
// fixture in data/ fails with a SceneError naming file, line, JSON path and problem.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <glm/gtc/matrix_transform.hpp>

#include "host/scene.hpp"

namespace fs = std::filesystem;
using namespace tp::host;

namespace {

const fs::path kData = TP_HOST_TEST_DATA;
const fs::path kScenes = TP_SCENES_DIR;

struct Expected {
  const char* file;
  int line;
  const char* path;
  const char* problem;  // substring of SceneError::problem()
};

SceneError load_error(const fs::path& file) {
  try {
    load_scene(file);
  } catch (const SceneError& e) {
    return e;
  }
  ADD_FAILURE() << file << " loaded without error";
  return SceneError("", -1, "", "");
}

}  // namespace

class MalformedScene : public ::testing::TestWithParam<Expected> {};

TEST_P(MalformedScene, NamesFileLinePathAndProblem) {
  const Expected& x = GetParam();
  const SceneError e = load_error(kData / x.file);
  EXPECT_EQ(e.file(), (kData / x.file).string());
  EXPECT_EQ(e.line(), x.line) << e.what();
  EXPECT_EQ(e.path(), x.path) << e.what();
  EXPECT_NE(e.problem().find(x.problem), std::string::npos) << e.what();
  // The message carries all of it, for the command-line tool to print as is.
  EXPECT_NE(std::string(e.what()).find(x.file), std::string::npos);
}

INSTANTIATE_TEST_SUITE_P(
    Fixtures, MalformedScene,
    ::testing::Values(
        Expected{"malformed.json", 4, "", "malformed JSON"},
        Expected{"unknown_key.json", 6, "/lights/1/color", "unknown key \"color\""},
        Expected{"wrong_type.json", 5, "/material/ka", "expected a number, got string"},
        Expected{"out_of_range.json", 7, "/lights/2/position/1", "out of range"},
        Expected{"nan.json", 4, "", "malformed JSON"},
        Expected{"too_many_lights.json", 3, "/lights", "at most 16 lights, got 17"},
        Expected{"missing_mesh.json", 5, "/meshes/0/obj", "mesh file not found"},
        Expected{"bad_obj.json", 6, "/meshes/1/obj",
                 "bad.obj:6: face refers to vertex 7 but the file has 3"},
        Expected{"missing_key.json", 1, "", "missing key \"camera\""},
        // A repeated key would silently drop its first value; the line is the repeat's.
        Expected{"duplicate_key.json", 7, "/lights/1/position", "duplicate key \"position\""},
        Expected{"bad_generator_param.json", 6, "/meshes/0/params/subdivisions", "out of range"},
        Expected{"bad_budget.json", 6, "/budget", "out of range"},
        // Found by fuzz_scene: a zero up passed the parallel test (0 < 0 is false) and made the
        // view matrix NaN.
        Expected{"zero_up.json", 6, "/camera/up", "up is zero or parallel"}));

TEST(SceneParse, OverflowingNumberIsRejectedWithItsLine) {
  // nlohmann either refuses 1e999 while parsing or yields infinity; both must be an error on
  // line 4 (the parse error carries no JSON path; the range check does).
  const SceneError e = load_error(kData / "overflow_number.json");
  EXPECT_EQ(e.line(), 4) << e.what();
  const bool parse = e.problem().find("malformed JSON") != std::string::npos;
  const bool range = e.path() == "/material/n" && e.problem().find("finite") != std::string::npos;
  EXPECT_TRUE(parse || range) << e.what();
}

TEST(SceneParse, DeepNestingIsRefusedBeforeParsing) {
  // 100,000 nested arrays (200 KB) crashed the JSON library's recursive value tree; refused
  // with the line of the first bracket past the limit. Brackets inside strings do not count.
  const std::string deep =
      "{\n\"name\": \"[[[[\",\n\"x\": " + std::string(100000, '[') + std::string(100000, ']') + "}";
  try {
    parse_scene(deep, "deep.json", ".");
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.file(), "deep.json");
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(e.problem().find("nested deeper than 64"), std::string::npos) << e.what();
  }
  // At the limit itself the nesting is no error of its own (the scene reader then refuses
  // what it does not know).
  const std::string at_limit = "{\"x\": " + std::string(63, '[') + std::string(63, ']') + "}";
  try {
    parse_scene(at_limit, "limit.json", ".");
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.problem().find("nested deeper"), std::string::npos) << e.what();
  }
}

TEST(SceneParse, ANulByteIsMalformedNotTheEndOfTheFile) {
  // nlohmann's lexer reads a NUL byte as the end of its input: a good scene followed by "\0" and
  // anything loaded without a word (found by review, 2026-12-07). Refused with the NUL's line.
  const std::string good =
      "{\n\"camera\": {\"type\": \"orthographic\", \"extents\": [-2, 2, -2, 2]},\n"
      "\"lights\": [],\n\"meshes\": [{\"generator\": \"quad\"}]\n}\n";
  EXPECT_NO_THROW(parse_scene(good, "good.json", kData));
  const std::string after = good + '\0' + "garbage";
  try {
    parse_scene(after, "nul.json", kData);
    FAIL() << "a scene followed by a NUL byte and garbage loaded";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.file(), "nul.json");
    EXPECT_EQ(e.line(), 6);
    EXPECT_NE(e.problem().find("a NUL byte (0x00) at byte " + std::to_string(good.size() + 1)),
              std::string::npos)
        << e.what();
  }
}

TEST(SceneParse, MissingFileIsAnError) {
  // With the system's reason: "cannot open scene file" alone did not say why (found by review,
  // 2026-12-07).
  const SceneError e = load_error(kData / "no_such_scene.json");
  EXPECT_EQ(e.problem(), "cannot open scene file (No such file or directory)");
  EXPECT_EQ(load_error(kData).problem(), "cannot open scene file (Is a directory)");
}

TEST(SceneParse, AnObjNameTheSystemRefusesIsTheScenesError) {
  // Found by fuzz_scene: a 4,000-character name made std::filesystem throw "File name too long"
  // past the scene reader; it must be a SceneError at the "obj" key's line.
  const std::string text =
      "{\n\"camera\": {\"type\": \"orthographic\", \"extents\": [-1, 1, -1, 1]},\n"
      "\"lights\": [],\n\"meshes\": [\n{\"obj\": \"" +
      std::string(4000, 'A') + ".obj\"}]}";
  try {
    parse_scene(text, "long.json", kData);
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.file(), "long.json");
    EXPECT_EQ(e.line(), 5);
    EXPECT_EQ(e.path(), "/meshes/0/obj");
    EXPECT_NE(e.problem().find("mesh file not found"), std::string::npos) << e.what();
    EXPECT_NE(e.problem().find("too long"), std::string::npos) << e.what();
  }
}

TEST(SceneParse, InlineTextErrorsNameTheGivenFileName) {
  try {
    parse_scene("{\n \"camera\": {\"type\": \"fisheye\"}, \"lights\": [], \"meshes\": []}",
                "inline", ".");
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.file(), "inline");
    EXPECT_EQ(e.path(), "/camera/type");
    EXPECT_EQ(e.line(), 2);
  }
}

TEST(SceneParse, RelativeObjResolvesAgainstTheSceneFolder) {
  const Scene s = load_scene(kData / "good_obj.json");
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.meshes[0].mesh.triangles.size(), 2u);
  EXPECT_EQ(s.material.ka, 0.1);  // defaults are the papers' material
  EXPECT_EQ(s.material.n, 20);
}

TEST(ShippedScenes, AllLoadWithThePapersParameters) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(kScenes)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    const Scene s = load_scene(entry.path());
    ++count;
    EXPECT_EQ(s.material.ka, 0.1);
    EXPECT_EQ(s.material.kd, 0.6);
    EXPECT_EQ(s.material.ks, 0.4);
    EXPECT_EQ(s.material.n, 20);
    for (const auto& l : s.lights) EXPECT_EQ(l.colour, glm::dvec3(1, 1, 1));
    const std::string stem = entry.path().stem().string();
    const auto dash_l = stem.rfind("-l");
    const std::size_t want_lights =
        dash_l == std::string::npos ? 1 : std::stoul(stem.substr(dash_l + 2));
    EXPECT_EQ(s.lights.size(), want_lights);
    const bool tea = stem.rfind("teapot", 0) == 0;
    EXPECT_EQ(s.width, tea ? 640 : 512);
    EXPECT_EQ(s.height, tea ? 480 : 512);
    EXPECT_EQ(s.camera.kind, tea ? CameraKind::Perspective : CameraKind::Orthographic);
  }
  EXPECT_EQ(count, 24);  // 6 scenes × {1, 2, 4, 8} lights
}

TEST(ShippedScenes, TriangleCounts) {
  auto tris = [](const char* f) {
    return load_scene(kScenes / f).meshes.at(0).mesh.triangles.size();
  };
  EXPECT_EQ(tris("sphere-32.json"), 32u);
  EXPECT_EQ(tris("sphere-512.json"), 512u);
  EXPECT_EQ(tris("sphere-40.json"), 40u);
  EXPECT_EQ(tris("dodecahedron-30.json"), 30u);
  EXPECT_EQ(tris("triangle.json"), 1u);
  EXPECT_EQ(tris("teapot.json"), 4032u);
}

TEST(Matrices, OrthographicIsIdentityViewAndEyeLightsAreWorldLights) {
  const Scene s = load_scene(kScenes / "sphere-32.json");
  EXPECT_EQ(view_matrix(s.camera), glm::dmat4(1.0));
  const auto lights = eye_lights(s);
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_EQ(lights[0].kind, LightKind::Point);
  // scenes/README.md: 4·normalize(1, 1.2, 1.5), written with 6 decimals in the file.
  const glm::dvec3 want = 4.0 * glm::normalize(glm::dvec3(1, 1.2, 1.5));
  EXPECT_NEAR(glm::length(lights[0].vector - want), 0, 1e-6);
  EXPECT_TRUE(eye_at_infinity(s.camera));
  // glm::ortho maps the extents onto NDC [-1, 1].
  const glm::dvec4 c = projection_matrix(s.camera, 512, 512) * glm::dvec4(1.25, -1.25, 0, 1);
  EXPECT_NEAR(c.x, 1, 1e-12);
  EXPECT_NEAR(c.y, -1, 1e-12);
}

TEST(Matrices, PerspectiveTeapotLightGoesToEyeSpace) {
  const Scene s = load_scene(kScenes / "teapot.json");
  const auto lights = eye_lights(s);
  const glm::dmat4 v = glm::lookAt(glm::dvec3(0, 1.5, 6), glm::dvec3(0), glm::dvec3(0, 1, 0));
  const glm::dvec3 want =
      glm::normalize(glm::dvec3(v * glm::dvec4(glm::normalize(glm::dvec3(1, 1.5, 1)), 0)));
  EXPECT_NEAR(glm::length(lights.at(0).vector - want), 0, 1e-12);
  EXPECT_FALSE(eye_at_infinity(s.camera));
  // The eye-space origin is the camera position.
  const glm::dvec4 cam = v * glm::dvec4(0, 1.5, 6, 1);
  EXPECT_NEAR(glm::length(glm::dvec3(cam)), 0, 1e-12);
}

// Lines end at "\n", "\r\n" or a lone "\r", as in the OBJ reader: a scene with old Mac line ends
// reported every error on line 1 (found by review, 2026-12-07). The same scene three ways: a
// value out of range on line 5, and a key repeated on line 6 (found by a search from its object's
// line).
TEST(SceneParse, LinesEndAtLfCrLfOrALoneCr) {
  for (const std::string eol : {"\n", "\r\n", "\r"}) {
    SCOPED_TRACE(eol == "\r" ? "CR" : eol == "\n" ? "LF" : "CRLF");
    const auto scene = [&eol](const std::string& material) {
      return "{" + eol + "\"meshes\": [{\"generator\": \"triangle\"}]," + eol +
             "\"camera\": {\"type\": \"orthographic\"}, \"lights\": []," + eol + "\"material\": {" +
             eol + material + "}" + eol + "}";
    };
    try {
      parse_scene(scene("\"ka\": 2"), "eol.json", ".");
      ADD_FAILURE() << "ka = 2 taken";
    } catch (const SceneError& e) {
      EXPECT_EQ(e.line(), 5) << e.what();
      EXPECT_EQ(e.path(), "/material/ka");
    }
    try {
      parse_scene(scene("\"ka\": 0.1," + eol + "\"ka\": 0.2"), "eol.json", ".");
      ADD_FAILURE() << "a key twice taken";
    } catch (const SceneError& e) {
      EXPECT_EQ(e.line(), 6) << e.what();
    }
  }
}
