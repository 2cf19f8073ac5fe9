// Hostile input to the scene, OBJ and image readers, found by review (2026-12-06): each case
// was accepted, misread, misreported or took hours before its fix; each must now be an error
// naming the file, the line where there is one, and the problem. Inputs are generated here.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "host/device_renderer.hpp"
#include "host/image_io.hpp"
#include "host/meshes.hpp"
#include "host/scene.hpp"
#include "host/size_text.hpp"
#include "reader_errors.hpp"

namespace fs = std::filesystem;
using namespace tp::host;

namespace {

SceneError scene_error(const std::string& text) { return test::scene_error(text, "hostile.json"); }

// A valid scene whose camera object also holds `extra` (a member, or "" for none); the camera's
// members start on line 3.
std::string scene_with_camera_member(const std::string& extra) {
  return "{\n\"meshes\": [{\"generator\": \"triangle\"}],\n"
         "\"camera\": {\"type\": \"orthographic\"" +
         (extra.empty() ? "" : ",\n" + extra) + "},\n\"lights\": []}";
}

std::string obj_error(const std::string& text) { return test::obj_error(text, "hostile.obj"); }

const std::string kThreeVertices = "v -1 -1 0\nv 1 -1 0\nv 0 1 0\n";

}  // namespace

TEST(HostileScene, AKeyWithSlashesIsOneEscapedTokenOnItsOwnLine) {
  const SceneError e = scene_error(scene_with_camera_member("\"a/b~c\": 1"));
  EXPECT_EQ(e.path(), "/camera/a~1b~0c");
  EXPECT_EQ(e.line(), 4);
  EXPECT_NE(e.problem().find("unknown key \"a/b~c\""), std::string::npos) << e.problem();
}

// The locator stripped one character per pass for each "/" of an unescaped key: a key of n
// slashes cost n passes over the text, hours for a file at the size limit. Now one token.
TEST(HostileScene, AKeyOfManySlashesIsLocatedInOnePass) {
  const std::string key(200000, '/');
  const SceneError e = scene_error(scene_with_camera_member("\"" + key + "\": 1"));
  EXPECT_EQ(e.line(), 4);
  std::string escaped;
  for (std::size_t i = 0; i < key.size(); ++i) escaped += "~1";
  EXPECT_EQ(e.path(), "/camera/" + escaped);
}

TEST(HostileScene, ANumberTooLargeIsFoundOutsideStrings) {
  // The same token earlier in a string value must not take the line.
  const std::string text =
      "{\n\"name\": \"1e999\",\n"
      "\"meshes\": [{\"generator\": \"triangle\"}],\n"
      "\"camera\": {\"type\": \"orthographic\"},\n\"lights\": [],\n"
      "\"material\": {\"ks\": 1e999}}";
  const SceneError e = scene_error(text);
  EXPECT_EQ(e.line(), 6);
  EXPECT_NE(e.problem().find("1e999"), std::string::npos) << e.problem();
}

TEST(HostileScene, UnsignedIntegersAreReportedAsWritten) {
  const std::string text =
      "{\n\"resolution\": [18446744073709551615, 512],\n"
      "\"meshes\": [{\"generator\": \"triangle\"}],\n"
      "\"camera\": {\"type\": \"orthographic\"},\n\"lights\": []}";
  const SceneError e = scene_error(text);
  EXPECT_EQ(e.line(), 2);
  EXPECT_NE(e.problem().find("value 18446744073709551615 out of range"), std::string::npos)
      << e.problem();
  const std::string budget =
      "{\n\"budget\": 9223372036854775808,\n"
      "\"meshes\": [{\"generator\": \"triangle\"}],\n"
      "\"camera\": {\"type\": \"orthographic\"},\n\"lights\": []}";
  EXPECT_NE(scene_error(budget).problem().find("value 9223372036854775808 out of range"),
            std::string::npos);
  const std::string generator =
      "{\n\"meshes\": [{\"generator\": \"octa-sphere\",\n"
      "\"params\": {\"subdivisions\": 18446744073709551615}}],\n"
      "\"camera\": {\"type\": \"orthographic\"},\n\"lights\": []}";
  EXPECT_NE(scene_error(generator).problem().find("value 18446744073709551615 out of range"),
            std::string::npos)
      << scene_error(generator).problem();
}

