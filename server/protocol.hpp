// Wire format of the binary frame messages (docs/SERVER.md, "Frame header").
// Little-endian, a 40-byte fixed header, the frame's device counters, then the raw pixels:
//   0 magic "TPFB"   4 u16 version   6 u16 kind   8 u32 frame id   12 u16 width  14 u16 height
//  16 u16 format    18 u16 header bytes (40 + counter bytes)  20 u32 render time (us)
//  24 u64 FNV-1a 64 of the pixels   32 u32 payload bytes   36 u32 counter bytes
//  40 the counters of this frame as a compact JSON object {"name": value, ...} (UTF-8)
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace tp::server {

inline constexpr std::size_t kHeaderBytes = 40;  // the fixed part
inline constexpr std::size_t kMaxCounterBytes = 16 * 1024;
inline constexpr std::uint16_t kProtocolVersion = 2;

using Counters = std::vector<std::pair<std::string, std::uint64_t>>;

enum class FrameKind : std::uint16_t { device = 0, reference = 1 };
enum class PixelFormat : std::uint16_t { rgb888 = 1 };

// A JSON message's text for the WebSocket. Invalid UTF-8 in a string (clip_utf8 keeps quoted
// client text whole, but the JSON library's parse errors quote the client's bytes as they came)
// becomes U+FFFD rather than an exception that would end the server.
std::string json_text(const nlohmann::json& j);

// FNV-1a 64 over bytes: the frame checksum the page recomputes from the painted canvas.
std::uint64_t fnv1a64(std::span<const std::uint8_t> bytes);
std::string hex64(std::uint64_t v);

// An encoded, immutable frame message, shared by every session that sends it (no per-client
// copies: a slow client holds a reference, never a new buffer).
struct EncodedFrame {
  FrameKind kind = FrameKind::device;
  std::uint32_t id = 0;
  int width = 0, height = 0;
  std::uint64_t checksum = 0;
  double render_ms = 0;
  Counters counters;                        // the device's counters for this very frame
  std::size_t header_bytes = kHeaderBytes;  // where the pixels start
  std::string bytes;                        // header + counters + pixels, ready for the WebSocket
};
using FramePtr = std::shared_ptr<const EncodedFrame>;

FramePtr encode_frame(FrameKind kind, std::uint32_t id, int width, int height,
                      std::span<const std::uint8_t> rgb, double render_ms,
                      const Counters& counters = {});
// The same with the pixels' FNV-1a 64 already known (the render loop hashes every frame to
// detect repeats; the hash is not computed twice).
FramePtr encode_frame(FrameKind kind, std::uint32_t id, int width, int height,
                      std::span<const std::uint8_t> rgb, double render_ms, const Counters& counters,
                      std::uint64_t checksum);

// Parses a header (for tests and tools); false if the buffer is not a valid frame message.
bool decode_header(std::span<const std::uint8_t> msg, EncodedFrame& out);

}  // namespace tp::server
