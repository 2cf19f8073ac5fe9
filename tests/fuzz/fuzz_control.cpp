// Fuzz target: the server's control messages (server/control.cpp, control_type.cpp) on
// arbitrary text. The whole input is one message; then each of its lines is one message,
// applied in turn to a PatternSource, so that sequences (sixteen add_light, then one more) are
// reached too. Properties, besides no crash, no hang, no undefined behaviour and no exception:
//  - parse_control gives a command with a known type, or an error saying what is wrong;
//  - apply_control that fails leaves the source's settings and the loop flags as they were.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "server/control.hpp"
#include "server/pattern_source.hpp"
#include "tests/fuzz/fuzz_check.hpp"

namespace {

using tp::server::ViewSettings;

bool same_lights(const ViewSettings& a, const ViewSettings& b) {
  if (a.lights.size() != b.lights.size()) return false;
  for (std::size_t i = 0; i < a.lights.size(); ++i)
    if (a.lights[i].point != b.lights[i].point || a.lights[i].vector != b.lights[i].vector ||
        a.lights[i].color != b.lights[i].color)
      return false;
  return true;
}

bool same(const ViewSettings& a, const ViewSettings& b) {
  return a.scene == b.scene && a.method == b.method && a.use_ab == b.use_ab && a.n == b.n &&
         a.a == b.a && a.b == b.b && a.ka == b.ka && a.kd == b.kd && a.ks == b.ks &&
         a.color == b.color && same_lights(a, b) && a.width == b.width && a.height == b.height;
}

bool same(const tp::server::LoopFlags& a, const tp::server::LoopFlags& b) {
  return a.animate == b.animate && a.paused == b.paused && a.reference == b.reference;
}

// Parses one message and, if it is a setting, applies it; checks both steps' properties.
void message(const std::string& text, tp::server::PatternSource& source,
             tp::server::LoopFlags& flags) {
  const tp::server::ParseResult parsed = tp::server::parse_control(text);
  if (!parsed.command) {
    TP_FUZZ_CHECK(!parsed.error.empty(), "a refused message gets a reason");
    return;
  }
  const tp::server::Command& c = *parsed.command;
  TP_FUZZ_CHECK(c.type != tp::server::ControlType::unknown, "a parsed message has a known type");
  if (c.type == tp::server::ControlType::ack || c.type == tp::server::ControlType::get_state)
    return;  // the session answers these itself
  const ViewSettings before = source.settings();
  const tp::server::LoopFlags flags_before = flags;
  bool step = false;
  const tp::server::Result r = tp::server::apply_control(c, source, flags, step);
  if (!r.ok()) {
    TP_FUZZ_CHECK(!r.message().empty(), "a refused setting gets a reason");
    TP_FUZZ_CHECK(same(before, source.settings()), "a refused setting changed the settings");
    TP_FUZZ_CHECK(same(flags_before, flags), "a refused setting changed the loop flags");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  tp::server::PatternSource source;
  tp::server::LoopFlags flags;
  message(text, source, flags);
  for (std::size_t start = 0; start < text.size();) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    message(text.substr(start, end - start), source, flags);
    start = end + 1;
  }
  return 0;
}
