#include "host/stress_command.hpp"

#include <charconv>
#include <cstdint>
#include <functional>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "host/cli_options.hpp"
#include "host/file_identity.hpp"
#include "host/image_io.hpp"
#include "host/replace_file.hpp"

namespace tp::host {

namespace {

// A seed: a whole decimal number that fits 64 bits, written as it is read (CLI11 alone took -1 as
// 2^64 − 1, clamped 2^64 and beyond to it, read "" as 0 and "0x10" as 16), and written back as
// the number read, since CLI11's own conversion takes a leading 0 for octal (->transform keeps it).
const CLI::Validator kSeed(
    [](std::string& text) -> std::string {
      std::uint64_t v = 0;
      const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
      if (text.empty() || ec != std::errc() || end != text.data() + text.size())
        return "a whole number in 0.." + std::to_string(UINT64_MAX) + ", got '" + text + "'";
      text = std::to_string(v);
      return "";
    },
    "SEED");

// Writes a file whole or throws naming it, the old file kept (host/replace_file.hpp): the text is
// formed in memory first, so a full disk cannot leave half of it.
void write_file(const std::string& path, const std::function<void(std::ostream&)>& write) {
  std::ostringstream text;
  write(text);
  replace_file(path, text.view());
}

void list_cases(const std::vector<const stress::Case*>& chosen) {
  for (const stress::Case* c : chosen)
    std::cout << c->name << (c->quick ? "\tquick\t" : "\t\t") << c->family << "\t" << c->what
              << "\n";
}

// Why --quick and --cases select nothing; a filter that matches only cases outside the quick
// subset says so, since those cases exist.
std::string nothing_selected(const stress::Options& options) {
  std::string why = std::string("no ") + (options.quick ? "quick " : "") +
                    "case matches --cases '" + options.case_filter + "'";
  if (options.quick) {
    stress::Options all = options;
    all.quick = false;
    if (const std::size_t n = stress::selected_cases(all).size(); n != 0)
      return why + " (" + std::to_string(n) + (n == 1 ? " case" : " cases") +
             " outside the quick subset " + (n == 1 ? "does" : "do") + ": leave out --quick)";
  }
  return why + " (tinyphong stress --list names the cases)";
}

}  // namespace

int run_stress_command(const StressCli& cli) {
  const std::vector<const stress::Case*> chosen = stress::selected_cases(cli.options);
  if (chosen.empty()) {
    std::cerr << "tinyphong stress: " << nothing_selected(cli.options) << "\n";
    return 2;
  }
  if (cli.list) {
    list_cases(chosen);
    return 0;
  }
  // Checked before the run (found by review, 2026-12-08): one file for both outputs kept the
  // bounds rows alone, and rows pinned at another seed are not the bounds the table defines.
  if (!cli.json.empty() && !cli.bounds_out.empty() && same_output(cli.json, cli.bounds_out)) {
    std::cerr << "tinyphong stress: --json " << cli.json << " and --pin-bounds " << cli.bounds_out
              << " are one file: nothing run\n";
    return 2;
  }
  if (!cli.bounds_out.empty() && cli.options.seed != stress::kDefaultSeed) {
    std::cerr << "tinyphong stress: --pin-bounds pins the default seed's bounds ("
              << stress::kDefaultSeed << ", docs/STABILITY.md, \"Seeds\"), not seed "
              << cli.options.seed << "'s: nothing run\n";
    return 2;
  }
  std::vector<stress::Result> results;
  try {
    results = stress::run(cli.options, [](const stress::Result& r) {
      std::cerr << "  " << r.case_name << " / " << r.method << ": max " << r.error.max_abs
                << ", mean " << r.error.mean_abs << ", sat " << r.saturations << ", "
                << stress::verdict_name(r.verdict) << "\n";
    });
  } catch (const ImageIoError& e) {  // --images: a file not written is no result out of bounds
    std::cerr << "tinyphong stress: " << e.what() << "\n";
    return 3;
  }
  stress::print_tables(std::cout, results);
  if (cli.options.seed != stress::kDefaultSeed)
    std::cout << "(the bounds were measured at the default seed, " << stress::kDefaultSeed
              << "; at seed " << cli.options.seed
              << " the cases are other scenes, and a verdict says how far the default seed's "
                 "bounds carry to them: docs/STABILITY.md, \"Seeds\")\n";
  try {
    if (!cli.json.empty())
      write_file(cli.json, [&](std::ostream& f) { stress::write_json(f, results, cli.options); });
    if (!cli.bounds_out.empty())
      write_file(cli.bounds_out, [&](std::ostream& f) { stress::write_bounds_table(f, results); });
  } catch (const std::runtime_error& e) {
    std::cerr << "tinyphong stress: " << e.what() << "\n";
    return 3;
  }
  return stress::all_within(results) ? 0 : 1;
}

void add_stress_command(CLI::App& app, StressCli& cli) {
  auto* cmd = app.add_subcommand(
      "stress",
      "numerical stress suite: every method against the double reference on hard cases, "
      "with a verdict against its documented bound (docs/STABILITY.md)");
  cmd->add_flag("--quick", cli.options.quick, "only the quick subset (what the CTest runs)");
  cmd->add_option_function<std::string>(
         "--methods", [&cli](const std::string& text) { cli.options.methods = list_items(text); },
         "comma-separated methods (default: all)")
      ->check(method_list_check());
  cmd->add_option("--cases", cli.options.case_filter, "only cases whose name contains this");
  cmd->add_option("--seed", cli.options.seed,
                  "seed of the cases' random parts (the bounds are the default seed's)")
      ->transform(kSeed);
  cmd->add_option("--json", cli.json, "also write every result as JSON to this file");
  cmd->add_flag("--list", cli.list, "list the cases --quick and --cases select, and exit");
  cmd->add_option("--images", cli.options.image_dir,
                  "write each case's reference and device images (PNG) into this folder")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--pin-bounds", cli.bounds_out,
                  "write the measured results as host/stress_bounds.cpp's table rows, with the "
                  "documented margin (docs/STABILITY.md says when that is allowed)");
}

}  // namespace tp::host
