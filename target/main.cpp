// A Cortex-M image of the firmware: runs each embedded command stream (recorded on the host by
// `tinyphong record`, linked in by streams.S) through a fresh tp::fw::Device in a static memory
// block, and prints per stream
//     stream NAME HASH          (FNV-1a 64 of the framebuffer's colour bytes, target/fnv1a.hpp)
// or  stream NAME error CODE at word OFFSET
// then "done"; exits (semihosting) with success iff every stream ran. tests/target compares
// the hashes with `tinyphong replay --hash` of the same .tpcmd files.
#include <cstddef>
#include <cstdint>
#include <new>
#include <span>

#include "firmware/device.hpp"
#include "target/fnv1a.hpp"
#include "target/semihost.hpp"

#ifndef TP_BLOCK_BYTES
#define TP_BLOCK_BYTES (2u << 20)
#endif
#ifndef TP_IMAGE_NAME
#define TP_IMAGE_NAME "tinyphong"
#endif

struct EmbeddedStream {
  const char* name;
  const std::uint32_t* words;
  std::uint32_t word_count;
};
extern "C" const EmbeddedStream tp_streams[];
extern "C" const std::uint32_t tp_stream_count;

namespace {

// The device's memory block, and the Device object itself (constructed anew per stream so
// that each stream starts from a fresh device, as `tinyphong replay` does). Both are static:
// the firmware has no heap. .noinit: the device clears what it uses.
alignas(8) __attribute__((section(".noinit"))) std::byte block[TP_BLOCK_BYTES];
alignas(tp::fw::Device)
    __attribute__((section(".noinit"))) unsigned char device_storage[sizeof(tp::fw::Device)];

bool run(const EmbeddedStream& s) {
  using namespace tp::target;
  auto* device = new (device_storage) tp::fw::Device(std::span<std::byte>(block, sizeof block));
  const tp::fw::Error e = device->execute(std::span<const std::uint32_t>(s.words, s.word_count));
  write("stream ");
  write(s.name);
  bool ok = e == tp::fw::Error::kOk && device->state().viewport_set;
  if (ok) {
    const tp::fw::FramebufferView fb = device->framebuffer();
    const std::size_t bpp = fb.format == tp::fw::PixelFormat::kRgb888 ? 3 : 2;
    write(" ");
    write_hex64(framebuffer_fnv1a(fb.data, fb.height, fb.stride, bpp * fb.width));
    write("\n");
  } else {
    write(" error ");
    write_dec(static_cast<std::uint32_t>(e));
    write(" at word ");
    write_dec(device->words_consumed());
    write("\n");
  }
  device->~Device();
  return ok;
}

}  // namespace

int main() {
  using namespace tp::target;
  write("tinyphong target image " TP_IMAGE_NAME ": sizeof(Device) = ");
  write_dec(sizeof(tp::fw::Device));
  write(", block = ");
  write_dec(sizeof block);
  write(", streams = ");
  write_dec(tp_stream_count);
  write("\n");
  bool ok = true;
  for (std::uint32_t i = 0; i < tp_stream_count; ++i) ok = run(tp_streams[i]) && ok;
  write(ok ? "done\n" : "done with errors\n");
  return ok ? 0 : 1;
}
