// Control messages (small JSON objects, docs/SERVER.md "Control messages"): parsing and
// validation happen in the session, at once; application happens in the render loop between
// frames. A message that fails either step gets an error reply naming the problem and changes
// nothing.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "firmware/types.hpp"
#include "server/control_type.hpp"
#include "server/frame_source.hpp"
#include "server/result.hpp"

namespace tp::server {

inline constexpr std::size_t kControlMessageLimit = 4096;  // bytes; larger → error reply
// A name a message carries (a scene's, a method's): 1 to this many bytes. The scenes the server
// offers keep to it too (server/device_source.cpp).
inline constexpr std::size_t kMaxNameBytes = 64;
// The viewer's own sizes, inside what the device accepts (fw::kMaxDimension); the exponent is
// the device's own bound, the same one the scene reader states (1..fw::kMaxExponent).
inline constexpr int kMinSize = 16, kMaxSize = 2048;
inline constexpr double kMaxExponentN = fw::kMaxExponent;
static_assert(kMaxSize <= static_cast<int>(fw::kMaxDimension));

// Flags the render loop owns (not part of the scene).
struct LoopFlags {
  bool animate = true;
  bool paused = false;
  bool reference = false;
  bool compare_requested = false;  // compare_all: the render loop takes it (and clears it)
};

struct Command {
  ControlType type = ControlType::unknown;  // never unknown once parsed
  // Which fields are present depends on type; the parser checks the combination.
  std::optional<std::string> text;  // method / scene name
  std::optional<double> n, a, b, ka, kd, ks;
  std::optional<std::array<double, 3>> color, vector;
  std::optional<bool> on, point;
  std::optional<int> index, width, height, levels;
  std::uint32_t ack_id = 0;
  int ack_kind = 0;
};

struct ParseResult {
  std::optional<Command> command;
  std::string error;  // set when command is empty
  // The message's type when it names one the server knows, even when its fields are refused:
  // the error reply names the request it answers.
  ControlType type = ControlType::unknown;
};

// At most max_bytes of text, cut before a UTF-8 sequence that would not fit whole: a client's
// text quoted in an error reply stays valid UTF-8.
std::string clip_utf8(std::string_view text, std::size_t max_bytes);

ParseResult parse_control(const std::string& text);

// True for the types that only change the render loop's flags (LoopFlags, a step, a comparison),
// not what a frame looks like: after them the current image need not be rendered again.
bool changes_loop_flags_only(ControlType t);

// Applies a validated command (not ack/get_state) to the source and loop flags; on failure the
// state is untouched. step_requested is set by step.
Result apply_control(const Command& c, FrameSource& src, LoopFlags& flags, bool& step_requested);

}  // namespace tp::server
