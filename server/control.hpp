// Control messages (small JSON objects, docs/SERVER.md "Control messages"): parsing and
// validation happen in the session, at once; application happens in the render loop between
// frames. A message that fails either step gets an error reply naming the problem and changes
// nothing.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>

#include "server/frame_source.hpp"

namespace tp::server {

inline constexpr std::size_t kControlMessageLimit = 4096;  // bytes; larger → error reply
inline constexpr std::size_t kMaxLights = 16;  // the device's light slots (host::kMaxLights)
inline constexpr int kMinSize = 16, kMaxSize = 2048;

// Flags the render loop owns (not part of the scene).
struct LoopFlags {
  bool animate = true;
  bool paused = false;
  bool reference = false;
};

struct Command {
  std::string type;  // the message's "type", echoed in replies
  // Which fields are present depends on type; the parser checks the combination.
  std::optional<std::string> text;  // method / scene name
  std::optional<double> n, a, b, ka, kd, ks;
  std::optional<std::array<double, 3>> color, vector;
  std::optional<bool> on, point;
  std::optional<int> index, width, height;
  std::uint32_t ack_id = 0;
  int ack_kind = 0;
};

struct ParseResult {
  std::optional<Command> command;
  std::string error;  // set when command is empty
};

ParseResult parse_control(const std::string& text);

// Applies a validated command (not "ack"/"get_state") to the source and loop flags.
// Returns "" on success or the problem (state untouched). step_requested is set by "step".
std::string apply_control(const Command& c, FrameSource& src, LoopFlags& flags,
                          bool& step_requested);

}  // namespace tp::server
