// OBJ files: a scan of our own for the limits and the numbers (file:line errors), then
// tinyobjloader for the structure, then one mesh vertex per distinct (position, normal) pair.
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>

#include <tiny_obj_loader.h>

#include "host/meshes.hpp"
#include "host/text_file.hpp"

namespace tp::host {

namespace {

[[noreturn]] void refuse(const std::string& where, const std::string& problem) {
  throw MeshError("malformed OBJ " + where + ": " + problem);
}

std::string at_line(const std::string& file, std::size_t line) {
  return file + ":" + std::to_string(line);
}

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\v' || c == '\f'; }

// The next whitespace-separated word of `line` from `pos` on ("" at the end).
std::string_view next_word(std::string_view line, std::size_t& pos) {
  while (pos < line.size() && is_blank(line[pos])) ++pos;
  const std::size_t begin = pos;
  while (pos < line.size() && !is_blank(line[pos])) ++pos;
  return line.substr(begin, pos - begin);
}

// tinyobjloader reads a token that is not a number ("nan", "inf", "1e999", "x") as 0 or as
// infinity without a word, and stores single-precision floats (1e300 becomes infinity), so each
// number of a vertex record must be a finite double within the float range here.
void check_numbers(std::string_view record, std::string_view line, std::size_t pos,
                   const std::string& where) {
  static constexpr const char* kFields[] = {"x", "y", "z", "w"};
  for (int k = 0;; ++k) {
    const std::string_view token = next_word(line, pos);
    if (token.empty() || token[0] == '#') return;
    double value = 0;
    const char* begin = token.data() + (token[0] == '+' ? 1 : 0);  // from_chars takes no '+'
    const char* end = token.data() + token.size();
    const auto [ptr, ec] = std::from_chars(begin, end, value);
    if (ec != std::errc() || ptr != end || !std::isfinite(value)) {
      const std::string field = k < 4 ? kFields[k] : "value " + std::to_string(k + 1);
      refuse(where, std::string(record) + " " + field + " '" + std::string(token.substr(0, 32)) +
                        "' is not a finite number");
    }
    if (std::abs(value) > std::numeric_limits<float>::max())
      refuse(where, std::string(record) + " '" + std::string(token.substr(0, 32)) +
                        "' is beyond the single-precision range OBJ numbers are read in");
  }
}

// Triangles a face record makes once triangulated: corners - 2.
std::size_t face_triangles(std::string_view line, std::size_t pos) {
  std::size_t corners = 0;
  for (std::string_view w = next_word(line, pos); !w.empty() && w[0] != '#';
       w = next_word(line, pos))
    ++corners;
  return corners >= 3 ? corners - 2 : 0;
}

// Counts of the records seen so far, against the limits.
struct Tally {
  std::size_t positions = 0, triangles = 0;
};

// Records a mesh does not use whose parsing in tinyobjloader trusts the file's numbers: skin
// weights ("vw": a joint id beyond int converted from float, undefined behaviour; found by
// fuzzing) and tags ("t": counts sized into vectors). They are dropped before parsing.
bool dropped(std::string_view record) { return record == "vw" || record == "t"; }

// Checks one line; returns whether tinyobjloader is not to see it (dropped()).
bool check_line(std::string_view line, const std::string& where, Tally& tally) {
  if (line.size() > kMaxObjLineBytes)
    refuse(where, "line longer than " + std::to_string(kMaxObjLineBytes) +
                      " bytes (the limit of an OBJ line)");
  std::size_t pos = 0;
  const std::string_view record = next_word(line, pos);
  if (record == "v" || record == "vn" || record == "vt") check_numbers(record, line, pos, where);
  if (record == "v" && ++tally.positions > kMaxMeshVertices)
    refuse(where,
           "more than " + std::to_string(kMaxMeshVertices) + " vertices (the limit of a mesh)");
  if (record == "f") {
    tally.triangles += face_triangles(line, pos);
    if (tally.triangles > kMaxMeshTriangles)
      refuse(where,
             "more than " + std::to_string(kMaxMeshTriangles) + " triangles (the limit of a mesh)");
  }
  return dropped(record);
}

// Every line before tinyobjloader sees the text. Lines end at "\n", "\r\n" or a lone "\r", as
// tinyobjloader splits them, so that no record escapes the scan. Returns the text for
// tinyobjloader: the same, with the dropped records blanked (line numbers unchanged).
std::string scan_lines(std::string_view text, const std::string& file) {
  std::string for_parser(text);
  Tally tally;
  std::size_t number = 0;
  for (std::size_t start = 0; start < text.size();) {
    std::size_t end = text.find_first_of("\r\n", start);
    if (end == std::string_view::npos) end = text.size();
    if (check_line(text.substr(start, end - start), at_line(file, ++number), tally))
      for_parser.replace(start, end - start, end - start, ' ');
    start = end + (text.compare(end, 2, "\r\n") == 0 ? 2 : 1);
  }
  return for_parser;
}

glm::dvec3 unit_normal(const tinyobj::attrib_t& attrib, int normal_index, const std::string& file) {
  if (normal_index < 0) return glm::dvec3(0, 0, 1);  // replaced by compute_normals
  const auto ni = static_cast<std::size_t>(3 * normal_index);
  const glm::dvec3 n(attrib.normals[ni], attrib.normals[ni + 1], attrib.normals[ni + 2]);
  if (!(glm::length(n) > 0)) refuse(file, "zero normal");
  return glm::normalize(n);
}

// OBJ indexes positions and normals separately; one mesh vertex per distinct pair.
Mesh build_mesh(const tinyobj::ObjReader& reader, const std::string& file) {
  const auto& attrib = reader.GetAttrib();
  Mesh m;
  bool missing_normals = false;
  std::map<std::pair<int, int>, std::uint32_t> index;
  const auto nv = static_cast<int>(attrib.vertices.size() / 3);
  const auto nn = static_cast<int>(attrib.normals.size() / 3);
  for (const auto& shape : reader.GetShapes()) {
    const auto& ids = shape.mesh.indices;
    for (std::size_t f = 0; f + 2 < ids.size(); f += 3) {
      std::array<std::uint32_t, 3> tri{};
      for (std::size_t k = 0; k < 3; ++k) {
        const auto& id = ids[f + k];
        if (id.vertex_index < 0 || id.vertex_index >= nv)
          refuse(file, "face refers to a missing vertex");
        if (id.normal_index >= nn) refuse(file, "face refers to a missing normal");
        if (id.normal_index < 0) missing_normals = true;
        auto it = index.find({id.vertex_index, id.normal_index});
        if (it == index.end()) {
          const auto vi = static_cast<std::size_t>(3 * id.vertex_index);
          m.positions.emplace_back(attrib.vertices[vi], attrib.vertices[vi + 1],
                                   attrib.vertices[vi + 2]);
          m.normals.push_back(unit_normal(attrib, id.normal_index, file));
          const auto added = static_cast<std::uint32_t>(m.positions.size() - 1);
          it = index.emplace(std::make_pair(id.vertex_index, id.normal_index), added).first;
        }
        tri[k] = it->second;
      }
      m.triangles.push_back(tri);
    }
  }
  if (missing_normals) compute_normals(m);
  return m;
}

}  // namespace

Mesh parse_obj(std::string_view text, const std::string& file) {
  const std::string for_parser = scan_lines(text, file);
  tinyobj::ObjReaderConfig cfg;
  cfg.triangulate = true;
  cfg.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromString(for_parser, "", cfg)) refuse(file, reader.Error());
  Mesh m = build_mesh(reader, file);
  if (m.triangles.empty()) refuse(file, "no faces");
  // One vertex per distinct (position, normal) pair: up to three per triangle, more than the
  // file's "v" records, which the scan counted.
  if (m.positions.size() > kMaxMeshVertices)
    refuse(file, std::to_string(m.positions.size()) +
                     " distinct (position, normal) pairs, more than " +
                     std::to_string(kMaxMeshVertices) + " vertices (the limit of a mesh)");
  if (m.triangles.size() > kMaxMeshTriangles)
    refuse(file,
           "more than " + std::to_string(kMaxMeshTriangles) + " triangles (the limit of a mesh)");
  for (const auto& p : m.positions)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      refuse(file, "non-finite coordinate");
  return m;
}

Mesh load_obj(const std::filesystem::path& file) {
  std::error_code ec;  // a name the OS refuses is a MeshError, not a filesystem_error
  if (!std::filesystem::is_regular_file(file, ec))
    throw MeshError("mesh file not found: " + file.string() +
                    (ec ? " (" + ec.message() + ")" : std::string()));
  std::string text;
  switch (read_text_file(file, kMaxObjFileBytes, text)) {
    case ReadResult::ok: break;
    case ReadResult::cannot_open: throw MeshError("cannot read mesh file " + file.string());
    case ReadResult::too_large:
      refuse(file.string(), "larger than " + std::to_string(kMaxObjFileBytes) +
                                " bytes (the limit of an OBJ file)");
  }
  return parse_obj(text, file.string());
}

}  // namespace tp::host
