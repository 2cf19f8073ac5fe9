// The options that the CLI and the bench programs take alike, checked as CLI11 options: a bad
// value is refused as the option it is, with exit status 2, before any scene file is read (a bad
// method was once blamed on the scene file's line 0, and a bench program aborted on it). Each
// program had its own copy of the method check until 2026-12-07.
#pragma once

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "host/cli_numbers.hpp"
#include "host/device_renderer.hpp"
#include "host/size_text.hpp"

namespace tp::host {

// A shading method's name as `tinyphong methods` lists it; the refusal names the valid ones.
inline CLI::Validator method_check() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        try {
          (void)method_from_name(text);
          return "";
        } catch (const std::invalid_argument& e) {
          return e.what();
        }
      },
      "METHOD");
}

// WIDTHxHEIGHT within the device's viewport (parse_size).
inline CLI::Validator size_check() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        return parse_size(text) ? std::string() : size_expected(text);
      },
      "WxH");
}

// A list option's names, each once, in the order first given: "kb,kb" ran kb twice in stress
// and in tinyphong-results, every row doubled.
inline std::vector<std::string> each_once(const std::vector<std::string>& names) {
  std::vector<std::string> once;
  for (const std::string& n : names)
    if (std::find(once.begin(), once.end(), n) == once.end()) once.push_back(n);
  return once;
}

// The items of a comma-separated list, empty ones left out ("kb,,phong" names two), each once.
inline std::vector<std::string> list_items(const std::string& text) {
  std::vector<std::string> items;
  for (std::size_t start = 0; start <= text.size();) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    if (comma > start) items.push_back(text.substr(start, comma - start));
    start = comma + 1;
  }
  return each_once(items);
}

// --methods as one argument, a comma-separated list read by list_items: every item a method, and
// at least one. CLI11's own list (a vector option with a delimiter) took the next option for a
// method when the argument named none: "--methods , --cases x" blamed "--cases".
inline CLI::Validator method_list_check() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::vector<std::string> names = list_items(text);
        if (names.empty()) return "no method named in '" + text + "'";
        const CLI::Validator one = method_check();  // each item as --method checks its one
        for (std::string& name : names)
          if (std::string why = one(name); !why.empty()) return why;
        return "";
      },
      "METHOD[,METHOD...]");
}

// Parses the command line. Returns the exit status when the program should stop here: 0 after
// --help, 2 for a bad option (CLI11's own codes, 105, 109 and so on, are its internals), and
// nothing when the options are good.
inline std::optional<int> parse_options(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  return std::nullopt;
}

}  // namespace tp::host
