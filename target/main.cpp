// A Cortex-M image of the firmware: runs each embedded command stream (recorded on the host by
// `tinyphong record`, linked in by streams.S) through a fresh tp::fw::Device in a static memory
// block, and prints per stream
//     stream NAME HASH          (FNV-1a 64 of the framebuffer's colour bytes, target/fnv1a.hpp)
// or  stream NAME error CODE at word OFFSET   (target/report.hpp, as the replay image prints them)
// then "done"; exits (semihosting) with success iff every stream ran. tests/target compares
// the hashes with `tinyphong replay --hash` of the same .tpcmd files.
//
// Built with TP_COST (the m3-O2-cost-* images of scripts/target-cost.sh), each stream runs in
// two parts, the setup and then everything from the first draw on (draws, the model-views
// between them, end_frame), with the MPS2's CMSDK timer 0 read around the second part; it
// prints "cost NAME TICKS PIXELS_WRITTEN PIXELS_SHADED LDIVMOD ULDIVMOD WRAPPER", and once,
// first, a calibration: "calibration INSTRUCTIONS TICKS" of a loop of known length. Under QEMU's
// -icount shift=0 the ticks are proportional to guest instructions. LDIVMOD and ULDIVMOD are
// the calls of the 64-bit division helpers __aeabi_ldivmod and __aeabi_uldivmod in that part,
// counted by the wrappers of target/divcount.S, and WRAPPER the instructions those wrappers
// add per call (for the script to take out of the count).
#include <cstddef>
#include <cstdint>
#include <new>
#include <span>

#include "firmware/device.hpp"
#include "target/report.hpp"
#include "target/semihost.hpp"
#include "target/stack_mark.hpp"

// 3.5 MiB: the largest stream at the scenes' own resolutions (640x480 RGB888 with depth, the
// teapot's buffers, kb-adaptive's state: about 2.7 MB) with room to spare.
#ifndef TP_BLOCK_BYTES
#define TP_BLOCK_BYTES (7u << 19)
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

#ifdef TP_COST
// CMSDK APB timer 0 of the MPS2 FPGA images: a 32-bit down-counter at the 25 MHz peripheral
// clock (QEMU: hw/arm/mps2.c). Registers: CTRL, VALUE, RELOAD.
volatile std::uint32_t* timer0() { return reinterpret_cast<volatile std::uint32_t*>(0x40000000u); }
void timer_start() {
  timer0()[2] = 0xffffffffu;  // RELOAD
  timer0()[1] = 0xffffffffu;  // VALUE
  timer0()[0] = 1u;           // CTRL: enable
}
std::uint32_t timer_now() { return timer0()[1]; }

// target/divcount.S.
extern "C" std::uint32_t tp_ldivmod_calls, tp_uldivmod_calls;
constexpr std::uint32_t kDivWrapperInstructions = 7;

void print_calibration() {
  using namespace tp::target;
  constexpr std::uint32_t kIterations = 1000000;  // two instructions each: subs, bne
  std::uint32_t n = kIterations;
  const std::uint32_t t0 = timer_now();
  asm volatile("1: subs %0, %0, #1\n bne 1b" : "+r"(n) : : "cc");
  const std::uint32_t t1 = timer_now();
  write("calibration ");
  write_dec(2u * kIterations);
  write(" ");
  write_dec(t0 - t1);
  write("\n");
}

// The word offset of the first draw command (the stream's length if there is none).
std::size_t first_draw(const EmbeddedStream& s) {
  std::size_t at = 0;
  while (at < s.word_count &&
         (s.words[at] & 0xffffu) != static_cast<std::uint32_t>(tp::fw::Opcode::kDraw))
    at += 1 + (s.words[at] >> 16);
  return at < s.word_count ? at : s.word_count;
}

tp::fw::Error execute_timed(tp::fw::Device& device, const EmbeddedStream& s) {
  using namespace tp::target;
  const std::size_t split = first_draw(s);
  const std::span<const std::uint32_t> words(s.words, s.word_count);
  tp::fw::Error e = device.execute(words.first(split));
  if (e != tp::fw::Error::kOk) return e;
  const std::uint32_t ldiv0 = tp_ldivmod_calls, uldiv0 = tp_uldivmod_calls;
  const std::uint32_t t0 = timer_now();
  e = device.execute(words.subspan(split));
  const std::uint32_t t1 = timer_now();
  const std::uint32_t ldiv = tp_ldivmod_calls - ldiv0, uldiv = tp_uldivmod_calls - uldiv0;
  write("cost ");
  write(s.name);
  write(" ");
  write_dec(t0 - t1);
  write(" ");
  write_dec(device.counters().pixels_written);
  write(" ");
  write_dec(device.counters().pixels_shaded);
  write(" ");
  write_dec(ldiv);
  write(" ");
  write_dec(uldiv);
  write(" ");
  write_dec(kDivWrapperInstructions);
  write("\n");
  return e;
}
#endif

#ifdef TP_MEMORY_REPORT
// The block this build needs per linked method for a 160x120 RGB565 frame without a depth buffer,
// as "ID=BYTES+Vv+Ii": BYTES without a mesh, V more per vertex and I per index of the buffers'
// capacity (Method ids, firmware/types.hpp). A port's own figures: the method states are sized by
// its build's TP_MAX_LIGHTS (docs/TARGET.md, "A small part"; tests/target checks kb's).
void print_memory_report() {
  using namespace tp::target;
  using tp::fw::Device;
  tp::fw::ViewportCmd vp;
  vp.width = 160;
  vp.height = 120;
  vp.format = tp::fw::PixelFormat::kRgb565;
  vp.depth_buffer = false;
  constexpr std::uint32_t kMany = 64;  // a multiple of the 8-byte alignment of the buffers
  write("memory_required 160x120 rgb565 no-depth:");
  for (std::uint32_t id = 0; id < 32; ++id) {
    const auto m = static_cast<tp::fw::Method>(id);
    if (Device::method_bytes(m) == 0) continue;  // not linked
    const std::size_t none = Device::memory_required(vp, {}, m);
    const std::size_t vertices = Device::memory_required(vp, {kMany, 0}, m) - none;
    const std::size_t indices = Device::memory_required(vp, {0, kMany}, m) - none;
    write(" ");
    write_dec(id);
    write("=");
    write_dec(static_cast<std::uint32_t>(none));
    write("+");
    write_dec(static_cast<std::uint32_t>(vertices / kMany));
    write("v+");
    write_dec(static_cast<std::uint32_t>(indices / kMany));
    write("i");
  }
  write("\n");
}
#endif

bool run(const EmbeddedStream& s) {
  using namespace tp::target;
  auto* device = new (device_storage) tp::fw::Device(std::span<std::byte>(block, sizeof block));
#ifdef TP_COST
  const tp::fw::Error e = execute_timed(*device, s);
#else
  const tp::fw::Error e = device->execute(std::span<const std::uint32_t>(s.words, s.word_count));
#endif
  const bool ok = report_stream(s.name, *device, e, device->words_consumed());
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
#ifdef TP_COST
  timer_start();
  print_calibration();
#endif
#ifdef TP_MEMORY_REPORT
  print_memory_report();
#endif
  paint_stack();
  bool ok = true;
  for (std::uint32_t i = 0; i < tp_stream_count; ++i) ok = run(tp_streams[i]) && ok;
  write("stack high-water mark ");
  write_dec(stack_used_bytes());
  write(" bytes\n");
  write(ok ? "done\n" : "done with errors\n");
  return ok ? 0 : 1;
}
