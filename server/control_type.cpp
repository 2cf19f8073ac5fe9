#include "server/control_type.hpp"

#include <array>
#include <utility>

namespace tp::server {
namespace {

// One table for both directions, so a type's wire string is written once.
constexpr std::array<std::pair<ControlType, std::string_view>, 17> kNames = {{
    {ControlType::set_method, "set_method"},
    {ControlType::set_budget, "set_budget"},
    {ControlType::set_exponent, "set_exponent"},
    {ControlType::set_material, "set_material"},
    {ControlType::add_light, "add_light"},
    {ControlType::remove_light, "remove_light"},
    {ControlType::set_light, "set_light"},
    {ControlType::set_scene, "set_scene"},
    {ControlType::set_resolution, "set_resolution"},
    {ControlType::animate, "animate"},
    {ControlType::pause, "pause"},
    {ControlType::step, "step"},
    {ControlType::reference, "reference"},
    {ControlType::specular_only, "specular_only"},
    {ControlType::compare_all, "compare_all"},
    {ControlType::ack, "ack"},
    {ControlType::get_state, "get_state"},
}};

}  // namespace

ControlType string_to_control_type(std::string_view s) {
  for (const auto& [type, name] : kNames)
    if (name == s) return type;
  return ControlType::unknown;
}

std::string_view to_string(ControlType t) {
  for (const auto& [type, name] : kNames)
    if (type == t) return name;
  return "unknown";
}

}  // namespace tp::server
