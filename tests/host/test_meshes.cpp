// Generators: triangle counts, closedness (every edge shared by exactly two triangles, in
// opposite directions), outward CCW faces and unit outward normals; the teapot; OBJ files.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <utility>

#include "host/meshes.hpp"

using namespace tp::host;

namespace {

// Directed edge counts: closed and consistently oriented iff every directed edge occurs once
// and its reverse occurs once.
::testing::AssertionResult closed_and_oriented(const Mesh& m) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k)
      ++directed[{t[static_cast<std::size_t>(k)], t[static_cast<std::size_t>((k + 1) % 3)]}];
  for (const auto& [e, n] : directed) {
    if (n != 1) return ::testing::AssertionFailure() << "edge used " << n << " times one way";
    if (!directed.count({e.second, e.first}))
      return ::testing::AssertionFailure()
             << "edge " << e.first << "-" << e.second << " is a border";
  }
  return ::testing::AssertionSuccess();
}

void expect_outward_unit_sphere(const Mesh& m) {
  ASSERT_EQ(m.positions.size(), m.normals.size());
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    EXPECT_NEAR(glm::length(m.positions[i]), 1, 1e-12);
    EXPECT_NEAR(glm::length(m.normals[i] - m.positions[i]), 0, 1e-12);  // normal = position
  }
  for (const auto& t : m.triangles) {
    const glm::dvec3 a = m.positions[t[0]], b = m.positions[t[1]], c = m.positions[t[2]];
    EXPECT_GT(glm::dot(glm::cross(b - a, c - a), a + b + c), 0) << "face not CCW from outside";
  }
}

}  // namespace

TEST(Generators, OctaSphere32And512) {
  for (auto [s, n] : {std::pair{1, 32u}, std::pair{3, 512u}}) {
    const Mesh m = octa_sphere(s);
    EXPECT_EQ(m.triangles.size(), n);
    EXPECT_TRUE(closed_and_oriented(m));
    expect_outward_unit_sphere(m);
    // Euler: V − E + F = 2 with E = 3F/2.
    EXPECT_EQ(m.positions.size(), n / 2 + 2);
  }
}

TEST(Generators, UvSphere5x5Has40Triangles) {
  const Mesh m = uv_sphere(5, 5);
  EXPECT_EQ(m.triangles.size(), 40u);
  EXPECT_TRUE(closed_and_oriented(m));
  expect_outward_unit_sphere(m);
}

TEST(Generators, Dodecahedron30IsAClosed30TriangleSphere) {
  const Mesh m = coarse_sphere_30();
  EXPECT_EQ(m.triangles.size(), 30u);
  EXPECT_EQ(m.positions.size(), 17u);
  EXPECT_TRUE(closed_and_oriented(m));
  expect_outward_unit_sphere(m);
}

TEST(Generators, BigTriangle) {
  const Mesh m = big_triangle();
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.positions[0], glm::dvec3(-1, -0.9, 0));
  EXPECT_EQ(m.positions[2], glm::dvec3(0, 1, 0));
  EXPECT_NEAR(glm::length(m.normals[1] - glm::normalize(glm::dvec3(0.6, -0.54, 1))), 0, 1e-15);
  const auto& t = m.triangles[0];
  EXPECT_GT(
      glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]).z,
      0);
}

TEST(Generators, UnknownNamesAndParametersAreRejected) {
  EXPECT_THROW(generate_mesh("cube", nlohmann::json::object()), MeshError);
  EXPECT_THROW(generate_mesh("octa-sphere", {{"subdivision", 1}}), MeshError);  // typo
  EXPECT_THROW(generate_mesh("octa-sphere", {{"subdivisions", 1.5}}), MeshError);
  EXPECT_THROW(generate_mesh("uv-sphere", {{"slices", 2}}), MeshError);
  EXPECT_EQ(generate_mesh("octa-sphere", {{"subdivisions", 0}}).triangles.size(), 8u);
}

TEST(Teapot, FacetCountFollowsThePatchStructure) {
  EXPECT_EQ(teapot_triangle_count(8), 4032);  // 32·128 − 8 pole patches·8
  for (int tess : {2, 8}) {
    const Mesh m = teapot(tess);
    EXPECT_EQ(static_cast<int>(m.triangles.size()), teapot_triangle_count(tess));
  }
}

TEST(Teapot, NormalsAreUnitAndFacesAgreeWithThem) {
  const Mesh m = teapot(8);
  for (const auto& n : m.normals) EXPECT_NEAR(glm::length(n), 1, 1e-12);
  int disagree = 0;
  for (const auto& t : m.triangles) {
    const glm::dvec3 g =
        glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
    EXPECT_GT(glm::length(g), 0);
    for (auto v : t) disagree += glm::dot(g, m.normals[v]) <= 0;
  }
  // Vertex normals on a smooth surface face the same side as the facets around them; only at
  // sharp features (spout tip, handle joins) can a corner disagree. Measured 0 with tess 8
  // (host_meshes_test); allow none.
  EXPECT_EQ(disagree, 0);
}

