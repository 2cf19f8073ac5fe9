// OBJ files: a scan of our own for the limits and the numbers (file:line errors), then
// tinyobjloader for the structure, then one mesh vertex per distinct (position, normal) pair.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include <tiny_obj_loader.h>

#include "host/meshes.hpp"
#include "host/quote_token.hpp"
#include "host/text_file.hpp"

namespace tp::host {

namespace {

[[noreturn]] void refuse(const std::string& where, const std::string& problem) {
  throw MeshError("malformed OBJ " + where + ": " + problem);
}

std::string at_line(const std::string& file, std::size_t line) {
  return file + ":" + std::to_string(line);
}

// How much of a token an error quotes (host/quote_token.hpp).
constexpr std::size_t kQuotedBytes = 32;

// tinyobjloader separates words by spaces and tabs only; so does the scan, so that both see the
// same records ("\fv 1 2 3" is none) and the same numbers ("1\v2" is one word, not a number).
bool is_blank(char c) { return c == ' ' || c == '\t'; }

// The next whitespace-separated word of `line` from `pos` on ("" at the end).
std::string_view next_word(std::string_view line, std::size_t& pos) {
  while (pos < line.size() && is_blank(line[pos])) ++pos;
  const std::size_t begin = pos;
  while (pos < line.size() && !is_blank(line[pos])) ++pos;
  return line.substr(begin, pos - begin);
}

// The numbers of one "v" or "vn" record as this scan read them, and the record's line: what
// tinyobjloader reads must be the same numbers (compare_numbers).
struct Record {
  std::array<double, 3> values{};
  int count = 0;  // numbers read, at most the three compared
  std::size_t line = 0;
};

// tinyobjloader reads a token that is not a number ("nan", "inf", "1e999", "x") as 0 or as
// infinity without a word, and stores single-precision floats (1e300 becomes infinity), so each
// number of a vertex record must be a finite double within the float range here.
Record check_numbers(std::string_view record, std::string_view line, std::size_t pos,
                     const std::string& where) {
  static constexpr const char* kFields[] = {"x", "y", "z", "w"};
  Record read;
  for (int k = 0;; ++k) {
    const std::string_view token = next_word(line, pos);
    if (token.empty() || token[0] == '#') return read;
    // The record, field and token for an error; built only when there is one (a mesh has
    // millions of numbers).
    const auto named = [&] {
      return std::string(record) + " " +
             (k < 4 ? std::string(kFields[k]) : "value " + std::to_string(k + 1)) + " " +
             quote_token(token, kQuotedBytes);
    };
    double value = 0;
    // from_chars takes no '+'; one sign at most ("+-1" is no number).
    const char* begin =
        token.data() +
        (token[0] == '+' && token.size() > 1 && token[1] != '-' && token[1] != '+' ? 1 : 0);
    const char* end = token.data() + token.size();
    const auto [ptr, ec] = std::from_chars(begin, end, value);
    if (ec == std::errc::result_out_of_range) {  // overflow (1e999) or underflow (1e-400)
      const bool overflow = std::isinf(std::strtod(std::string(token).c_str(), nullptr));
      refuse(where,
             named() + (overflow ? " is not a finite number" : " is too small for a double"));
    }
    if (ec != std::errc() || ptr != end) refuse(where, named() + " is not a number");
    if (!std::isfinite(value)) refuse(where, named() + " is not a finite number");
    if (std::abs(value) > std::numeric_limits<float>::max())
      refuse(where, std::string(record) + " " + quote_token(token, kQuotedBytes) +
                        " is beyond the single-precision range OBJ numbers are read in");
    if (k < 3) read.values[static_cast<std::size_t>(read.count++)] = value;
  }
}

// What the scan has seen so far: counts against the limits, the numbers of every "v" and "vn"
// record, and the largest positive index of each kind that a face used, with its line (a face
// may name a vertex defined further down, so positive indices are checked at the end).
struct Tally {
  std::size_t positions = 0, triangles = 0;
  std::array<std::size_t, 3> defined{};       // "v", "vt", "vn" records so far
  std::array<long long, 3> largest{};         // largest positive index per kind
  std::array<std::size_t, 3> largest_line{};  // the line where it first appeared
  std::vector<Record> vertices, normals;
};

constexpr const char* kIndexKinds[] = {"vertex", "texture coordinate", "normal"};

// One corner of a face, "v", "v/vt", "v//vn" or "v/vt/vn": every index a whole integer, not zero,
// a negative one within the records before it (OBJ: -1 is the last so far). tinyobjloader reads
// them with atoi, which wraps or stops silently, so they are checked here.
void check_corner(std::string_view corner, std::size_t line, const std::string& where,
                  Tally& tally) {
  std::size_t kind = 0;
  for (std::size_t start = 0;; ++kind) {
    const std::size_t slash = corner.find('/', start);
    const std::string_view field = corner.substr(
        start, slash == std::string_view::npos ? std::string_view::npos : slash - start);
    if (kind > 2)
      refuse(where,
             "face corner " + quote_token(corner, kQuotedBytes) + " has more than three indices");
    const bool may_be_empty = kind == 1 && slash != std::string_view::npos;  // "v//vn"
    if (!(field.empty() && may_be_empty)) {
      long long index = 0;
      // atoi, which tinyobjloader uses, takes one '+'; from_chars takes none.
      const bool plus = field.size() > 1 && field[0] == '+' && field[1] != '+' && field[1] != '-';
      const auto [ptr, ec] =
          std::from_chars(field.data() + (plus ? 1 : 0), field.data() + field.size(), index);
      // "face corner '…': vertex index", built only for an error.
      const auto named = [&] {
        return "face corner " + quote_token(corner, kQuotedBytes) + ": " + kIndexKinds[kind] +
               " index";
      };
      if (ec != std::errc() || ptr != field.data() + field.size())
        refuse(where, named() + " is not an integer");
      if (index == 0) refuse(where, named() + " 0 (OBJ counts from 1)");
      if (index < 0 && static_cast<unsigned long long>(-(index + 1)) >= tally.defined[kind])
        refuse(where, named() + " " + std::to_string(index) + " but only " +
                          std::to_string(tally.defined[kind]) + " defined before it");
      if (index > tally.largest[kind]) {
        tally.largest[kind] = index;
        tally.largest_line[kind] = line;
      }
    }
    if (slash == std::string_view::npos) return;
    start = slash + 1;
  }
}

// Checks a face's corners; returns the triangles it makes once triangulated: corners - 2.
std::size_t check_face(std::string_view line, std::size_t pos, std::size_t line_number,
                       const std::string& where, Tally& tally) {
  std::size_t corners = 0;
  for (std::string_view w = next_word(line, pos); !w.empty() && w[0] != '#';
       w = next_word(line, pos)) {
    check_corner(w, line_number, where, tally);
    ++corners;
  }
  return corners >= 3 ? corners - 2 : 0;
}

// Records a mesh does not use whose parsing in tinyobjloader trusts the file's numbers: skin
// weights ("vw": a joint id beyond int converted from float, undefined behaviour; found by
// fuzzing) and tags ("t": counts sized into vectors). They are dropped before parsing.
bool dropped(std::string_view record) { return record == "vw" || record == "t"; }

// Checks one line; returns whether tinyobjloader is not to see it (dropped()).
bool check_line(std::string_view line, std::size_t line_number, const std::string& where,
                Tally& tally) {
  if (line.size() > kMaxObjLineBytes)
    refuse(where, "line longer than " + std::to_string(kMaxObjLineBytes) +
                      " bytes (the limit of an OBJ line)");
  std::size_t pos = 0;
  std::string_view record = next_word(line, pos);
  // tinyobjloader reads a record only when a space or tab follows its keyword: a lone "v" is none.
  if (pos == line.size()) record = {};
  if (record == "v" || record == "vn" || record == "vt") {
    Record read = check_numbers(record, line, pos, where);
    read.line = line_number;
    // tinyobjloader reads a missing coordinate as 0: "v 1" would be the point (1, 0, 0).
    if (record != "vt" && read.count < 3)
      refuse(where, std::string(record) + " record with " + std::to_string(read.count) +
                        (read.count == 1 ? " number" : " numbers") + ", not x, y and z");
    const std::size_t kind = record == "v" ? 0 : record == "vt" ? 1 : 2;
    ++tally.defined[kind];
    if (kind == 0) tally.vertices.push_back(read);
    if (kind == 2) tally.normals.push_back(read);
  }
  if (record == "v" && ++tally.positions > kMaxMeshVertices)
    refuse(where,
           "more than " + std::to_string(kMaxMeshVertices) + " vertices (the limit of a mesh)");
  if (record == "f") {
    tally.triangles += check_face(line, pos, line_number, where, tally);
    if (tally.triangles > kMaxMeshTriangles)
      refuse(where,
             "more than " + std::to_string(kMaxMeshTriangles) + " triangles (the limit of a mesh)");
  }
  return dropped(record);
}

// Every line before tinyobjloader sees the text. Lines end at "\n", "\r\n" or a lone "\r", as
// tinyobjloader splits them, so that no record escapes the scan. Returns the text for
// tinyobjloader: the same, with the dropped records blanked (line numbers unchanged).
std::string scan_lines(std::string_view text, const std::string& file, Tally& tally) {
  std::string for_parser(text);
  std::size_t number = 0;
  for (std::size_t start = 0; start < text.size();) {
    std::size_t end = text.find_first_of("\r\n", start);
    if (end == std::string_view::npos) end = text.size();
    ++number;
    if (check_line(text.substr(start, end - start), number, at_line(file, number), tally))
      for_parser.replace(start, end - start, end - start, ' ');
    start = end + (text.compare(end, 2, "\r\n") == 0 ? 2 : 1);
  }
  for (std::size_t kind = 0; kind < 3; ++kind)
    if (static_cast<unsigned long long>(tally.largest[kind]) > tally.defined[kind])
      refuse(at_line(file, tally.largest_line[kind]),
             std::string("face refers to ") + kIndexKinds[kind] + " " +
                 std::to_string(tally.largest[kind]) + " but the file has " +
                 std::to_string(tally.defined[kind]));
  return for_parser;
}

std::string number_text(double v) {
  if (std::isnan(v)) return "nan";  // whatever its sign bit
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

// tinyobjloader's own number parser is not the scan's: a token both accept can still be read
// differently ("0.000…01e450" is NaN to it). Each of its single-precision values must be the
// scan's number to within float rounding, else the record's line is named.
void compare_numbers(const std::vector<float>& parsed, const std::vector<Record>& scanned,
                     const char* record, const std::string& file) {
  // Both read the same lines as records (is_blank, check_line); a difference in count would
  // make every line named below wrong, so it is an error of its own.
  if (parsed.size() != 3 * scanned.size())
    refuse(file, std::string("the OBJ parser read ") + std::to_string(parsed.size() / 3) + " " +
                     record + " records, the scan " + std::to_string(scanned.size()));
  for (std::size_t r = 0; r < scanned.size() && 3 * r + 2 < parsed.size(); ++r)
    for (int k = 0; k < scanned[r].count; ++k) {
      const double want = scanned[r].values[static_cast<std::size_t>(k)];
      const double got = parsed[3 * r + static_cast<std::size_t>(k)];
      if (!(std::abs(got - want) <= 1e-6 * std::abs(want) + 1e-30))
        refuse(at_line(file, scanned[r].line),
               std::string(record) + " number " + std::to_string(k + 1) + " is read as " +
                   number_text(got) + " by the OBJ parser, not as " + number_text(want) +
                   " (write it in fewer digits)");
    }
}

glm::dvec3 unit_normal(const tinyobj::attrib_t& attrib, int normal_index, const Tally& tally,
                       const std::string& file) {
  if (normal_index < 0) return glm::dvec3(0, 0, 1);  // replaced by compute_missing_normals
  const auto ni = static_cast<std::size_t>(3 * normal_index);
  const glm::dvec3 n(attrib.normals[ni], attrib.normals[ni + 1], attrib.normals[ni + 2]);
  if (!(glm::length(n) > 0)) {
    const auto r = static_cast<std::size_t>(normal_index);
    refuse(r < tally.normals.size() ? at_line(file, tally.normals[r].line) : file,
           "a face uses the zero normal of this vn record");
  }
  return glm::normalize(n);
}

// The normals of the vertices made from corners that give none (`f 1 2 3`, `f 1/2 3/4 5/6`): the
// area-weighted mean of the faces around the vertex's position, as compute_normals gives a file
// with no normals at all. The file's own normals are kept: a file that gave them on some faces
// only had them all replaced (found by review, 2026-12-07).
void compute_missing_normals(Mesh& m, const std::vector<int>& position_of,
                             const std::vector<bool>& missing, std::size_t positions) {
  std::vector<glm::dvec3> around(positions, glm::dvec3(0));
  for (const auto& t : m.triangles) {
    const glm::dvec3 n = glm::cross(m.positions[t[1]] - m.positions[t[0]],
                                    m.positions[t[2]] - m.positions[t[0]]);  // 2·area·normal
    for (auto v : t) around[static_cast<std::size_t>(position_of[v])] += n;
  }
  for (std::size_t v = 0; v < m.normals.size(); ++v) {
    if (!missing[v]) continue;
    const glm::dvec3 n = around[static_cast<std::size_t>(position_of[v])];
    m.normals[v] = glm::length(n) > 0 ? glm::normalize(n) : glm::dvec3(0, 0, 1);
  }
}

// OBJ indexes positions and normals separately; one mesh vertex per distinct pair.
Mesh build_mesh(const tinyobj::ObjReader& reader, const Tally& tally, const std::string& file) {
  const auto& attrib = reader.GetAttrib();
  Mesh m;
  std::vector<int> position_of;  // per vertex of m: its "v" record
  std::vector<bool> missing;     // per vertex of m: made from corners without a normal
  std::map<std::pair<int, int>, std::uint32_t> index;
  const auto nv = static_cast<int>(attrib.vertices.size() / 3);
  const auto nn = static_cast<int>(attrib.normals.size() / 3);
  for (const auto& shape : reader.GetShapes()) {
    const auto& ids = shape.mesh.indices;
    for (std::size_t f = 0; f + 2 < ids.size(); f += 3) {
      std::array<std::uint32_t, 3> tri{};
      for (std::size_t k = 0; k < 3; ++k) {
        const auto& id = ids[f + k];
        // The scan has checked every index; these hold whatever tinyobjloader did with them.
        if (id.vertex_index < 0 || id.vertex_index >= nv)
          refuse(file, "face refers to a missing vertex");
        if (id.normal_index >= nn) refuse(file, "face refers to a missing normal");
        auto it = index.find({id.vertex_index, id.normal_index});
        if (it == index.end()) {
          const auto vi = static_cast<std::size_t>(3 * id.vertex_index);
          m.positions.emplace_back(attrib.vertices[vi], attrib.vertices[vi + 1],
                                   attrib.vertices[vi + 2]);
          m.normals.push_back(unit_normal(attrib, id.normal_index, tally, file));
          position_of.push_back(id.vertex_index);
          missing.push_back(id.normal_index < 0);
          const auto added = static_cast<std::uint32_t>(m.positions.size() - 1);
          it = index.emplace(std::make_pair(id.vertex_index, id.normal_index), added).first;
        }
        tri[k] = it->second;
      }
      m.triangles.push_back(tri);
    }
  }
  if (std::ranges::find(missing, true) != missing.end())
    compute_missing_normals(m, position_of, missing, static_cast<std::size_t>(nv));
  return m;
}

}  // namespace

Mesh parse_obj(std::string_view text, const std::string& file) {
  // A UTF-8 byte order mark, which some editors write, is no part of the first record: left in,
  // it made the first "v" line no record, and every index after it named the next vertex.
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
  Tally tally;
  const std::string for_parser = scan_lines(text, file, tally);
  tinyobj::ObjReaderConfig cfg;
  cfg.triangulate = true;
  cfg.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromString(for_parser, "", cfg)) refuse(file, reader.Error());
  compare_numbers(reader.GetAttrib().vertices, tally.vertices, "v", file);
  compare_numbers(reader.GetAttrib().normals, tally.normals, "vn", file);
  Mesh m = build_mesh(reader, tally, file);
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
  if (!std::filesystem::is_regular_file(file, ec)) {
    std::error_code ignored;
    if (!ec && std::filesystem::exists(file, ignored))
      throw MeshError("mesh file is not a regular file: " + file.string());
    throw MeshError("mesh file not found: " + file.string() +
                    (ec ? " (" + ec.message() + ")" : std::string()));
  }
  std::string text;
  int os_error = 0;
  // A regular file, checked again on the open descriptor: one put in place of the file after the
  // check above (a FIFO) would block the read.
  switch (read_text_file(file, kMaxObjFileBytes, text, &os_error, Accept::regular_file)) {
    case ReadResult::ok: break;
    case ReadResult::cannot_open:
      throw MeshError("cannot read mesh file " + file.string() + os_reason(os_error));
    case ReadResult::not_regular:
      throw MeshError("mesh file is not a regular file: " + file.string());
    case ReadResult::too_large:
      refuse(file.string(), "larger than " + std::to_string(kMaxObjFileBytes) +
                                " bytes (the limit of an OBJ file)");
  }
  return parse_obj(text, file.string());
}

}  // namespace tp::host
