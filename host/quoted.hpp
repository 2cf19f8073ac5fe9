// A token from the user's input quoted for an error message.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

namespace tp::host {

// At most the first max_bytes of a token, in single quotes, control bytes as \xNN: so that a NUL
// does not end the message where it is printed (a C string, an exception's what()) and a CR or
// ESC does not garble a terminal.
inline std::string quoted(std::string_view token, std::size_t max_bytes) {
  std::string out = "'";
  for (const char c : token.substr(0, max_bytes)) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) {
      char hex[5];
      std::snprintf(hex, sizeof hex, "\\x%02x", byte);
      out += hex;
    } else {
      out += c;
    }
  }
  return out + "'";
}

}  // namespace tp::host