TEST(HostileScene, AStringWithANulIsRefused) {
  // The mesh path was cut at the NUL by the operating system: "quad.obj" loaded silently.
  const std::string text =
      "{\n\"meshes\": [{\"obj\": \"quad.obj\\u0000junk\"}],\n"
      "\"camera\": {\"type\": \"orthographic\"},\n\"lights\": []}";
  const SceneError e = scene_error(text);
  EXPECT_EQ(e.path(), "/meshes/0/obj");
  EXPECT_NE(e.problem().find("NUL"), std::string::npos) << e.problem();
}

// tinyobjloader reads indices with atoi: 4294967299 wrapped to 3, 99999999999999999999 to -1 (the
// last vertex), "3abc" was 3, and a relative normal index before the first was "no normal".
TEST(HostileObj, FaceIndicesAreWholeIntegersInRange) {
  const std::pair<std::string, std::string> cases[] = {
      {"f 1 2 4294967299\n", "hostile.obj:4: face refers to vertex 4294967299 but the file has 3"},
      {"f 1 2 -4294967295\n",
       "hostile.obj:4: face corner '-4294967295': vertex index "
       "-4294967295 but only 3 defined before it"},
      {"f 1 2 99999999999999999999\n",
       "hostile.obj:4: face corner '99999999999999999999': "
       "vertex index is not an integer"},
      {"f 1 2 3abc\n", "hostile.obj:4: face corner '3abc': vertex index is not an integer"},
      {"f 1 2 0\n", "hostile.obj:4: face corner '0': vertex index 0 (OBJ counts from 1)"},
      {"vn 0 0 1\nf 1//-2 2//-2 3//-2\n",
       "hostile.obj:5: face corner '1//-2': normal index -2 but only 1 defined before it"},
      {"vn 0 0 1\nf 1//2 2//1 3//1\n", "hostile.obj:5: face refers to normal 2 but the file has 1"},
      {"f 1/1 2/1 3/1\n", "hostile.obj:4: face refers to texture coordinate 1 but the file has 0"},
      {"f 1/1/1/1 2 3\n", "hostile.obj:4: face corner '1/1/1/1' has more than three indices"},
      {"f 1/ 2 3\n", "hostile.obj:4: face corner '1/': texture coordinate index is not an integer"},
  };
  for (const auto& [faces, message] : cases) {
    const std::string error = obj_error(kThreeVertices + faces);
    EXPECT_NE(error.find(message), std::string::npos) << faces << " -> " << error;
  }
  // What stays accepted: a face before the vertices it names, relative indices, "v//vn", a '+'.
  EXPECT_EQ(obj_error("f 1 2 3\n" + kThreeVertices), "");
  EXPECT_EQ(obj_error(kThreeVertices + "f +1 +2 +3\n"), "");
  EXPECT_EQ(obj_error(kThreeVertices + "f -3 -2 -1\n"), "");
  EXPECT_EQ(obj_error(kThreeVertices + "vn 0 0 1\nvt 0 0\nf 1//1 2/1/1 -1/-1/-1\n"), "");
}

// Numbers the scan accepted and tinyobjloader read otherwise: "+-1" became 0, and a long way of
// writing 1 became NaN (then reported as a non-finite coordinate without a line).
TEST(HostileObj, NumbersAreReadAsTheScanReadThem) {
  EXPECT_NE(obj_error("v +-1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n")
                .find("hostile.obj:1: v x '+-1' is not a number"),
            std::string::npos);
  const std::string one = "0." + std::string(449, '0') + "1e450";
  const std::string error = obj_error("v " + one + " -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_NE(error.find("hostile.obj:1: v number 1 is read as nan by the OBJ parser, not as 1"),
            std::string::npos)
      << error;
  EXPECT_NE(obj_error("v 0 0 1e-400\n")
                .find("hostile.obj:1: v z '1e-400' is too small for a "
                      "double"),
            std::string::npos);
  EXPECT_NE(obj_error("v 0 0 -1e999\n").find("hostile.obj:1: v z '-1e999' is not a finite number"),
            std::string::npos);
}

