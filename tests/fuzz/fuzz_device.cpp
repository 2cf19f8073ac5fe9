// Fuzz target: the device's command stream (firmware/command.cpp) on arbitrary 32-bit words.
//
// The input's bytes are little-endian words. Device A runs them one command at a time (the
// header's length says where a command ends); device B runs the whole stream with one execute().
// Properties, besides no crash and no undefined behaviour:
//  - a command that fails changes nothing: DeviceState, counters and every byte of the memory
//    block are compared before and after it, and last_error() is its error;
//  - a command that succeeds leaves last_error() == kOk;
//  - execute() on the whole stream stops where A met its first error, with the same error, the
//    same words consumed, and the same state, counters and memory (or, without an error,
//    consumes everything and ends in A's state);
//  - a verification variant draws its method's image (the registry's same_image_as: kb-noskip
//    kb's, kb-adaptive-noskip kb-adaptive's, brown-noskip brown's): device C runs the stream with
//    every method that has a twin swapped for it, in step with A up to A's first failing
//    command; each command must succeed or fail as A's does, and after every draw C's colour,
//    depth and write-count buffers must equal A's.
// After its first error A goes on with the next command, so that the fuzzer can keep building
// state past a bad command.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <new>
#include <span>
#include <type_traits>
#include <vector>

#include "firmware/device.hpp"
#include "firmware/registry.hpp"
#include "tests/fuzz/fuzz_check.hpp"

