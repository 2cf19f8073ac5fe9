// The "type" of a control message, parsed once (like Beast's http::verb / string_to_verb) so
// that the schema, the validation, the application and the session switch over an enum and a
// misspelt type is a compile error rather than a branch that never matches.
#pragma once
#include <string_view>

namespace tp::server {

// The names are the wire strings (docs/SERVER.md, "Client → server control messages").
enum class ControlType {
  unknown = 0,  // not a type the server knows: refused with "unknown message type '…'"
  set_method,
  set_budget,
  set_exponent,
  set_material,
  add_light,
  remove_light,
  set_light,
  set_scene,
  set_resolution,
  animate,
  pause,
  step,
  reference,
  specular_only,
  compare_all,
  ack,
  get_state,
};

// The exact wire string, else ControlType::unknown (case matters, as in the protocol).
ControlType string_to_control_type(std::string_view s);

// The wire string ("unknown" for ControlType::unknown), for replies and logging.
std::string_view to_string(ControlType t);

}  // namespace tp::server
