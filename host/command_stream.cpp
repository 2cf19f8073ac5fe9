#include "host/command_stream.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <iterator>

#include "host/replace_file.hpp"
#include "host/text_file.hpp"
#include "target/fnv1a.hpp"

namespace tp::host {

std::string_view error_name(fw::Error e) {
  switch (e) {
    case fw::Error::kOk: return "ok";
    case fw::Error::kBadOpcode: return "bad opcode";
    case fw::Error::kBadLength: return "bad command length";
    case fw::Error::kBadArgument: return "bad argument";
    case fw::Error::kOutOfMemory: return "out of device memory";
    case fw::Error::kViewportTooLarge: return "viewport too large";
    case fw::Error::kIndexOutOfRange: return "index out of range";
    case fw::Error::kNotUnit: return "a normal or direction is not unit length";
    case fw::Error::kOutOfRange: return "a value is outside the device's range";
    case fw::Error::kTooManyLights: return "too many lights";
    case fw::Error::kUnknownMethod: return "shading method not available";
    case fw::Error::kNoViewport: return "no viewport set";
  }
  return "unknown error";
}

namespace {

static_assert(std::endian::native == std::endian::little,
              ".tpcmd files are little-endian words; a big-endian host would need byte swaps");

template <class Q>
std::uint32_t bits(Q q) {
  return static_cast<std::uint32_t>(q.raw());  // the raw two's-complement bits
}

// The payload length is the header's top 16 bits.
constexpr std::size_t kMaxPayload = 0xffff;
constexpr std::size_t kVerticesPerCommand = (kMaxPayload - 2) / 6;
constexpr std::size_t kIndicesPerCommand = kMaxPayload - 2;

std::string payload_name(std::uint32_t opcode) {
  switch (static_cast<fw::Opcode>(opcode)) {
    case fw::Opcode::kSetViewport: return "set_viewport";
    case fw::Opcode::kSetBufferCapacity: return "set_buffer_capacity";
    case fw::Opcode::kSetModelView: return "set_modelview";
    case fw::Opcode::kSetProjection: return "set_projection";
    case fw::Opcode::kSetEye: return "set_eye";
    case fw::Opcode::kSetMaterial: return "set_material";
    case fw::Opcode::kSetLight: return "set_light";
    case fw::Opcode::kSetMethod: return "set_method";
    case fw::Opcode::kSetCulling: return "set_culling";
    case fw::Opcode::kSetDepthTest: return "set_depth_test";
    case fw::Opcode::kUploadVertices: return "upload_vertices";
    case fw::Opcode::kUploadIndices: return "upload_indices";
    case fw::Opcode::kClear: return "clear";
    case fw::Opcode::kDraw: return "draw";
    case fw::Opcode::kEndFrame: return "end_frame";
    case fw::Opcode::kSetBudget: return "set_budget";
  }
  return "unknown opcode " + std::to_string(opcode);
}

std::string stream_message(std::size_t offset, std::uint32_t opcode, fw::Error e) {
  return "command " + opcode_name(opcode) + " at word " + std::to_string(offset) +
         " failed: " + std::string(error_name(e));
}

}  // namespace

void CommandWriter::header(fw::Opcode op, std::size_t payload_words) {
  words_.push_back(fw::command_header(op, static_cast<std::uint32_t>(payload_words)));
}

void CommandWriter::matrix(fw::Opcode op, const fw::Mat4& m) {
  header(op, 16);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) words_.push_back(bits(m.m[c][r]));
}

void CommandWriter::set_viewport(const fw::ViewportCmd& c) {
  header(fw::Opcode::kSetViewport, 4);
  const std::uint32_t flags =
      (c.write_count ? fw::kViewportWriteCount : 0u) | (c.depth_buffer ? 0u : fw::kViewportNoDepth);
  words_.insert(words_.end(), {c.width, c.height, static_cast<std::uint32_t>(c.format), flags});
}

void CommandWriter::set_buffer_capacity(const fw::BufferCapacityCmd& c) {
  header(fw::Opcode::kSetBufferCapacity, 2);
  words_.insert(words_.end(), {c.max_vertices, c.max_indices});
}

void CommandWriter::set_eye(fw::EyeMode mode) {
  header(fw::Opcode::kSetEye, 1);
  words_.push_back(static_cast<std::uint32_t>(mode));
}

void CommandWriter::set_material(const fw::MaterialCmd& c) {
  header(fw::Opcode::kSetMaterial, 9);
  words_.insert(words_.end(), {bits(c.color[0]), bits(c.color[1]), bits(c.color[2]), bits(c.ka),
                               bits(c.kd), bits(c.ks), c.n, bits(c.a), bits(c.b)});
}

