// Fuzz target: the binary frame header (server/protocol.cpp), which the page and the tests
// decode. Two properties on every input, besides no crash, no undefined behaviour and no
// exception:
//  - decoding: decode_header on the raw bytes either refuses them or gives fields that, encoded
//    again, decode to the same fields (and to the same pixels);
//  - round trip: a frame encoded from fields taken from the input (sizes up to 32 x 32, counter
//    names like the device's) decodes to exactly those fields.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "server/protocol.hpp"
#include "tests/fuzz/fuzz_check.hpp"

namespace {

using tp::server::EncodedFrame;

// Reads fields off the input, zeros past its end.
class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> d) : d_(d) {}
  std::uint64_t take(int bytes) {
    std::uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) v |= std::uint64_t{at_ < d_.size() ? d_[at_++] : 0u} << (8 * i);
    return v;
  }
  std::span<const std::uint8_t> rest() const { return d_.subspan(std::min(at_, d_.size())); }

 private:
  std::span<const std::uint8_t> d_;
  std::size_t at_ = 0;
};

std::map<std::string, std::uint64_t> as_map(const tp::server::Counters& c) {
  std::map<std::string, std::uint64_t> m;
  for (const auto& [k, v] : c) m[k] = v;  // the JSON object keeps the last of a repeated name
  return m;
}

bool same_fields(const EncodedFrame& a, const EncodedFrame& b) {
  return a.kind == b.kind && a.id == b.id && a.width == b.width && a.height == b.height &&
         a.checksum == b.checksum && a.render_ms == b.render_ms &&
         as_map(a.counters) == as_map(b.counters);
}

std::span<const std::uint8_t> bytes_of(const std::string& s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

void decode_and_encode_again(std::span<const std::uint8_t> msg) {
  EncodedFrame first;
  if (!tp::server::decode_header(msg, first)) return;
  const auto pixels = msg.subspan(first.header_bytes);
  const auto again =
      tp::server::encode_frame(first.kind, first.id, first.width, first.height, pixels,
                               first.render_ms, first.counters, first.checksum);
  EncodedFrame second;
  TP_FUZZ_CHECK(tp::server::decode_header(bytes_of(again->bytes), second),
                "a decoded frame encodes to a valid frame");
  TP_FUZZ_CHECK(same_fields(first, second), "decode, encode, decode keeps the fields");
  TP_FUZZ_CHECK(bytes_of(again->bytes).subspan(second.header_bytes).size() == pixels.size(),
                "the pixels survive");
}

void encode_and_decode(std::span<const std::uint8_t> data) {
  Reader r(data);
  const auto kind = static_cast<tp::server::FrameKind>(r.take(1) & 1);
  const auto id = static_cast<std::uint32_t>(r.take(4));
  const int width = static_cast<int>(r.take(1) % 33), height = static_cast<int>(r.take(1) % 33);
  const auto render_us = static_cast<std::uint32_t>(r.take(4));
  tp::server::Counters counters;
  for (auto n = r.take(1) % 24; n > 0; --n) {
    std::string name(r.take(1) % 24 + 1, 'a');
    for (char& c : name) c = "abcdefghijklmnopqrstuvwxyz_"[r.take(1) % 27];
    counters.emplace_back(name, r.take(8));
  }
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(width * height * 3));
  const auto rest = r.rest();
  std::copy_n(rest.begin(), std::min(rest.size(), rgb.size()), rgb.begin());
  const double render_ms = render_us / 1000.0;
  const auto frame = tp::server::encode_frame(kind, id, width, height, rgb, render_ms, counters);
  EncodedFrame decoded;
  TP_FUZZ_CHECK(tp::server::decode_header(bytes_of(frame->bytes), decoded),
                "an encoded frame decodes");
  TP_FUZZ_CHECK(decoded.kind == kind && decoded.id == id && decoded.width == width &&
                    decoded.height == height && decoded.render_ms == render_ms,
                "the header's fields round-trip");
  TP_FUZZ_CHECK(decoded.checksum == tp::server::fnv1a64(rgb), "the checksum is the pixels'");
  TP_FUZZ_CHECK(as_map(decoded.counters) == as_map(counters), "the counters round-trip");
  TP_FUZZ_CHECK(decoded.header_bytes == frame->header_bytes, "the pixels start where encoded");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> input(data, size);
  decode_and_encode_again(input);
  encode_and_decode(input);
  return 0;
}