// The scan and tinyobjloader see the same records: words end at spaces and tabs only, and a
// keyword alone on its line is no record (the scan counted "v" and "\fv 0 0 0" as vertices that
// tinyobjloader did not, so its later checks named the wrong lines).
TEST(HostileObj, TheScanSeesTheRecordsTheParserSees) {
  EXPECT_EQ(obj_error("v\n" + kThreeVertices + "f 1 2 3\n"), "");
  EXPECT_NE(obj_error("\fv 0 0 0\n" + kThreeVertices + "f 1 2 4\n")
                .find("hostile.obj:5: face refers to vertex 4 but the file has 3"),
            std::string::npos);
  EXPECT_NE(obj_error("v 1\v2 0 0\n").find("hostile.obj:1: v x '1\\x0b2' is not a number"),
            std::string::npos);
  const std::string normals = obj_error(kThreeVertices + "vn\nvn 0 0 1\nf 1//2 2//2 3//2\n");
  EXPECT_NE(normals.find("hostile.obj:6: face refers to normal 2 but the file has 1"),
            std::string::npos)
      << normals;
}

// Found by review, 2026-12-07: a UTF-8 byte order mark made the first "v" line no record, so
// every index named the next vertex and another mesh rendered without a word; tinyobjloader read
// "v 1" as (1, 0, 0) and "vn 0 1" as (0, 1, 0); and a NUL in a token ended the message there. The
// mark is skipped, a "v" or "vn" record needs its three numbers, and control bytes are shown.
TEST(HostileObj, ByteOrderMarkShortRecordsAndControlBytes) {
  const std::string quad = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n";
  const Mesh plain = parse_obj(quad, "q.obj"), marked = parse_obj("\xEF\xBB\xBF" + quad, "q.obj");
  EXPECT_EQ(marked.positions, plain.positions);
  EXPECT_EQ(marked.triangles, plain.triangles);
  EXPECT_NE(obj_error("v 1\n" + kThreeVertices + "f 2 3 4\n")
                .find("hostile.obj:1: v record with 1 number, not x, y and z"),
            std::string::npos);
  EXPECT_NE(obj_error(kThreeVertices + "vn 0 1\nf 1//1 2//1 3//1\n")
                .find("hostile.obj:4: vn record with 2 numbers, not x, y and z"),
            std::string::npos);
  EXPECT_NE(obj_error(kThreeVertices + "v \nf 1 2 3\n")
                .find("hostile.obj:4: v record with 0 numbers, not x, y and z"),
            std::string::npos);
  const std::string nul = obj_error(kThreeVertices + std::string("f 1 2 3 \0 junk\n", 15));
  EXPECT_NE(nul.find("hostile.obj:4: face corner '\\x00': vertex index is not an integer"),
            std::string::npos)
      << nul;
}

TEST(HostileObj, AZeroNormalIsReportedAtItsRecord) {
  const std::string error = obj_error(kThreeVertices + "vn 0 0 1\nvn 0 0 0\nf 1//1 2//2 3//1\n");
  EXPECT_NE(error.find("hostile.obj:5: a face uses the zero normal of this vn record"),
            std::string::npos)
      << error;
}

TEST(HostileObj, APathThatIsNotARegularFileIsSaidToBeOne) {
  try {
    load_obj(fs::path(TP_HOST_TEST_DATA));
    ADD_FAILURE() << "a directory loaded";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("mesh file is not a regular file"), std::string::npos)
        << e.what();
  }
}

namespace {

std::uint32_t crc32(const std::string& bytes) {  // PNG's chunk CRC (ISO 3309)
  std::uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return c ^ 0xFFFFFFFFu;
}

std::string big_endian(std::uint32_t v) {
  return {static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8),
          static_cast<char>(v)};
}

std::string chunk(const std::string& type, const std::string& data) {
  return big_endian(static_cast<std::uint32_t>(data.size())) + type + data +
         big_endian(crc32(type + data));
}

}  // namespace