TEST(Teapot, NormalsPointOutward) {
  const Mesh m = teapot(8);
  // y-up, bottom at y = 0, lid top at 3.15, body radius 2 at y = 0.9 .. 1.35.
  int body = 0, lid = 0, bottom = 0;
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const glm::dvec3 p = m.positions[i], n = m.normals[i];
    const double r = std::hypot(p.x, p.z);
    if (p.y > 0.5 && p.y < 2.2 && r > 1.7 && std::abs(p.x) < 1.6) {  // body, away from spout/handle
      EXPECT_GT(glm::dot(glm::dvec3(p.x, 0, p.z), n), 0) << "body normal points inward";
      ++body;
    }
    if (p.y > 3.1 && r < 0.3) {  // top of the knob (it bulges to r = 0.36 at y = 3.05)
      EXPECT_GT(n.y, 0) << "lid-top normal points down";
      ++lid;
    }
    if (p.y < 0.02 && r < 1.3) {  // the nearly flat bottom
      EXPECT_LT(n.y, 0) << "bottom normal points up";
      ++bottom;
    }
  }
  EXPECT_GT(body, 50);
  EXPECT_GT(lid, 5);
  EXPECT_GT(bottom, 5);
}

TEST(Obj, LoadsTheShippedQuad) {
  const Mesh m = load_obj(std::string(TP_SCENES_DIR) + "/quad.obj");
  ASSERT_EQ(m.triangles.size(), 2u);
  ASSERT_EQ(m.positions.size(), 4u);
  for (const auto& n : m.normals) EXPECT_EQ(n, glm::dvec3(0, 0, 1));
}

TEST(Obj, ComputesMissingNormalsAndRejectsBadFiles) {
  const std::string data = TP_HOST_TEST_DATA;
  EXPECT_THROW(load_obj(data + "/bad.obj"), MeshError);
  EXPECT_THROW(load_obj(data + "/nothing_here.obj"), MeshError);
  // A name the OS refuses is a MeshError too, not an escaping filesystem_error.
  EXPECT_THROW(load_obj(data + "/" + std::string(4000, 'A') + ".obj"), MeshError);
}

TEST(Obj, NonFiniteNumbersNameFileLineAndField) {
  // tinyobjloader alone read "nan" as 0 and rendered the mesh without a word.
  const std::string data = TP_HOST_TEST_DATA;
  const std::pair<const char*, const char*> cases[] = {
      {"/nan_vertex.obj", "nan_vertex.obj:3: v x 'nan' is not a finite number"},
      {"/inf_normal.obj", "inf_normal.obj:6: vn z 'inf' is not a finite number"},
      {"/huge_vertex.obj", "huge_vertex.obj:4: v y '1e999' is not a finite number"},
  };
  // What the check must not refuse: CRLF line ends, a leading '+', a trailing comment.
  EXPECT_EQ(load_obj(data + "/crlf_plus.obj").triangles.size(), 1u);
  for (const auto& [file, message] : cases) {
    try {
      load_obj(data + file);
      ADD_FAILURE() << file << " loaded";
    } catch (const MeshError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
}

// A file that gives normals on some faces only keeps them, and only the corners without one get
// the faces' mean: all of them were replaced (found by review, 2026-12-07). A square folded along
// its diagonal (1, 3): the face 1 2 3 in z = 0, the face 1 3 4 tilted up toward vertex 4.
TEST(Obj, KeepsTheNormalsAFileGivesAndComputesOnlyTheMissingOnes) {
  const Mesh m = parse_obj(
      "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 1\n"
      "vn 0.6 0 0.8\nvn -0.6 0 0.8\n"
      "f 1//1 2//2 3//2\nf 1 3 4\n",
      "mixed.obj");
  ASSERT_EQ(m.triangles.size(), 2u);
  ASSERT_EQ(m.positions.size(), 6u);  // three corners with normals, three without
  const auto& first = m.triangles[0];
  // (the file's numbers are read in single precision)
  EXPECT_NEAR(glm::length(m.normals[first[0]] - glm::dvec3(0.6, 0, 0.8)), 0, 1e-6);
  EXPECT_NEAR(glm::length(m.normals[first[1]] - glm::dvec3(-0.6, 0, 0.8)), 0, 1e-6);
  EXPECT_NEAR(glm::length(m.normals[first[2]] - glm::dvec3(-0.6, 0, 0.8)), 0, 1e-6);
  // The second face's corners: at 1 and 3 the area-weighted mean of both faces (each face's
  // cross product is twice its area times its normal), at 4 the second face's normal alone.
  const glm::dvec3 p1(-1, -1, 0), p2(1, -1, 0), p3(1, 1, 0), p4(-1, 1, 1);
  const glm::dvec3 a = glm::cross(p2 - p1, p3 - p1), b = glm::cross(p3 - p1, p4 - p1);
  const auto& second = m.triangles[1];
  EXPECT_NEAR(glm::length(m.normals[second[0]] - glm::normalize(a + b)), 0, 1e-12);
  EXPECT_NEAR(glm::length(m.normals[second[1]] - glm::normalize(a + b)), 0, 1e-12);
  EXPECT_NEAR(glm::length(m.normals[second[2]] - glm::normalize(b)), 0, 1e-12);
}

TEST(Obj, NormalsFromGeometryWhenAbsent) {
  Mesh m = octa_sphere(1);
  compute_normals(m);
  // Area-weighted normals of the 1× subdivided octahedron: at the 6 original vertices by
  // symmetry exactly the position.
  for (std::size_t i = 0; i < 6; ++i)
    EXPECT_NEAR(glm::length(m.normals[i] - m.positions[i]), 0, 1e-12);
}
