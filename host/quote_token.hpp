// A token from the user's input quoted for an error message.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

namespace tp::host {

// At most the first max_bytes of a token, in single quotes, control bytes as \xNN: so that a NUL
// does not end the message where it is printed (a C string, an exception's what()) and a CR or
// ESC does not garble a terminal. A longer token is cut before a UTF-8 sequence that would not
// fit whole, and "..." after the quote says so.
inline std::string quote_token(std::string_view token, std::size_t max_bytes) {
  std::size_t end = token.size();
  if (end > max_bytes) {
    end = max_bytes;
    while (end > 0 && (static_cast<unsigned char>(token[end]) & 0xC0) == 0x80) --end;
  }
  std::string out = "'";
  for (const char c : token.substr(0, end)) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) {
      char hex[5];
      std::snprintf(hex, sizeof hex, "\\x%02x", byte);
      out += hex;
    } else {
      out += c;
    }
  }
  return out + (end < token.size() ? "'..." : "'");
}

}  // namespace tp::host
