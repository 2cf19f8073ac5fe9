// The stated limits of the scene and OBJ readers (host/scene.hpp, host/meshes.hpp): each one,
// crossed by one, is an error naming the file, the limit and, where there is one, the line;
// at the limit itself the input is accepted. Inputs are generated here, none is committed.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "host/scene.hpp"
#include "reader_errors.hpp"

namespace fs = std::filesystem;
using namespace tp::host;

namespace {

std::string obj_error(const std::string& text) { return test::obj_error(text, "big.obj"); }

std::string repeat(const std::string& line, std::size_t times) {
  std::string out;
  out.reserve(line.size() * times);
  for (std::size_t i = 0; i < times; ++i) out += line;
  return out;
}

SceneError scene_error(const std::string& text) { return test::scene_error(text, "limits.json"); }

// A scene around the given meshes (JSON array elements).
std::string scene_with_meshes(const std::string& meshes) {
  return "{\"camera\": {\"type\": \"orthographic\"}, \"lights\": [],\n\"meshes\": [" + meshes +
         "]}";
}

// A file of `bytes` spaces in the test's temporary folder.
fs::path file_of_size(const std::string& name, std::size_t bytes) {
  const fs::path p = fs::path(::testing::TempDir()) / name;
  std::ofstream(p, std::ios::binary) << std::string(bytes, ' ');
  return p;
}

}  // namespace

TEST(ObjLimits, TrianglesAreCountedToTheLineThatCrossesTheLimit) {
  const std::string head = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  const std::string over = obj_error(head + repeat("f 1 2 3\n", kMaxMeshTriangles + 1));
  EXPECT_NE(over.find("big.obj:" + std::to_string(3 + kMaxMeshTriangles + 1) +
                      ": more than 1048576 triangles (the limit of a mesh)"),
            std::string::npos)
      << over;
  // A polygon counts as its triangles (corners - 2): a 6-gon past the limit by 3.
  const std::string polygon =
      obj_error(head + repeat("f 1 2 3\n", kMaxMeshTriangles - 1) + "f 1 2 3 1 2 3\n");
  EXPECT_NE(polygon.find("more than 1048576 triangles"), std::string::npos) << polygon;
}

TEST(ObjLimits, VerticesAreCountedToTheLineThatCrossesTheLimit) {
  const std::string over = obj_error(repeat("v 0 0 0\n", kMaxMeshVertices + 1));
  EXPECT_NE(over.find("big.obj:" + std::to_string(kMaxMeshVertices + 1) +
                      ": more than 1048576 vertices (the limit of a mesh)"),
            std::string::npos)
      << over;
}

TEST(ObjLimits, LongLinesAreRefusedWithTheirLine) {
  const std::string text = "v 0 0 0\nv 1 0 0 # " + std::string(kMaxObjLineBytes, 'x') + "\n";
  const std::string e = obj_error(text);
  EXPECT_NE(e.find("big.obj:2: line longer than 4096 bytes"), std::string::npos) << e;
  // Exactly at the limit the line is read.
  const std::string at =
      "v 0 0 0 #" + std::string(kMaxObjLineBytes - 9, 'x') + "\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  EXPECT_EQ(obj_error(at), "");
}

TEST(ObjLimits, LargeFilesAreRefusedBeforeTheyAreRead) {
  const fs::path big = file_of_size("big.obj", kMaxObjFileBytes + 1);
  try {
    load_obj(big);
    FAIL() << "a file over the limit loaded";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find(big.string() +
                                         ": larger than 67108864 bytes (the limit of an OBJ file)"),
              std::string::npos)
        << e.what();
  }
  fs::remove(big);
}

TEST(ObjLimits, NumbersBeyondSinglePrecisionAreRefusedWithTheirLine) {
  // tinyobjloader stores floats: 1e300 would become infinity after the check for finite numbers.
  const std::string e = obj_error("v 0 0 0\nv 1e300 0 0\n");
  EXPECT_NE(e.find("big.obj:2: v '1e300' is beyond the single-precision range"), std::string::npos)
      << e;
}

TEST(ObjLimits, LinesEndAtCrLfOrALoneCrAsInTinyobjloader) {
  // A lone CR ends a line for tinyobjloader, so it does for the scan too: the second record
  // is checked, and reported on line 2.
  const std::string e = obj_error("v 0 0 0\rv nan 0 0\r");
  EXPECT_NE(e.find("big.obj:2: v x 'nan'"), std::string::npos) << e;
  EXPECT_EQ(parse_obj("v 0 0 0\rv 1 0 0\r\nv 0 1 0\rf 1 2 3\r", "cr.obj").triangles.size(), 1u);
}

TEST(SceneLimits, LargeFilesAreRefusedWholeNotInPart) {
  const SceneError text = scene_error(std::string(kMaxSceneFileBytes + 1, ' '));
  EXPECT_EQ(text.file(), "limits.json");
  EXPECT_EQ(text.problem(), "larger than 1048576 bytes (the limit of a scene file)");
  const fs::path big = file_of_size("big.json", kMaxSceneFileBytes + 1);
  try {
    load_scene(big);
    FAIL() << "a file over the limit loaded";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.file(), big.string());
    EXPECT_EQ(e.problem(), "larger than 1048576 bytes (the limit of a scene file)");
  }
  fs::remove(big);
}

TEST(SceneLimits, MeshCount) {
  const std::string triangle = "{\"generator\": \"triangle\"}";
  std::string at_limit = triangle;
  for (std::size_t i = 1; i < kMaxSceneMeshes; ++i) at_limit += ", " + triangle;
  EXPECT_EQ(parse_scene(scene_with_meshes(at_limit), "ok.json", ".").meshes.size(),
            kMaxSceneMeshes);
  const SceneError e = scene_error(scene_with_meshes(at_limit + ", " + triangle));
  EXPECT_EQ(e.path(), "/meshes");
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.problem(), "at most 64 meshes, got 65");
}

TEST(SceneLimits, TrianglesOfAllMeshesTogether) {
  // Each 512 x 512 UV sphere has 523,264 triangles: two fit in 2^20, the third crosses it.
  const std::string sphere =
      "{\"generator\": \"uv-sphere\", \"params\": {\"slices\": 512, \"stacks\": 512}}";
  const SceneError e = scene_error(scene_with_meshes(sphere + ",\n" + sphere + ",\n" + sphere));
  EXPECT_EQ(e.path(), "/meshes/2");
  EXPECT_EQ(e.line(), 4);
  EXPECT_EQ(e.problem(),
            "the meshes have 1569792 triangles together, more than 1048576 (the limit of a scene)");
}

TEST(SceneLimits, ResolutionIsTheDevicesViewport) {
  const SceneError e = scene_error(
      "{\"resolution\": [4097, 16], \"camera\": {\"type\": \"orthographic\"}, \"lights\": [], "
      "\"meshes\": [{\"generator\": \"triangle\"}]}");
  EXPECT_EQ(e.path(), "/resolution/0");
  EXPECT_EQ(e.problem(), "value 4097 out of range [1, 4096]");
}

TEST(ObjRecords, SkinWeightsAndTagsAreDroppedBeforeParsing) {
  // tinyobjloader converted a skin weight's joint id of 1e30 from float to int (undefined
  // behaviour, found by fuzzing) and sizes vectors from a tag's counts; the mesh uses neither.
  const Mesh m = parse_obj(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nvw 1 1e30 0.5\nt crease 999999999/0/0 1\nf 1 2 3\n", "w.obj");
  EXPECT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.positions.size(), 3u);
}
