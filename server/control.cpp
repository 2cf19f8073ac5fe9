#include "server/control.hpp"

#include <cmath>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

namespace tp::server {
namespace {

using nlohmann::json;

// Allowed fields per message type; anything else is refused by name.
const std::map<std::string, std::set<std::string>>& schema() {
  static const std::map<std::string, std::set<std::string>> s = {
      {"set_method", {"method"}},
      {"set_exponent", {"n", "a", "b"}},
      {"set_material", {"ka", "kd", "ks", "color"}},
      {"add_light", {"kind", "vector", "color"}},
      {"remove_light", {"index"}},
      {"set_light", {"index", "kind", "vector", "color"}},
      {"set_scene", {"name"}},
      {"set_resolution", {"width", "height"}},
      {"animate", {"on"}},
      {"pause", {"on"}},
      {"step", {}},
      {"reference", {"on"}},
      {"ack", {"id", "kind"}},
      {"get_state", {}},
  };
  return s;
}

// Each getter returns "" or the problem with the field named.
std::string get_number(const json& j, const char* k, double lo, double hi, std::optional<double>& out) {
  if (!j.contains(k)) return "";
  const json& v = j[k];
  if (!v.is_number()) return std::string("'") + k + "' must be a number";
  const double d = v.get<double>();
  if (!std::isfinite(d) || d < lo || d > hi)
    return std::string("'") + k + "' out of range [" + json(lo).dump() + ", " + json(hi).dump() + "]";
  out = d;
  return "";
}

std::string get_int(const json& j, const char* k, long lo, long hi, std::optional<int>& out) {
  if (!j.contains(k)) return "";
  const json& v = j[k];
  if (!v.is_number_integer()) return std::string("'") + k + "' must be an integer";
  const auto i = v.get<long long>();
  if (i < lo || i > hi)
    return std::string("'") + k + "' out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  out = static_cast<int>(i);
  return "";
}

std::string get_vec3(const json& j, const char* k, double lo, double hi,
                     std::optional<std::array<double, 3>>& out) {
  if (!j.contains(k)) return "";
  const json& v = j[k];
  if (!v.is_array() || v.size() != 3) return std::string("'") + k + "' must be an array of 3 numbers";
  std::array<double, 3> a{};
  for (std::size_t i = 0; i < 3; ++i) {
    if (!v[i].is_number()) return std::string("'") + k + "' must be an array of 3 numbers";
    a[i] = v[i].get<double>();
    if (!std::isfinite(a[i]) || a[i] < lo || a[i] > hi)
      return std::string("'") + k + "' component out of range [" + json(lo).dump() + ", " + json(hi).dump() + "]";
  }
  out = a;
  return "";
}

std::string get_string(const json& j, const char* k, std::optional<std::string>& out) {
  if (!j.contains(k)) return "";
  if (!j[k].is_string()) return std::string("'") + k + "' must be a string";
  auto s = j[k].get<std::string>();
  if (s.empty() || s.size() > 64) return std::string("'") + k + "' must be 1 to 64 characters";
  out = s;
  return "";
}

std::string get_bool(const json& j, const char* k, std::optional<bool>& out) {
  if (!j.contains(k)) return "";
  if (!j[k].is_boolean()) return std::string("'") + k + "' must be true or false";
  out = j[k].get<bool>();
  return "";
}

std::string get_kind(const json& j, const std::string& type, Command& c) {
  if (!j.contains("kind")) return "";
  if (!j["kind"].is_string()) return "'kind' must be a string";
  const auto k = j["kind"].get<std::string>();
  if (type == "ack") {
    if (k != "device" && k != "reference") return "'kind' must be \"device\" or \"reference\"";
    c.ack_kind = k == "reference" ? 1 : 0;
  } else {
    if (k != "directional" && k != "point") return "'kind' must be \"directional\" or \"point\"";
    c.point = k == "point";
  }
  return "";
}

std::string check_combination(const json& j, Command& c) {
  const std::string& t = c.type;
  auto need = [&](const char* k) { return j.contains(k) ? std::string() : std::string("missing '") + k + "'"; };
  std::string e;
  if (t == "set_method") return need("method");
  if (t == "set_scene") return need("name");
  if (t == "set_resolution") return !(e = need("width")).empty() ? e : need("height");
  if (t == "animate" || t == "pause" || t == "reference") return need("on");
  if (t == "remove_light") return need("index");
  if (t == "add_light") {
    if (!(e = need("kind")).empty() || !(e = need("vector")).empty()) return e;
    const auto& v = *c.vector;
    if (!*c.point && std::hypot(v[0], v[1], v[2]) < 1e-6) return "'vector' of a directional light must not be zero";
    return "";
  }
  if (t == "set_light") {
    if (!(e = need("index")).empty()) return e;
    if (!c.point && !c.vector && !c.color) return "set_light needs 'kind', 'vector' or 'color'";
    return "";
  }
  if (t == "set_material" && !c.ka && !c.kd && !c.ks && !c.color)
    return "set_material needs 'ka', 'kd', 'ks' or 'color'";
  if (t == "set_exponent") {
    const bool has_n = c.n.has_value(), has_ab = c.a.has_value() || c.b.has_value();
    if (has_n == has_ab) return "set_exponent needs either 'n' or both 'a' and 'b'";
    if (has_ab && (!c.a || !c.b)) return "set_exponent needs both 'a' and 'b'";
    if (has_ab && !(*c.a < *c.b)) return "'a' must be less than 'b' (Kuijk-Blake f: a < b)";
  }
  if (t == "ack") {
    if (!j.contains("id") || !j["id"].is_number_unsigned()) return "'id' must be an unsigned integer";
    const auto id = j["id"].get<std::uint64_t>();
    if (id > 0xffffffffULL) return "'id' out of range";
    c.ack_id = static_cast<std::uint32_t>(id);
  }
  return "";
}

}  // namespace

ParseResult parse_control(const std::string& text) {
  if (text.size() > kControlMessageLimit)
    return {std::nullopt, "message too large (" + std::to_string(text.size()) + " bytes > " +
                              std::to_string(kControlMessageLimit) + ")"};
  json j = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return {std::nullopt, "malformed JSON"};
  if (!j.is_object()) return {std::nullopt, "message must be a JSON object"};
  if (!j.contains("type") || !j["type"].is_string()) return {std::nullopt, "missing string 'type'"};
  Command c;
  c.type = j["type"].get<std::string>();
  const auto it = schema().find(c.type);
  if (it == schema().end()) return {std::nullopt, "unknown message type '" + c.type.substr(0, 64) + "'"};
  for (const auto& [k, v] : j.items())
    if (k != "type" && !it->second.count(k)) return {std::nullopt, "unknown field '" + k.substr(0, 64) + "'"};
  std::string e;
  const double kPi = 3.14159265358979323846;
  // Ranges: n up to 1000 (the device may refuse more); angles (a, b) in radians within (0, π];
  // reflectances in [0, 1]; light colours up to 4 (intensity); light vectors within ±1000.
  if (!(e = get_string(j, "method", c.text)).empty() || !(e = get_string(j, "name", c.text)).empty() ||
      !(e = get_number(j, "n", 1, 1000, c.n)).empty() || !(e = get_number(j, "a", 1e-4, kPi, c.a)).empty() ||
      !(e = get_number(j, "b", 1e-4, kPi, c.b)).empty() || !(e = get_number(j, "ka", 0, 1, c.ka)).empty() ||
      !(e = get_number(j, "kd", 0, 1, c.kd)).empty() || !(e = get_number(j, "ks", 0, 1, c.ks)).empty() ||
      !(e = get_vec3(j, "color", 0, c.type == "set_material" ? 1 : 4, c.color)).empty() ||
      !(e = get_vec3(j, "vector", -1000, 1000, c.vector)).empty() ||
      !(e = get_bool(j, "on", c.on)).empty() || !(e = get_kind(j, c.type, c)).empty() ||
      !(e = get_int(j, "index", 0, static_cast<long>(kMaxLights) - 1, c.index)).empty() ||
      !(e = get_int(j, "width", kMinSize, kMaxSize, c.width)).empty() ||
      !(e = get_int(j, "height", kMinSize, kMaxSize, c.height)).empty() ||
      !(e = check_combination(j, c)).empty())
    return {std::nullopt, e};
  return {std::move(c), ""};
}

namespace {

std::string edit_lights(const Command& c, ViewSettings& s) {
  if (c.type == "add_light") {
    if (s.lights.size() >= kMaxLights) return "too many lights (at most " + std::to_string(kMaxLights) + ")";
    LightSetting l;
    l.point = *c.point;
    l.vector = *c.vector;
    if (c.color) l.color = *c.color;
    s.lights.push_back(l);
    return "";
  }
  const auto i = static_cast<std::size_t>(*c.index);
  if (i >= s.lights.size()) return "no light with index " + std::to_string(i);
  if (c.type == "remove_light") {
    if (s.lights.size() == 1) return "cannot remove the last light";
    s.lights.erase(s.lights.begin() + static_cast<std::ptrdiff_t>(i));
    return "";
  }
  LightSetting& l = s.lights[i];
  if (c.point) l.point = *c.point;
  if (c.vector) l.vector = *c.vector;
  if (c.color) l.color = *c.color;
  if (!l.point && std::hypot(l.vector[0], l.vector[1], l.vector[2]) < 1e-6)
    return "'vector' of a directional light must not be zero";
  return "";
}

}  // namespace

std::string apply_control(const Command& c, FrameSource& src, LoopFlags& flags, bool& step_requested) {
  const std::string& t = c.type;
  if (t == "animate") { flags.animate = *c.on; return ""; }
  if (t == "pause") { flags.paused = *c.on; return ""; }
  if (t == "reference") { flags.reference = *c.on; return ""; }
  if (t == "step") { step_requested = true; return ""; }
  if (t == "set_scene") return src.load_scene(*c.text);
  ViewSettings s = src.settings();  // edit a copy: the source keeps the old one on failure
  if (t == "set_method") {
    s.method = *c.text;
  } else if (t == "set_exponent") {
    s.use_ab = c.a.has_value();
    if (s.use_ab) { s.a = *c.a; s.b = *c.b; } else { s.n = *c.n; }
  } else if (t == "set_material") {
    if (c.ka) s.ka = *c.ka;
    if (c.kd) s.kd = *c.kd;
    if (c.ks) s.ks = *c.ks;
    if (c.color) s.color = *c.color;
  } else if (t == "set_resolution") {
    s.width = *c.width;
    s.height = *c.height;
  } else if (t == "add_light" || t == "remove_light" || t == "set_light") {
    if (auto e = edit_lights(c, s); !e.empty()) return e;
  } else {
    return "message type '" + t + "' is not a setting";
  }
  return src.apply(s);
}

}  // namespace tp::server
