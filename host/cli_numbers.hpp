// Numbers as command-line options take them, checked as CLI11 options: shared by the CLI, the
// bench programs (host/cli_options.hpp) and the server, which has no device headers to include.
#pragma once

#include <charconv>
#include <string>
#include <string_view>
#include <system_error>

#include <CLI/CLI.hpp>

namespace tp::host {

// A whole number written in decimal ("12", "+3", "-1", "010") within [low, high]. CLI11's own
// reading of an integer option also took hexadecimal ("0x10") and a leading space (" 3"), and
// called "1e3", "1.5" and "nan" out of range (found by review, 2026-12-08; --rotate's and --seed's
// checks had been mended the day before). The text is then written back as the number read:
// CLI11 converts it with base 0, which reads a leading 0 as octal ("010" as 8). Give it with
// ->transform(), which keeps what a validator writes; ->check() runs it on a copy.
inline CLI::Validator whole_number(long long low, long long high) {
  const std::string range = std::to_string(low) + ".." + std::to_string(high);
  return CLI::Validator(
      [low, high, range](std::string& text) -> std::string {
        std::string_view digits = text;
        const bool plus = digits.starts_with('+');
        if (plus) digits.remove_prefix(1);
        long long v = 0;
        const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
        const bool read = ec == std::errc() || ec == std::errc::result_out_of_range;
        if (!read || end != digits.data() + digits.size() || (plus && digits.starts_with('-')))
          return "a whole number in " + range + " (decimal digits), got '" + text + "'";
        if (ec == std::errc::result_out_of_range || v < low || v > high)
          return "a whole number in " + range + ", got '" + text + "'";
        text = std::to_string(v);
        return "";
      },
      "INT in " + range);
}

}  // namespace tp::host
