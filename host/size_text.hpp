// WIDTHxHEIGHT as the CLI and the bench programs take it (--size): two whole decimal numbers in
// 1..fw::kMaxDimension joined by 'x' or 'X', and nothing else. sscanf's %d wrapped 4294967297
// to 1 (an out-of-range %d is undefined) and ignored trailing text.
#pragma once

#include <charconv>
#include <optional>
#include <string>
#include <string_view>

#include "firmware/types.hpp"

namespace tp::host {

struct Size {
  int width = 0, height = 0;
};

inline std::optional<Size> parse_size(std::string_view text) {
  constexpr int kMax = static_cast<int>(fw::kMaxDimension);  // the device's viewport
  const auto side = [](std::string_view t, int& v) {
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    return ec == std::errc() && end == t.data() + t.size() && v >= 1 && v <= kMax;
  };
  const std::size_t x = text.find_first_of("xX");
  Size s;
  if (x == std::string_view::npos || !side(text.substr(0, x), s.width) ||
      !side(text.substr(x + 1), s.height))
    return std::nullopt;
  return s;
}

// The refusal's text, after the option's name: "expected WIDTHxHEIGHT, each 1..4096, got 'T'".
inline std::string size_expected(std::string_view text) {
  return "expected WIDTHxHEIGHT, each 1.." + std::to_string(fw::kMaxDimension) + ", got '" +
         std::string(text) + "'";
}

}  // namespace tp::host