void CommandWriter::set_light(const fw::LightCmd& c) {
  header(fw::Opcode::kSetLight, 11);
  words_.insert(words_.end(),
                {c.index, static_cast<std::uint32_t>(c.type), bits(c.color[0]), bits(c.color[1]),
                 bits(c.color[2]), bits(c.direction.x), bits(c.direction.y), bits(c.direction.z),
                 bits(c.position.x), bits(c.position.y), bits(c.position.z)});
}

void CommandWriter::set_method(fw::Method m) {
  header(fw::Opcode::kSetMethod, 1);
  words_.push_back(static_cast<std::uint32_t>(m));
}

void CommandWriter::set_culling(bool on) {
  header(fw::Opcode::kSetCulling, 1);
  words_.push_back(on ? 1u : 0u);
}

void CommandWriter::set_budget(std::uint32_t levels) {
  header(fw::Opcode::kSetBudget, 1);
  words_.push_back(levels);
}

void CommandWriter::upload_vertices(std::uint32_t first, std::span<const fw::Vertex> vertices) {
  std::size_t done = 0;
  do {  // an empty upload is still sent: the driver's stream does not depend on the mesh size
    const std::size_t n = std::min(kVerticesPerCommand, vertices.size() - done);
    header(fw::Opcode::kUploadVertices, 2 + 6 * n);
    words_.insert(words_.end(),
                  {first + static_cast<std::uint32_t>(done), static_cast<std::uint32_t>(n)});
    for (const fw::Vertex& v : vertices.subspan(done, n))
      words_.insert(words_.end(), {bits(v.position.x), bits(v.position.y), bits(v.position.z),
                                   bits(v.normal.x), bits(v.normal.y), bits(v.normal.z)});
    done += n;
  } while (done < vertices.size());
}

void CommandWriter::upload_indices(std::uint32_t first, std::span<const std::uint32_t> indices) {
  std::size_t done = 0;
  do {
    const std::size_t n = std::min(kIndicesPerCommand, indices.size() - done);
    header(fw::Opcode::kUploadIndices, 2 + n);
    words_.insert(words_.end(),
                  {first + static_cast<std::uint32_t>(done), static_cast<std::uint32_t>(n)});
    const auto chunk = indices.subspan(done, n);
    words_.insert(words_.end(), chunk.begin(), chunk.end());
    done += n;
  } while (done < indices.size());
}

void CommandWriter::clear(fw::Rgb8 colour) {
  header(fw::Opcode::kClear, 1);
  words_.push_back((std::uint32_t{colour.r} << 16) | (std::uint32_t{colour.g} << 8) | colour.b);
}

void CommandWriter::draw(const fw::DrawCmd& c) {
  header(fw::Opcode::kDraw, 2);
  words_.insert(words_.end(), {c.first, c.count});
}

void CommandWriter::end_frame() { header(fw::Opcode::kEndFrame, 0); }

std::string opcode_name(std::uint32_t opcode) { return payload_name(opcode); }

StreamError::StreamError(std::size_t offset, std::uint32_t op, fw::Error e, const std::string& note)
    : std::runtime_error(stream_message(offset, op, e) + (note.empty() ? "" : " (" + note + ")")),
      word_offset(offset),
      opcode(op),
      error(e) {}

std::optional<std::string> unfinished_frame(std::span<const std::uint32_t> words) {
  if (words.empty()) return "the stream is empty: no frame";
  std::size_t last = 0;
  for (std::size_t at = 0; at < words.size(); at += 1 + (words[at] >> 16)) last = at;
  const std::uint32_t op = words[last] & 0xffffu;
  if (op == static_cast<std::uint32_t>(fw::Opcode::kEndFrame)) return std::nullopt;
  return "the stream ends with " + opcode_name(op) + " at word " + std::to_string(last) +
         ", not end_frame: no whole frame (a truncated file?)";
}

void run_stream(fw::Device& device, std::span<const std::uint32_t> words) {
  const fw::Error e = device.execute(words);
  if (e == fw::Error::kOk) return;
  const std::size_t at = device.words_consumed();
  throw StreamError(at, at < words.size() ? words[at] & 0xffffu : 0u, e);
}

namespace {

// The layout-changing commands' values as the device accepts them, by its own rules
// (firmware/device.hpp), but for the memory check itself.
bool accepted_viewport(std::span<const std::uint32_t> p, fw::ViewportCmd& vp) {
  fw::ViewportCmd c;
  if (!fw::decode_viewport(p, c) || !fw::viewport_size_ok(c) || !fw::pixel_format_ok(c.format))
    return false;
  vp = c;
  return true;
}

bool accepted_capacity(std::span<const std::uint32_t> p, fw::BufferCapacityCmd& cap) {
  const fw::BufferCapacityCmd c{p[0], p[1]};
  if (!fw::capacity_ok(c)) return false;
  cap = c;
  return true;
}

bool accepted_method(std::span<const std::uint32_t> p, fw::Method& m) {
  const auto id = static_cast<fw::Method>(p[0]);
  if (fw::Device::method_bytes(id) == 0) return false;  // not linked, or no such method
  m = id;
  return true;
}

}  // namespace

