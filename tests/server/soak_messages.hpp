// Control messages for the server soak test (docs/SERVER.md, "Soak test"): random valid ones
// (every type a page sends, values inside the documented ranges) and random invalid ones (every
// way docs/SERVER.md says a message is refused while the connection is kept).
#pragma once
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace tpt::soak {

using Rng = std::mt19937_64;

// What the server offers, from its first "state" message.
struct Catalog {
  std::vector<std::string> methods, scenes;
};

// One of the sizes the director switches between: small enough that a Debug or sanitizer build
// renders every scene at several frames per second, with the extremes of the allowed range.
struct Size {
  int width, height;
};
const std::vector<Size>& soak_sizes();

// A message the server must accept or refuse with a reply; ok only if valid.
struct ControlMessage {
  std::string text;
  bool valid;
};

// set_method, set_exponent (n or a, b), set_material, add_light, set_light, remove_light, step
// (lights may be refused when all 16 slots are taken or the last one would go: still a reply).
ControlMessage random_valid_message(Rng& rng, const Catalog& catalog);
// Malformed JSON, not an object, unknown type or field, wrong types, out-of-range values,
// unknown names, acks of frames never sent, over the 4 KiB application limit, deep nesting.
ControlMessage random_invalid_message(Rng& rng);

// Uniform helpers shared by the clients.
int uniform_int(Rng& rng, int lo, int hi);  // [lo, hi]
double uniform_real(Rng& rng, double lo, double hi);
bool chance(Rng& rng, double p);

}  // namespace tpt::soak