// A 57-byte PNG declaring 20000 × 20000 RGB pixels had the reader allocate their 1.2 GB before
// libpng found no pixel data; the declared size is now refused first.
TEST(HostileImage, ADeclaredSizeBeyondTheLimitIsRefusedBeforeReading) {
  std::string ihdr = big_endian(20000) + big_endian(20000);
  ihdr += std::string{8, 2, 0, 0, 0};  // 8 bits, RGB, deflate, adaptive filter, no interlace
  const std::string png = std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) +
                          chunk("IDAT", "") + chunk("IEND", "");
  const fs::path file =
      fs::path(::testing::TempDir()) / ("tp_declares_20000_" + std::to_string(getpid()) + ".png");
  std::ofstream(file, std::ios::binary) << png;
  try {
    (void)read_png(file);
    ADD_FAILURE() << "read";
  } catch (const ImageIoError& e) {
    EXPECT_NE(std::string(e.what()).find("it declares 20000 x 20000 pixels of 3 channels"),
              std::string::npos)
        << e.what();
  }
  fs::remove(file);
}

// A grey image with alpha was read as (grey, alpha, alpha): the third channel's index was
// clamped to the last channel, which is alpha. Grey is replicated, alpha dropped.
TEST(HostileImage, GreyWithAlphaIsGrey) {
  const std::string scanline{0, static_cast<char>(128), static_cast<char>(255)};  // no filter
  // zlib: header, one stored (uncompressed) deflate block, Adler-32 of the data.
  std::uint32_t a = 1, b = 0;
  for (unsigned char c : scanline) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  const auto n = static_cast<char>(scanline.size());
  const std::string zlib = std::string{0x78, 0x01, 0x01, n, 0, static_cast<char>(~n), -1} +
                           scanline + big_endian((b << 16) | a);
  std::string ihdr = big_endian(1) + big_endian(1);
  ihdr += std::string{8, 4, 0, 0, 0};  // 8 bits, grey with alpha
  const std::string png = std::string("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) +
                          chunk("IDAT", zlib) + chunk("IEND", "");
  const fs::path file =
      fs::path(::testing::TempDir()) / ("tp_grey_alpha_" + std::to_string(getpid()) + ".png");
  std::ofstream(file, std::ios::binary) << png;
  const Image8 im = read_png(file);
  EXPECT_EQ(im.width, 1);
  EXPECT_EQ(im.height, 1);
  EXPECT_EQ(im.rgb, (std::vector<std::uint8_t>{128, 128, 128}));
  fs::remove(file);
}

// Found by review (2026-12-06): a 20000 x 20000 renderer (tinyphong-draw --size) allocated its
// 2.75 GB block before the device refused the viewport. The sides are checked first.
TEST(HostileSize, ADeviceBeyondItsViewportIsRefusedBeforeItsBlock) {
  using tp::host::DeviceRenderer;
  for (const auto& [w, h] : std::vector<std::pair<int, int>>{
           {20000, 20000}, {4097, 16}, {16, 4097}, {0, 16}, {16, -1}, {1 << 30, 1 << 30}})
    EXPECT_THROW(DeviceRenderer(w, h), std::invalid_argument) << w << "x" << h;
  EXPECT_NO_THROW(DeviceRenderer(4096, 16));
}

// The --size text of the CLI and the bench programs: two whole numbers in 1..4096.
TEST(HostileSize, SizeTextIsTwoWholeNumbersWithinTheDevice) {
  using tp::host::parse_size;
  const auto s = parse_size("640X480");
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->width, 640);
  EXPECT_EQ(s->height, 480);
  EXPECT_TRUE(parse_size("4096x1").has_value());
  for (const char* bad : {"4294967360x64", "99999999999x64", "64x64junk", "64x64x9", "0x5", "5x0",
                          "4097x5", "x", "", "5", " 5x5", "+5x5", "-5x5", "5x-5", "8192x8192"})
    EXPECT_FALSE(parse_size(bad).has_value()) << bad;
  EXPECT_EQ(tp::host::size_expected("9x"), "expected WIDTHxHEIGHT, each 1..4096, got '9x'");
}

