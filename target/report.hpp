// The line every Cortex-M image prints per stream, which tests/target compares with the host's
// hashes (`tinyphong replay --hash`): "stream NAME HASH" (FNV-1a 64 of the framebuffer's colour
// bytes, target/fnv1a.hpp) when the stream gave a frame, else "stream NAME error CODE at word
// OFFSET".
#pragma once

#include <cstddef>
#include <cstdint>

#include "firmware/device.hpp"
#include "target/fnv1a.hpp"
#include "target/semihost.hpp"

namespace tp::target {

// For a stream that `device` ran up to word `word` with error `e`: whether it gave a frame (every
// command ran and it set a viewport; otherwise the error is printed, 0 for a stream without a
// viewport).
inline bool report_stream(const char* name, const fw::Device& device, fw::Error e,
                          std::size_t word) {
  write("stream ");
  write(name);
  const bool frame = e == fw::Error::kOk && device.state().viewport_set;
  if (frame) {
    write(" ");
    write_hex64(framebuffer_fnv1a(device.framebuffer()));
  } else {
    write(" error ");
    write_dec(static_cast<std::uint32_t>(e));
    write(" at word ");
    write_dec(word);
  }
  write("\n");
  return frame;
}

}  // namespace tp::target
