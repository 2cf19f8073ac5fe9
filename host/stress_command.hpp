// `tinyphong stress`: the numerical stress suite's subcommand, its options and its run
// (docs/STABILITY.md). The suite itself is host/stress.hpp; this file is its command line.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "host/stress.hpp"

namespace tp::host {

struct StressCli {
  stress::Options options;
  std::string json;
  std::string bounds_out;
  bool list = false;
};

// Adds the subcommand "stress" to `app`, its options read into `cli`.
void add_stress_command(CLI::App& app, StressCli& cli);

// Exit status 0 when every result is within its documented bound, 1 otherwise, 2 when the
// options select nothing, 3 when an output file (the JSON, the bounds, an image) cannot be written.
int run_stress_command(const StressCli& cli);

}  // namespace tp::host
