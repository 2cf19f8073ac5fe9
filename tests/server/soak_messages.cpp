#include "soak_messages.hpp"

#include <array>
#include <functional>

#include <nlohmann/json.hpp>

namespace tpt::soak {

using nlohmann::json;

int uniform_int(Rng& rng, int lo, int hi) {
  return std::uniform_int_distribution<int>(lo, hi)(rng);
}

double uniform_real(Rng& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

bool chance(Rng& rng, double p) { return std::bernoulli_distribution(p)(rng); }

const std::vector<Size>& soak_sizes() {
  static const std::vector<Size> sizes = {{16, 16},   {160, 120}, {240, 180}, {320, 240},
                                          {256, 256}, {400, 300}, {2048, 16}, {16, 600}};
  return sizes;
}

namespace {

template <typename T>
const T& pick(Rng& rng, const std::vector<T>& v) {
  return v[static_cast<std::size_t>(uniform_int(rng, 0, static_cast<int>(v.size()) - 1))];
}

json vec3(Rng& rng, double lo, double hi) {
  return json::array(
      {uniform_real(rng, lo, hi), uniform_real(rng, lo, hi), uniform_real(rng, lo, hi)});
}

json exponent(Rng& rng) {
  if (chance(rng, 0.7)) {
    // Log-uniform over the whole documented range 1..10,000.
    return {{"type", "set_exponent"}, {"n", std::round(std::pow(10.0, uniform_real(rng, 0, 4)))}};
  }
  const double a = uniform_real(rng, 0.01, 1.5);
  return {{"type", "set_exponent"}, {"a", a}, {"b", uniform_real(rng, a + 0.01, 3.14)}};
}

json light(Rng& rng, const char* type) {
  const bool point = chance(rng, 0.5);
  // Point lights anywhere within ±6 (the scenes' objects are about unit size); directional
  // lights away from zero (a zero direction is refused by the parser, not what is tested here).
  json v = point ? vec3(rng, -6, 6) : json::array({uniform_real(rng, 0.2, 1), 1.5, 1});
  return {{"type", type},
          {"kind", point ? "point" : "directional"},
          {"vector", v},
          {"color", vec3(rng, 0, 1.5)}};
}

json valid_json(Rng& rng, const Catalog& catalog) {
  switch (uniform_int(rng, 0, 7)) {
    case 0: return {{"type", "set_method"}, {"method", pick(rng, catalog.methods)}};
    case 1: return exponent(rng);
    case 2:
      return {{"type", "set_material"},
              {"ka", uniform_real(rng, 0, 0.3)},
              {"kd", uniform_real(rng, 0, 1)},
              {"ks", uniform_real(rng, 0, 1)},
              {"color", vec3(rng, 0, 1)}};
    case 3: return light(rng, "add_light");
    case 4: {
      json j = light(rng, "set_light");
      j["index"] = uniform_int(rng, 0, 3);
      return j;
    }
    case 5: return {{"type", "remove_light"}, {"index", uniform_int(rng, 0, 3)}};
    case 6: return {{"type", "step"}};
    default: return {{"type", "set_material"}, {"ks", uniform_real(rng, 0, 1)}};
  }
}

// Each returns the text of one kind of refused message.
const std::vector<std::function<std::string(Rng&)>>& invalid_kinds() {
  static const std::vector<std::function<std::string(Rng&)>> kinds = {
      [](Rng& rng) {  // truncated JSON
        std::string s = json{{"type", "set_exponent"}, {"n", 20}}.dump();
        return s.substr(0, static_cast<std::size_t>(uniform_int(rng, 0, int(s.size()) - 1)));
      },
      [](Rng&) { return std::string("[1,2,3]"); },
      [](Rng&) { return std::string("\"set_method\""); },
      [](Rng&) { return std::string("{}"); },
      [](Rng&) {
        return json{{"type", 42}}.dump();
      },
      [](Rng& rng) {
        return json{{"type", "explode" + std::to_string(rng() % 100)}}.dump();
      },
      [](Rng&) {
        return json{{"type", "step"}, {"extra", true}}.dump();
      },
      [](Rng&) {
        return json{{"type", "set_exponent"}, {"n", "twenty"}}.dump();
      },
      [](Rng& rng) {
        return json{{"type", "set_exponent"}, {"n", rng() % 2 ? 0 : 10001}}.dump();
      },
      [](Rng&) {
        return json{{"type", "set_exponent"}, {"a", 2.0}, {"b", 1.0}}.dump();
      },
      [](Rng&) {
        return json{{"type", "set_exponent"}, {"n", 20}, {"a", 0.1}}.dump();
      },
      [](Rng&) {
        return json{{"type", "set_material"}, {"ka", 1.5}}.dump();
      },
      [](Rng&) {
        return json{{"type", "set_material"}, {"color", {1, 2}}}.dump();
      },
      [](Rng&) {
        return json{{"type", "set_material"}}.dump();
      },
      [](Rng&) {
        return json{{"type", "add_light"}, {"kind", "point"}, {"vector", {1e9, 0, 0}}}.dump();
      },
      [](Rng&) {
        return json{{"type", "add_light"}, {"kind", "directional"}, {"vector", {0, 0, 0}}}.dump();
      },
      [](Rng&) {
        return json{{"type", "add_light"}, {"kind", "laser"}, {"vector", {1, 0, 0}}}.dump();
      },
      [](Rng&) {
        return json{{"type", "remove_light"}, {"index", 16}}.dump();
      },
      [](Rng&) {
        return json{{"type", "remove_light"}, {"index", -1}}.dump();
      },
      [](Rng&) {
        return json{{"type", "set_light"}, {"index", 0}}.dump();
      },
      [](Rng&) {
        return json{{"type", "set_method"}, {"method", "no-such-method"}}.dump();
      },
      [](Rng&) {
        return json{{"type", "set_method"}, {"method", std::string(65, 'm')}}.dump();
      },
      [](Rng&) {
        return json{{"type", "set_scene"}, {"name", "../../etc/passwd"}}.dump();
      },
      [](Rng&) {
        return json{{"type", "set_resolution"}, {"width", 15}, {"height", 16}}.dump();
      },
      [](Rng&) {
        return json{{"type", "set_resolution"}, {"width", 4096}, {"height", 16}}.dump();
      },
      [](Rng&) {
        return json{{"type", "set_resolution"}, {"width", 320}}.dump();
      },
      [](Rng&) {
        return json{{"type", "animate"}, {"on", "yes"}}.dump();
      },
      [](Rng&) {
        return json{{"type", "pause"}}.dump();
      },
      [](Rng&) {
        return json{{"type", "reference"}, {"on", 1}}.dump();
      },
      [](Rng& rng) {  // an ack of a frame this client was never sent
        return json{{"type", "ack"}, {"id", 4000000000u + rng() % 1000}, {"kind", "device"}}.dump();
      },
      [](Rng&) {
        return json{{"type", "ack"}, {"id", -1}, {"kind", "device"}}.dump();
      },
      [](Rng&) {
        return json{{"type", "ack"}, {"id", 1}, {"kind", "sideways"}}.dump();
      },
      [](Rng& rng) {  // over the 4 KiB application limit, under Beast's 64 KiB
        return json{
            {"type", "set_method"},
            {"method", std::string(static_cast<std::size_t>(uniform_int(rng, 4100, 60000)), 'x')}}
            .dump();
      },
      [](Rng&) {  // deep nesting within the size limit
        return std::string(1500, '[') + std::string(1500, ']');
      },
  };
  return kinds;
}

}  // namespace

ControlMessage random_valid_message(Rng& rng, const Catalog& catalog) {
  return {valid_json(rng, catalog).dump(), true};
}

ControlMessage random_invalid_message(Rng& rng) { return {pick(rng, invalid_kinds())(rng), false}; }

}  // namespace tpt::soak