// Found by review, 2026-12-07: a < b as doubles that round to one angle in the device's Q2.29
// passed the scene's check, and the device refused set_material, naming no field. The host
// names it.
TEST(HostileScene, AnglesThatRoundToOneAreRefusedNamingB) {
  const auto with_ab = [](const std::string& a, const std::string& b) {
    return "{\"meshes\": [{\"generator\": \"triangle\"}], \"lights\": [],"
           " \"camera\": {\"type\": \"orthographic\"},"
           " \"material\": {\"a\": " +
           a + ", \"b\": " + b + "}}";
  };
  DeviceRenderer device(64, 64);
  try {
    device.set_scene(parse_scene(with_ab("1.5707963267948", "1.5707963267948966"), "ab.json",
                                 TP_HOST_TEST_DATA));
    ADD_FAILURE() << "the scene was taken";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.path(), "/material/b");
    EXPECT_NE(e.problem().find("b must exceed a by at least that"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(device.set_scene(
      parse_scene(with_ab("0.5", "1.5707963267948966"), "ab.json", TP_HOST_TEST_DATA)));
}

// Found by review, 2026-12-07: the host converted coordinates to Q15.16 (|v| < 2^15), and the
// device, whose bound is 2^14, refused a mesh vertex at 30,000 units naming only
// "upload_vertices at word 235". The host names the vertex and the device's range.
TEST(HostileScene, CoordinatesBeyondTheDevicesRangeAreNamed) {
  const std::filesystem::path dir = ::testing::TempDir();
  std::ofstream(dir / "far.obj") << "v 0 0 0\nv 30000 0 0\nv 0 1 0\nf 1 2 3\n";
  DeviceRenderer device(64, 64);
  try {
    device.set_scene(parse_scene(
        "{\"meshes\": [{\"obj\": \"far.obj\"}], \"lights\": [],"
        " \"camera\": {\"type\": \"orthographic\", \"extents\": [-10000, 10000, -10000, 10000]}}",
        "far.json", dir.string()));
    ADD_FAILURE() << "the scene was taken";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("mesh 0 vertex 1.x = 30000 does not fit the device's "
                                         "coordinates (Q15.16, |v| < 2^14)"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove(dir / "far.obj");
}

// Found by review, 2026-12-07: the renderer sized its block for the layout with a depth buffer,
// and a frame without one, one or two pixels high, needs more (the write counts and the depth
// buffer's one row): kb-adaptive, whose state is the largest, was refused at set_method ("out of
// device memory") at 640x1 and 1x2 (`tinyphong render --no-depth-buffer --size 640x1`). Every
// method, every layout the renderer sets, at those sizes.
TEST(HostileSize, FramesOneOrTwoPixelsHighFitTheirBlockInEveryLayout) {
  for (const auto& [w, h] :
       std::vector<std::pair<int, int>>{{1, 1}, {640, 1}, {4096, 1}, {1, 2}, {3, 2}, {7, 5}}) {
    for (const auto& info : method_names()) {
      for (const int layout : {0, 1, 2}) {  // depth buffer; write counts; a small part's frame
        Scene scene =
            parse_scene("{\"meshes\": [{\"generator\": \"triangle\"}], \"resolution\": [" +
                            std::to_string(w) + ", " + std::to_string(h) +
                            "], \"lights\": [{\"type\": \"point\", \"position\": [0, 0, "
                            "0.05]}], \"camera\": {\"type\": \"orthographic\"}}",
                        "flat.json", TP_HOST_TEST_DATA);
        scene.method = std::string(info.name);
        scene.depth_buffer = layout == 0;
        scene.small_part_frame = layout == 2;
        // Buffers for the mesh alone, as the CLI sizes them (the defaults' 2^17 vertices leave
        // room enough to hide the shortfall).
        std::uint32_t vertices = 0, indices = 0;
        for (const auto& m : scene.meshes) {
          vertices += static_cast<std::uint32_t>(m.mesh.positions.size());
          indices += static_cast<std::uint32_t>(3 * m.mesh.triangles.size());
        }
        DeviceRenderer device(w, h, vertices, indices);
        EXPECT_NO_THROW({
          device.set_scene(scene);
          device.render();
        }) << w
           << "x" << h << " " << info.name << " layout " << layout;
      }
    }
  }
}