StreamMemory memory_for_stream(std::span<const std::uint32_t> words, std::size_t limit) {
  // A fresh device's state (DeviceState's defaults): no viewport, no buffers, Gouraud.
  fw::ViewportCmd vp;
  fw::BufferCapacityCmd cap;
  fw::Method method = fw::Method::kGouraud;
  StreamMemory need{fw::Device::memory_required(vp, cap, method)};
  for (std::size_t at = 0; at < words.size();) {
    // Where the device stops, the scan stops: a command it cannot frame (Device::execute's
    // rules), or layout values it refuses. Other refused values are the device's alone to find,
    // so a stream that fails at one may get a larger block than it uses, never a smaller one.
    const std::uint32_t op = words[at] & 0xffffu, len = words[at] >> 16;
    if (!fw::known_opcode(op) || len > words.size() - at - 1) break;
    const auto opcode = static_cast<fw::Opcode>(op);
    const std::uint32_t expected = fw::payload_words(opcode);
    if (expected != fw::kVariablePayload && len != expected) break;
    const std::size_t header = at;
    const auto p = words.subspan(at + 1, len);
    at += 1 + std::size_t{len};
    bool accepted = false;
    switch (opcode) {
      case fw::Opcode::kSetViewport: accepted = accepted_viewport(p, vp); break;
      case fw::Opcode::kSetBufferCapacity: accepted = accepted_capacity(p, cap); break;
      case fw::Opcode::kSetMethod: accepted = accepted_method(p, method); break;
      default: continue;  // not a layout command
    }
    if (!accepted) break;
    const std::size_t bytes = fw::Device::memory_required(vp, cap, method);
    if (bytes > limit) {
      need.over_at = header;
      need.over_bytes = bytes;
      break;
    }
    need.bytes = std::max(need.bytes, bytes);
  }
  return need;
}

StreamReplay::StreamReplay(std::span<const std::uint32_t> words, std::size_t max_memory)
    : need_(memory_for_stream(words, max_memory)),
      memory_(need_.bytes),
      device_(std::span<std::byte>(memory_)) {
  try {
    run_stream(device_, words);
  } catch (const StreamError& e) {
    if (e.error != fw::Error::kOutOfMemory || e.word_offset != need_.over_at) throw;
    throw StreamError(e.word_offset, e.opcode, e.error,
                      "it needs " + std::to_string(need_.over_bytes) +
                          " bytes, more than replay's limit of " + std::to_string(max_memory));
  }
  if (!device_.state().viewport_set)
    throw std::runtime_error("the stream sets no viewport: no image");
}

std::vector<std::uint32_t> read_command_file(const std::string& path) {
  std::string bytes;
  int os_error = 0;
  switch (read_text_file(path, kMaxCommandFileBytes, bytes, &os_error)) {
    case ReadResult::ok: break;
    case ReadResult::cannot_open:
      throw std::runtime_error(path + ": cannot open or read" + os_reason(os_error));
    case ReadResult::not_regular:  // (not asked for: any file is read)
      throw std::runtime_error(path + ": not a regular file");
    case ReadResult::too_large:
      throw std::runtime_error(path + ": larger than " + std::to_string(kMaxCommandFileBytes) +
                               " bytes (the limit of a command file)");
  }
  if (bytes.size() % 4 != 0)
    throw std::runtime_error(path + ": " + std::to_string(bytes.size()) +
                             " bytes is not a whole number of 32-bit words (a truncated file?)");
  std::vector<std::uint32_t> words(bytes.size() / 4);
  if (!bytes.empty()) std::memcpy(words.data(), bytes.data(), bytes.size());
  return words;
}

void write_command_file(const std::string& path, std::span<const std::uint32_t> words) {
  replace_file(path, std::as_bytes(words));  // the host's order is the file's (above)
}

std::uint64_t framebuffer_hash(const fw::FramebufferView& fb) {
  return target::framebuffer_fnv1a(fb);
}

std::string hash_hex(std::uint64_t h) {
  static const char* digits = "0123456789abcdef";
  std::string s(16, '0');
  for (int i = 15; i >= 0; --i, h >>= 4) s[static_cast<std::size_t>(i)] = digits[h & 15u];
  return s;
}

}  // namespace tp::host