namespace {

using tp::fw::Device;
using tp::fw::Error;

// Room for a viewport of about 40 x 40 and a hundred vertices (32 KiB), plus the
// largest method's state (memory_required without a method covers every method, so that the
// fuzzer can select and draw with each): a command needing more is refused with kOutOfMemory,
// which is itself a path under test. The snapshots copy only the block's used part, [0, end) of
// the layout, so that the large method regions cost only the inputs that select those methods
// (copying a 96 KiB block at every command made fuzzing 3 times slower).
std::size_t memory_bytes() {
  static const std::size_t bytes =
      32 * 1024 + Device::memory_required(tp::fw::ViewportCmd{}, tp::fw::BufferCapacityCmd{});
  return bytes;
}

std::vector<std::uint32_t> words_of(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint32_t> words(size / 4);
  for (std::size_t i = 0; i < words.size(); ++i)
    words[i] = std::uint32_t{data[4 * i]} | std::uint32_t{data[4 * i + 1]} << 8 |
               std::uint32_t{data[4 * i + 2]} << 16 | std::uint32_t{data[4 * i + 3]} << 24;
  return words;
}

// Everything a command may change, as bytes.
struct Snapshot {
  std::array<std::byte, sizeof(tp::fw::DeviceState)> state;
  std::array<std::byte, sizeof(tp::fw::Counters)> counters;
  std::vector<std::byte> memory;
  std::size_t method_at = 0, method_end = 0;  // the active method's region of the block
};

// The state's pointer to its own device's counters differs between A and B; it is left out.
constexpr std::size_t kCountersPointerAt =
    offsetof(tp::fw::DeviceState, shading) + offsetof(tp::fw::ShadeContext, counters);
static_assert(std::is_standard_layout_v<tp::fw::DeviceState>);

void take(const Device& d, std::span<const std::byte> memory, Snapshot& s) {
  std::memcpy(s.state.data(), &d.state(), sizeof(tp::fw::DeviceState));
  std::fill_n(s.state.begin() + kCountersPointerAt, sizeof(tp::fw::Counters*), std::byte{0});
  std::memcpy(s.counters.data(), &d.counters(), sizeof(tp::fw::Counters));
  const std::size_t used = std::min(d.state().end, memory.size());
  s.memory.assign(memory.begin(), memory.begin() + static_cast<std::ptrdiff_t>(used));
  s.method_at = d.state().off_method;
  s.method_end = d.state().end;
}

// One device before and after a command: everything, to the byte (of the block's used part: a
// failing command leaves the layout, and so the used part, as it was).
bool same(const Snapshot& a, const Snapshot& b) {
  return a.state == b.state && a.counters == b.counters && a.memory == b.memory;
}

// Devices A and B after the same commands: everything but the method's region, where each
// method object holds pointers to its own device's state (the material, the lights, the
// counters), which differ between the two devices by construction. (The offsets count from the
// block's 8-byte-aligned start; the vectors' storage is at least that aligned, so they index the
// snapshots directly.)
bool same_across_devices(const Snapshot& a, const Snapshot& b) {
  if (!(a.state == b.state && a.counters == b.counters && a.memory.size() == b.memory.size()))
    return false;
  const auto equal = [&](std::size_t from, std::size_t to) {
    return std::equal(a.memory.begin() + static_cast<std::ptrdiff_t>(from),
                      a.memory.begin() + static_cast<std::ptrdiff_t>(to),
                      b.memory.begin() + static_cast<std::ptrdiff_t>(from));
  };
  const std::size_t at = std::min(a.method_at, a.memory.size());
  const std::size_t end = std::min(a.method_end, a.memory.size());
  return equal(0, at) && equal(end, a.memory.size());
}

// Where the command at `at` ends: its header's payload length, cut at the end of the stream
// (execute() then refuses it with kBadLength).
std::size_t command_end(std::span<const std::uint32_t> words, std::size_t at) {
  const std::size_t len = words[at] >> 16;
  return std::min(words.size(), at + 1 + len);
}

// The registry's verification variants come in pairs: a method named by one variant at most,
// which names none itself (twin_of is then its own inverse).
constexpr bool twins_are_pairs() {
  for (const tp::fw::MethodInfo& row : tp::fw::kMethodTable) {
    if (row.same_image_as == tp::fw::Method{}) continue;
    int named = 0;
    for (const tp::fw::MethodInfo& other : tp::fw::kMethodTable) {
      if (other.same_image_as == row.same_image_as) ++named;
      if (other.id == row.same_image_as && other.same_image_as != tp::fw::Method{}) return false;
    }
    if (named != 1) return false;
  }
  return true;
}
static_assert(twins_are_pairs(), "a method named by two verification variants, or a chain");

// The method whose image m must reproduce, or the variant that must reproduce m's; m itself if
// it has no twin.
tp::fw::Method twin_of(tp::fw::Method m) {
  if (m == tp::fw::Method{}) return m;  // no method: the rows without a twin name it
  for (const tp::fw::MethodInfo& row : tp::fw::kMethodTable) {
    if (row.id == m && row.same_image_as != tp::fw::Method{}) return row.same_image_as;
    if (row.same_image_as == m) return row.id;
  }
  return m;
}

// The stream with the method of every set_method command swapped for its twin; empty if none
// has one (the twin stream would be the stream itself).
std::vector<std::uint32_t> twin_stream(std::span<const std::uint32_t> stream) {
  std::vector<std::uint32_t> words(stream.begin(), stream.end());
  bool swapped = false;
  for (std::size_t at = 0; at < words.size();) {
    const std::size_t end = command_end(words, at);
    const auto op = static_cast<tp::fw::Opcode>(words[at] & 0xffffu);
    if (op == tp::fw::Opcode::kSetMethod && end - at == 2) {
      const auto m = static_cast<tp::fw::Method>(words[at + 1]);
      const tp::fw::Method twin = twin_of(m);
      if (twin != m) {
        words[at + 1] = static_cast<std::uint32_t>(twin);
        swapped = true;
      }
    }
    at = end;
  }
  if (!swapped) words.clear();
  return words;
}

// Whether two devices hold the same image: colour, depth and write counts, as read back.
bool same_image(const Device& x, const Device& y) {
  const tp::fw::FramebufferView fx = x.framebuffer(), fy = y.framebuffer();
  if (fx.width != fy.width || fx.height != fy.height || fx.stride != fy.stride ||
      fx.format != fy.format)
    return false;
  const std::size_t pixels = std::size_t{fx.width} * fx.height;
  if (!std::equal(fx.data, fx.data + std::size_t{fx.stride} * fx.height, fy.data)) return false;
  const std::uint32_t *dx = x.depth_buffer(), *dy = y.depth_buffer();
  if ((dx == nullptr) != (dy == nullptr)) return false;
  if (dx != nullptr && !std::equal(dx, dx + pixels, dy)) return false;
  const std::uint8_t *cx = x.write_counts(), *cy = y.write_counts();
  if ((cx == nullptr) != (cy == nullptr)) return false;
  return cx == nullptr || std::equal(cx, cx + pixels, cy);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::vector<std::uint32_t> words = words_of(data, size);
  static std::vector<std::byte> memory_a(memory_bytes()), memory_b(memory_bytes());
  std::fill(memory_a.begin(), memory_a.end(), std::byte{0});
  std::fill(memory_b.begin(), memory_b.end(), std::byte{0});
  // In zeroed storage, so that the padding bytes of the two devices' states are alike too.
  alignas(Device) static std::array<std::byte, sizeof(Device)> storage_a, storage_b;
  storage_a.fill(std::byte{0});
  storage_b.fill(std::byte{0});
  Device& a = *new (storage_a.data()) Device{std::span<std::byte>(memory_a)};
  Device& b = *new (storage_b.data()) Device{std::span<std::byte>(memory_b)};

  const Error whole = b.execute(words);
  Snapshot before, after, at_b;
  take(b, memory_b, at_b);

  // Device C runs the twin stream in step with A, up to A's first failing command.
  const std::vector<std::uint32_t> twins = twin_stream(words);
  static std::vector<std::byte> memory_c(memory_bytes());
  alignas(Device) static std::array<std::byte, sizeof(Device)> storage_c;
  Device* c = nullptr;
  if (!twins.empty()) {
    std::fill(memory_c.begin(), memory_c.end(), std::byte{0});
    c = new (storage_c.data()) Device{std::span<std::byte>(memory_c)};
  }

  bool compared = false;
  for (std::size_t at = 0; at < words.size();) {
    const std::size_t end = command_end(words, at);
    take(a, memory_a, before);
    const Error e = a.execute(std::span<const std::uint32_t>(words).subspan(at, end - at));
    TP_FUZZ_CHECK(a.last_error() == e, "last_error() is the command's result");
    if (c != nullptr && !compared) {
      const Error ec = c->execute(std::span<const std::uint32_t>(twins).subspan(at, end - at));
      TP_FUZZ_CHECK(ec == e, "a method and its twin fail the same commands");
      if (e == Error::kOk &&
          static_cast<tp::fw::Opcode>(words[at] & 0xffffu) == tp::fw::Opcode::kDraw)
        TP_FUZZ_CHECK(same_image(a, *c), "a verification variant draws its method's image");
    }
    if (e != Error::kOk) {
      take(a, memory_a, after);
      TP_FUZZ_CHECK(same(before, after), "a failing command changed the device");
      if (!compared) {
        TP_FUZZ_CHECK(whole == e, "execute() on the stream fails with the same error");
        TP_FUZZ_CHECK(b.words_consumed() == at, "execute() stops at the failing command");
        TP_FUZZ_CHECK(same_across_devices(after, at_b),
                      "execute() on the stream ends in the same state");
        compared = true;
      }
    }
    at = end;
  }
  if (!compared) {
    take(a, memory_a, after);
    TP_FUZZ_CHECK(whole == Error::kOk, "execute() on a valid stream succeeds");
    TP_FUZZ_CHECK(b.words_consumed() == words.size(), "execute() consumes a valid stream");
    TP_FUZZ_CHECK(same_across_devices(after, at_b),
                  "execute() on the stream ends in the same state");
  }
  if (c != nullptr) c->~Device();
  a.~Device();
  b.~Device();
  return 0;
}
