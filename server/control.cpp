#include "server/control.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/scene.hpp"

namespace tp::server {
namespace {

using nlohmann::json;

// Allowed fields per message type; anything else is refused by name. A switch, so that a new
// type without an entry is a compiler warning.
std::span<const std::string_view> allowed_fields(ControlType t) {
  static constexpr std::string_view method[] = {"method"}, levels[] = {"levels"},
                                    exponent[] = {"n", "a", "b"},
                                    material[] = {"ka", "kd", "ks", "color"},
                                    add_light[] = {"kind", "vector", "color"}, index[] = {"index"},
                                    set_light[] = {"index", "kind", "vector", "color"},
                                    name[] = {"name"}, size[] = {"width", "height"}, on[] = {"on"},
                                    ack[] = {"id", "kind"};
  switch (t) {
    case ControlType::set_method: return method;
    case ControlType::set_budget: return levels;
    case ControlType::set_exponent: return exponent;
    case ControlType::set_material: return material;
    case ControlType::add_light: return add_light;
    case ControlType::remove_light: return index;
    case ControlType::set_light: return set_light;
    case ControlType::set_scene: return name;
    case ControlType::set_resolution: return size;
    case ControlType::animate:
    case ControlType::pause:
    case ControlType::reference:
    case ControlType::specular_only: return on;
    case ControlType::ack: return ack;
    case ControlType::step:
    case ControlType::compare_all:
    case ControlType::get_state:
    case ControlType::unknown: return {};
  }
  return {};
}

bool allows(ControlType t, std::string_view field) {
  const auto fields = allowed_fields(t);
  return std::find(fields.begin(), fields.end(), field) != fields.end();
}

Result field_error(const char* k, const std::string& what) {
  return Result::failure(std::string("'") + k + "' " + what);
}

// Each getter leaves out untouched when the field is absent (the combination check decides
// whether it was needed) and fails with the field named.
Result get_number(const json& j, const char* k, double lo, double hi, std::optional<double>& out) {
  if (!j.contains(k)) return Result::success();
  const json& v = j[k];
  if (!v.is_number()) return field_error(k, "must be a number");
  const double d = v.get<double>();
  if (!std::isfinite(d) || d < lo || d > hi)
    return field_error(k, "out of range [" + json(lo).dump() + ", " + json(hi).dump() + "]");
  out = d;
  return Result::success();
}

Result get_int(const json& j, const char* k, long lo, long hi, std::optional<int>& out) {
  if (!j.contains(k)) return Result::success();
  const json& v = j[k];
  if (!v.is_number_integer()) return field_error(k, "must be an integer");
  const auto i = v.get<long long>();
  if (i < lo || i > hi)
    return field_error(k, "out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  out = static_cast<int>(i);
  return Result::success();
}

Result get_vec3(const json& j, const char* k, double lo, double hi,
                std::optional<std::array<double, 3>>& out) {
  if (!j.contains(k)) return Result::success();
  const json& v = j[k];
  if (!v.is_array() || v.size() != 3) return field_error(k, "must be an array of 3 numbers");
  std::array<double, 3> a{};
  for (std::size_t i = 0; i < 3; ++i) {
    if (!v[i].is_number()) return field_error(k, "must be an array of 3 numbers");
    a[i] = v[i].get<double>();
    if (!std::isfinite(a[i]) || a[i] < lo || a[i] > hi)
      return field_error(
          k, "component out of range [" + json(lo).dump() + ", " + json(hi).dump() + "]");
  }
  out = a;
  return Result::success();
}

Result get_string(const json& j, const char* k, std::optional<std::string>& out) {
  if (!j.contains(k)) return Result::success();
  if (!j[k].is_string()) return field_error(k, "must be a string");
  auto s = j[k].get<std::string>();
  if (s.empty() || s.size() > kMaxNameBytes)
    return field_error(k, "must be 1 to " + std::to_string(kMaxNameBytes) + " bytes");
  out = s;
  return Result::success();
}

Result get_bool(const json& j, const char* k, std::optional<bool>& out) {
  if (!j.contains(k)) return Result::success();
  if (!j[k].is_boolean()) return field_error(k, "must be true or false");
  out = j[k].get<bool>();
  return Result::success();
}

// "kind" means the frame kind in an ack and the light kind elsewhere.
Result get_kind(const json& j, Command& c) {
  if (!j.contains("kind")) return Result::success();
  if (!j["kind"].is_string()) return Result::failure("'kind' must be a string");
  const auto k = j["kind"].get<std::string>();
  if (c.type == ControlType::ack) {
    if (k != "device" && k != "reference")
      return Result::failure("'kind' must be \"device\" or \"reference\"");
    c.ack_kind = k == "reference" ? 1 : 0;
  } else {
    if (k != "directional" && k != "point")
      return Result::failure("'kind' must be \"directional\" or \"point\"");
    c.point = k == "point";
  }
  return Result::success();
}

bool directional_zero(bool point, const std::array<double, 3>& v) {
  return !point && std::hypot(v[0], v[1], v[2]) < 1e-6;
}

// The fields each type needs together, once every present field is valid on its own.
Result check_combination(const json& j, Command& c) {
  auto need = [&](const char* k) {
    return j.contains(k) ? Result::success() : Result::failure(std::string("missing '") + k + "'");
  };
  switch (c.type) {
    case ControlType::set_method: return need("method");
    case ControlType::set_budget: return need("levels");
    case ControlType::set_scene: return need("name");
    case ControlType::set_resolution: {
      Result r = need("width");
      return r.ok() ? need("height") : r;
    }
    case ControlType::animate:
    case ControlType::pause:
    case ControlType::reference:
    case ControlType::specular_only: return need("on");
    case ControlType::remove_light: return need("index");
    case ControlType::add_light: {
      Result r = need("kind");
      if (r.ok()) r = need("vector");
      if (!r.ok()) return r;
      if (directional_zero(*c.point, *c.vector))
        return Result::failure("'vector' of a directional light must not be zero");
      return Result::success();
    }
    case ControlType::set_light: {
      if (Result r = need("index"); !r.ok()) return r;
      if (!c.point && !c.vector && !c.color)
        return Result::failure("set_light needs 'kind', 'vector' or 'color'");
      return Result::success();
    }
    case ControlType::set_material:
      if (!c.ka && !c.kd && !c.ks && !c.color)
        return Result::failure("set_material needs 'ka', 'kd', 'ks' or 'color'");
      return Result::success();
    case ControlType::set_exponent: {
      const bool has_n = c.n.has_value(), has_ab = c.a.has_value() || c.b.has_value();
      if (has_n == has_ab)
        return Result::failure("set_exponent needs either 'n' or both 'a' and 'b'");
      if (has_n && *c.n != std::floor(*c.n))  // the device's exponent is an integer
        return Result::failure("'n' must be a whole number");
      if (has_ab && (!c.a || !c.b)) return Result::failure("set_exponent needs both 'a' and 'b'");
      if (has_ab && !(*c.a < *c.b))
        return Result::failure("'a' must be less than 'b' (Kuijk-Blake f: a < b)");
      return Result::success();
    }
    case ControlType::ack: {
      if (!j.contains("id") || !j["id"].is_number_unsigned())
        return Result::failure("'id' must be an unsigned integer");
      const auto id = j["id"].get<std::uint64_t>();
      if (id > 0xffffffffULL) return Result::failure("'id' out of range");
      c.ack_id = static_cast<std::uint32_t>(id);
      return Result::success();
    }
    case ControlType::step:
    case ControlType::compare_all:
    case ControlType::get_state:
    case ControlType::unknown: return Result::success();
  }
  return Result::success();
}

// Every field on its own, then the combination; the first problem in this order is the reply.
Result read_fields(const json& j, Command& c) {
  constexpr double kPi = std::numbers::pi;
  const double color_max = c.type == ControlType::set_material ? 1.0 : 4.0;
  // Ranges: n up to kMaxExponentN; angles (a, b) in radians within [kMinAngleAB, π/2], the scene
  // files' (host/scene.hpp; π/2 is the device's bound too, and its set_material refused b above
  // it with a message naming no field); reflectances in
  // [0, 1]; material colours in [0, 1], light colours up to 4 (intensity); light vectors within
  // ±1000; a light index names one of the device's light slots.
  const Result checks[] = {
      get_string(j, "method", c.text),
      get_string(j, "name", c.text),
      get_number(j, "n", 1, kMaxExponentN, c.n),
      get_number(j, "a", host::kMinAngleAB, kPi / 2, c.a),
      get_number(j, "b", host::kMinAngleAB, kPi / 2, c.b),
      get_number(j, "ka", 0, 1, c.ka),
      get_number(j, "kd", 0, 1, c.kd),
      get_number(j, "ks", 0, 1, c.ks),
      get_vec3(j, "color", 0, color_max, c.color),
      get_vec3(j, "vector", -1000, 1000, c.vector),
      get_bool(j, "on", c.on),
      get_kind(j, c),
      get_int(j, "index", 0, static_cast<long>(fw::kMaxLights) - 1, c.index),
      get_int(j, "levels", 1, static_cast<long>(fw::kMaxBudgetLevels), c.levels),
      get_int(j, "width", kMinSize, kMaxSize, c.width),
      get_int(j, "height", kMinSize, kMaxSize, c.height),
  };
  for (const Result& r : checks)
    if (!r.ok()) return r;
  return check_combination(j, c);
}

}  // namespace

ParseResult parse_control(const std::string& text) {
  if (text.size() > kControlMessageLimit)
    return {std::nullopt, "message too large (" + std::to_string(text.size()) + " bytes > " +
                              std::to_string(kControlMessageLimit) + ")"};
  // A NUL byte ends nlohmann's input: {"type":"step"}\0 and whatever followed were taken as the
  // message before it (found by review, 2026-12-07). JSON text holds none.
  if (const std::size_t nul = text.find('\0'); nul != std::string::npos)
    return {std::nullopt, "malformed JSON: a NUL byte (0x00) at byte " + std::to_string(nul + 1)};
  // A key given twice in one object: JSON lets nlohmann keep the last value, so
  // {"type":"step","type":"set_budget","levels":3} was a set_budget. Refused, as the scene
  // files refuse it (host/scene.cpp).
  std::vector<std::set<std::string>> keys;
  std::string twice;
  const json::parser_callback_t note_keys = [&](int, json::parse_event_t event, json& parsed) {
    if (event == json::parse_event_t::object_start) keys.emplace_back();
    if (event == json::parse_event_t::object_end) keys.pop_back();
    if (event == json::parse_event_t::key && twice.empty() &&
        !keys.back().insert(parsed.get<std::string>()).second)
      twice = parsed.get<std::string>();
    return true;
  };
  json j;
  try {
    j = json::parse(text, note_keys);
  } catch (const json::exception& e) {
    // The library's own words name the problem and where: "number overflow parsing '1e400'",
    // "syntax error while parsing value - invalid literal; last read: 'tru'" (a bare "malformed
    // JSON" named neither; found by review, 2026-12-07).
    return {std::nullopt, "malformed JSON: " + clip_utf8(e.what(), 200)};
  }
  if (!j.is_object()) return {std::nullopt, "message must be a JSON object"};
  const std::string duplicate = "duplicate key '" + clip_utf8(twice, 64) + "'";
  if (twice == "type") return {std::nullopt, duplicate};
  if (!j.contains("type") || !j["type"].is_string()) return {std::nullopt, "missing string 'type'"};
  const auto type_name = j["type"].get<std::string>();
  Command c;
  c.type = string_to_control_type(type_name);
  if (c.type == ControlType::unknown)
    return {std::nullopt, "unknown message type '" + clip_utf8(type_name, 64) + "'"};
  if (!twice.empty()) return {std::nullopt, duplicate, c.type};
  for (const auto& [k, v] : j.items())
    if (k != "type" && !allows(c.type, k))
      return {std::nullopt, "unknown field '" + clip_utf8(k, 64) + "'", c.type};
  if (Result r = read_fields(j, c); !r.ok()) return {std::nullopt, r.message(), c.type};
  const ControlType type = c.type;
  return {std::move(c), "", type};
}

std::string clip_utf8(std::string_view text, std::size_t max_bytes) {
  if (text.size() <= max_bytes) return std::string(text);
  std::size_t end = max_bytes;
  // A continuation byte (10xxxxxx) at the cut belongs to a sequence that started before it.
  while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80) --end;
  return std::string(text.substr(0, end));
}

bool changes_loop_flags_only(ControlType t) {
  return t == ControlType::animate || t == ControlType::pause || t == ControlType::step ||
         t == ControlType::reference || t == ControlType::compare_all;
}

namespace {

Result edit_lights(const Command& c, ViewSettings& s) {
  if (c.type == ControlType::add_light) {
    if (s.lights.size() >= fw::kMaxLights)
      return Result::failure("too many lights (at most " + std::to_string(fw::kMaxLights) + ")");
    LightSetting l;
    l.point = *c.point;
    l.vector = *c.vector;
    if (c.color) l.color = *c.color;
    s.lights.push_back(l);
    return Result::success();
  }
  const auto i = static_cast<std::size_t>(*c.index);
  if (i >= s.lights.size()) return Result::failure("no light with index " + std::to_string(i));
  if (c.type == ControlType::remove_light) {
    if (s.lights.size() == 1) return Result::failure("cannot remove the last light");
    s.lights.erase(s.lights.begin() + static_cast<std::ptrdiff_t>(i));
    return Result::success();
  }
  LightSetting& l = s.lights[i];
  if (c.point) l.point = *c.point;
  if (c.vector) l.vector = *c.vector;
  if (c.color) l.color = *c.color;
  if (directional_zero(l.point, l.vector))
    return Result::failure("'vector' of a directional light must not be zero");
  return Result::success();
}

}  // namespace

Result apply_control(const Command& c, FrameSource& src, LoopFlags& flags, bool& step_requested) {
  ViewSettings s = src.settings();  // edit a copy: the source keeps the old one on failure
  switch (c.type) {
    case ControlType::animate: flags.animate = *c.on; return Result::success();
    case ControlType::pause: flags.paused = *c.on; return Result::success();
    case ControlType::reference: flags.reference = *c.on; return Result::success();
    case ControlType::step: step_requested = true; return Result::success();
    case ControlType::compare_all: flags.compare_requested = true; return Result::success();
    case ControlType::set_scene: return src.load_scene(*c.text);
    case ControlType::set_method: s.method = *c.text; break;
    case ControlType::set_budget: s.budget = *c.levels; break;
    case ControlType::specular_only: s.specular_only = *c.on; break;
    case ControlType::set_exponent:
      s.use_ab = c.a.has_value();
      if (s.use_ab) {
        s.a = *c.a;
        s.b = *c.b;
      } else {
        s.n = *c.n;
      }
      break;
    case ControlType::set_material:
      if (c.ka) s.ka = *c.ka;
      if (c.kd) s.kd = *c.kd;
      if (c.ks) s.ks = *c.ks;
      if (c.color) s.color = *c.color;
      break;
    case ControlType::set_resolution:
      s.width = *c.width;
      s.height = *c.height;
      break;
    case ControlType::add_light:
    case ControlType::remove_light:
    case ControlType::set_light:
      if (Result r = edit_lights(c, s); !r.ok()) return r;
      break;
    case ControlType::ack:
    case ControlType::get_state:
    case ControlType::unknown:
      return Result::failure("message type '" + std::string(to_string(c.type)) +
                             "' is not a setting");
  }
  return src.apply(s);
}

}  // namespace tp::server
