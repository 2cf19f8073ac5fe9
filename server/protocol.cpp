#include "server/protocol.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

namespace tp::server {
namespace {

void put16(std::string& b, std::size_t at, std::uint16_t v) {
  b[at] = static_cast<char>(v & 0xff);
  b[at + 1] = static_cast<char>(v >> 8);
}
void put32(std::string& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = static_cast<char>((v >> (8 * i)) & 0xff);
}
void put64(std::string& b, std::size_t at, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) b[at + i] = static_cast<char>((v >> (8 * i)) & 0xff);
}
std::uint64_t get(std::span<const std::uint8_t> m, std::size_t at, int n) {
  std::uint64_t v = 0;
  for (int i = n - 1; i >= 0; --i) v = (v << 8) | m[at + static_cast<std::size_t>(i)];
  return v;
}

}  // namespace

std::string json_text(const nlohmann::json& j) {
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::uint64_t fnv1a64(std::span<const std::uint8_t> bytes) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (std::uint8_t c : bytes) {
    h ^= c;
    h *= 0x100000001b3ULL;
  }
  return h;
}

std::string hex64(std::uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

FramePtr encode_frame(FrameKind kind, std::uint32_t id, int width, int height,
                      std::span<const std::uint8_t> rgb, double render_ms,
                      const Counters& counters) {
  return encode_frame(kind, id, width, height, rgb, render_ms, counters, fnv1a64(rgb));
}

FramePtr encode_frame(FrameKind kind, std::uint32_t id, int width, int height,
                      std::span<const std::uint8_t> rgb, double render_ms, const Counters& counters,
                      std::uint64_t checksum) {
  auto f = std::make_shared<EncodedFrame>();
  f->kind = kind;
  f->id = id;
  f->width = width;
  f->height = height;
  f->render_ms = render_ms;
  f->checksum = checksum;
  nlohmann::json c = nlohmann::json::object();
  for (const auto& [k, v] : counters) c[k] = v;
  std::string block = json_text(c);
  if (block.size() > kMaxCounterBytes) block = "{}";  // never: ~20 counters are ~600 bytes
  f->counters = counters;
  f->header_bytes = kHeaderBytes + block.size();
  std::string& b = f->bytes;
  b.assign(f->header_bytes + rgb.size(), '\0');
  b[0] = 'T';
  b[1] = 'P';
  b[2] = 'F';
  b[3] = 'B';
  put16(b, 4, kProtocolVersion);
  put16(b, 6, static_cast<std::uint16_t>(kind));
  put32(b, 8, id);
  put16(b, 12, static_cast<std::uint16_t>(width));
  put16(b, 14, static_cast<std::uint16_t>(height));
  put16(b, 16, static_cast<std::uint16_t>(PixelFormat::rgb888));
  put16(b, 18, static_cast<std::uint16_t>(f->header_bytes));
  // Saturates at the field's largest value, so that every time a header can carry (and
  // decode_header gives) encodes back to itself (it saturated at 4e9 before: found by the
  // frame header's fuzz target).
  constexpr double kMaxMicroseconds = 4294967295.0;  // 2^32 - 1
  const double us = std::clamp(render_ms * 1000.0, 0.0, kMaxMicroseconds);
  put32(b, 20, static_cast<std::uint32_t>(std::lround(us)));
  put64(b, 24, f->checksum);
  put32(b, 32, static_cast<std::uint32_t>(rgb.size()));
  put32(b, 36, static_cast<std::uint32_t>(block.size()));
  std::copy(block.begin(), block.end(), b.begin() + static_cast<std::ptrdiff_t>(kHeaderBytes));
  std::copy(rgb.begin(), rgb.end(), b.begin() + static_cast<std::ptrdiff_t>(f->header_bytes));
  return f;
}

bool decode_header(std::span<const std::uint8_t> m, EncodedFrame& out) {
  if (m.size() < kHeaderBytes || m[0] != 'T' || m[1] != 'P' || m[2] != 'F' || m[3] != 'B')
    return false;
  const auto counter_bytes = get(m, 36, 4);
  if (get(m, 4, 2) != kProtocolVersion || get(m, 16, 2) != 1 || counter_bytes > kMaxCounterBytes ||
      get(m, 18, 2) != kHeaderBytes + counter_bytes || m.size() < kHeaderBytes + counter_bytes)
    return false;
  out.header_bytes = static_cast<std::size_t>(kHeaderBytes + counter_bytes);
  const auto block = m.subspan(kHeaderBytes, static_cast<std::size_t>(counter_bytes));
  const auto parsed = nlohmann::json::parse(block.begin(), block.end(), nullptr, false);
  if (!parsed.is_object()) return false;
  out.counters.clear();
  for (const auto& [k, v] : parsed.items()) {
    if (!v.is_number_unsigned()) return false;
    out.counters.emplace_back(k, v.get<std::uint64_t>());
  }
  const auto kind = get(m, 6, 2);
  if (kind != static_cast<std::uint16_t>(FrameKind::device) &&
      kind != static_cast<std::uint16_t>(FrameKind::reference))
    return false;  // a kind the protocol does not define
  out.kind = static_cast<FrameKind>(kind);
  out.id = static_cast<std::uint32_t>(get(m, 8, 4));
  out.width = static_cast<int>(get(m, 12, 2));
  out.height = static_cast<int>(get(m, 14, 2));
  out.render_ms = static_cast<double>(get(m, 20, 4)) / 1000.0;
  out.checksum = get(m, 24, 8);
  const auto payload = get(m, 32, 4);
  const auto expect =
      static_cast<std::uint64_t>(out.width) * static_cast<std::uint64_t>(out.height) * 3;
  return payload == expect && m.size() == out.header_bytes + payload;
}

}  // namespace tp::server
