// The device's command stream on the host side: the encoder the driver (DeviceRenderer) builds
// every command with, so that what `tinyphong record` writes is exactly what `render` runs;
// the .tpcmd file (raw little-endian 32-bit words, nothing else; docs/TARGET.md); running a
// stream with an error that names the word offset; and the framebuffer hash the Cortex-M
// images print (target/fnv1a.hpp), so that host and target hash the same bytes the same way.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "firmware/device.hpp"

namespace tp::host {

// Appends commands as words, in the layouts of firmware/device.hpp (enum class Opcode).
class CommandWriter {
 public:
  void set_viewport(const fw::ViewportCmd& c);
  void set_buffer_capacity(const fw::BufferCapacityCmd& c);
  void set_modelview(const fw::Mat4& m) { matrix(fw::Opcode::kSetModelView, m); }
  void set_projection(const fw::Mat4& m) { matrix(fw::Opcode::kSetProjection, m); }
  void set_eye(fw::EyeMode mode);
  void set_material(const fw::MaterialCmd& c);
  void set_light(const fw::LightCmd& c);
  void set_method(fw::Method m);
  void set_culling(bool on);
  void set_budget(std::uint32_t levels);
  // Uploads longer than one command can carry (the payload length is 16 bits) are split.
  void upload_vertices(std::uint32_t first, std::span<const fw::Vertex> vertices);
  void upload_indices(std::uint32_t first, std::span<const std::uint32_t> indices);
  void clear(fw::Rgb8 colour);
  void draw(const fw::DrawCmd& c);
  void end_frame();

  const std::vector<std::uint32_t>& words() const { return words_; }

 private:
  void header(fw::Opcode op, std::size_t payload_words);
  void matrix(fw::Opcode op, const fw::Mat4& m);
  std::vector<std::uint32_t> words_;
};

// "set_viewport", "upload_vertices", ...; "unknown opcode N" otherwise.
std::string opcode_name(std::uint32_t opcode);

// "ok", "bad opcode", ...: the device's error codes by name (for messages).
std::string_view error_name(fw::Error e);

// A command the device refused: where (word offset of its header), which, and why.
class StreamError : public std::runtime_error {
 public:
  // `note`, if given, follows the device's error in the message.
  StreamError(std::size_t word_offset, std::uint32_t opcode, fw::Error error,
              const std::string& note = {});
  std::size_t word_offset;
  std::uint32_t opcode;  // 0 if the stream ended inside the header's payload
  fw::Error error;
};

// A stream that ran (whole commands only) but whose last command is not end_frame stops inside a
// frame: a file cut at a command's boundary, which `tinyphong replay` refuses with this message
// (the frame so far would pass for the frame). nullopt when it ends with end_frame.
std::optional<std::string> unfinished_frame(std::span<const std::uint32_t> words);

// Runs `words` through Device::execute; throws StreamError at the first failing command.
void run_stream(fw::Device& device, std::span<const std::uint32_t> words);

// The memory block a fresh device needs for this stream. The device's layout is followed command
// by command, as the device takes it: the viewport, buffer capacity and method that each
// set_viewport, set_buffer_capacity and set_method with values the device accepts leaves in
// force, each such state needing Device::memory_required(viewport, capacity, method), the
// device's own check. `bytes` is the largest need of the fresh device's state and of every state
// before the first that needs more than `limit`; given that block the device refuses that
// state's command with kOutOfMemory at its word (`over_at`), unless an earlier command fails
// first. The scan ends where the device would stop at the latest: a command it cannot frame
// (Device::execute's rules: fw::known_opcode, fw::payload_words), or a layout command whose
// values it refuses.
struct StreamMemory {
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  std::size_t bytes = 0;
  std::size_t over_at = kNone;  // the word offset of the first command over `limit`, if any
  std::size_t over_bytes = 0;   // what the state it sets needs
};
StreamMemory memory_for_stream(std::span<const std::uint32_t> words,
                               std::size_t limit = static_cast<std::size_t>(-1));

// A stream run through a fresh device, in a memory block of the size the stream needs
// (memory_for_stream), at most max_memory: what `tinyphong replay`, the replay tests and the
// target tests' host hashes do. The constructor throws StreamError at the first command the
// device refuses, in stream order: a command whose state needs more than max_memory (a dozen
// words can ask for 2^24 vertices) fails with kOutOfMemory, its message giving the bytes and the
// limit; and std::runtime_error if the stream sets no viewport (no frame).
class StreamReplay {
 public:
  // Well above what any frame of a scene file needs: a 4096 x 4096 viewport with the largest
  // mesh a scene may hold takes well under it.
  static constexpr std::size_t kMaxMemory = std::size_t{1} << 30;

  explicit StreamReplay(std::span<const std::uint32_t> words, std::size_t max_memory = kMaxMemory);
  const fw::Device& device() const { return device_; }

 private:
  StreamMemory need_;
  std::vector<std::byte> memory_;
  fw::Device device_;
};

// .tpcmd files. read_command_file throws std::runtime_error naming the file if it cannot be
// read, holds more than kMaxCommandFileBytes (refused before more is read: /dev/zero ends) or is
// not a whole number of 32-bit words. A paper scene's frame is at most a few hundred KiB.
inline constexpr std::size_t kMaxCommandFileBytes = std::size_t{64} << 20;
std::vector<std::uint32_t> read_command_file(const std::string& path);
// Throws std::runtime_error naming the file if it cannot be written. A regular file is replaced
// whole or not at all, by host/replace_file.hpp's replace_file (which says where that cannot
// hold): written to a file with no name yet, then named PATH.part and renamed over PATH.
void write_command_file(const std::string& path, std::span<const std::uint32_t> words);

// FNV-1a 64 of the framebuffer's colour bytes, row by row (no stride padding): the hash the
// Cortex-M images print.
std::uint64_t framebuffer_hash(const fw::FramebufferView& fb);
std::string hash_hex(std::uint64_t h);  // 16 lower-case hex digits

}  // namespace tp::host
