// Prints the accuracy of every fixed-point function against long double as a markdown table:
// max |err|, mean |err| and mean signed err in LSB of the output format, over the same input
// sets as the tests (tests/fixedpoint/measure.hpp). Usage: accuracy_fixedpoint [filter]
#include <algorithm>
#include <cstdio>
#include <string>

#include "host/standard_output.hpp"
#include "tests/fixedpoint/measure.hpp"
#include "tests/fixedpoint/measure_quat.hpp"
#include "tests/fixedpoint/measure_trig.hpp"

int main(int argc, char** argv) {
  using namespace tp::fx::testing;
  const std::string filter = argc > 1 ? argv[1] : "";
  std::vector<Case> cases = arith_cases();
  for (auto& c : vec_cases()) cases.push_back(std::move(c));
  for (auto& c : trig_cases()) cases.push_back(std::move(c));
  for (auto& c : trig_fast_cases()) cases.push_back(std::move(c));
  for (auto& c : quat_cases()) cases.push_back(std::move(c));
  // A filter that names no function (--help, a typo) printed an empty table and exited 0.
  const bool any = filter.empty() || std::any_of(cases.begin(), cases.end(), [&](const Case& c) {
                     return c.name.find(filter) != std::string::npos;
                   });
  if (argc > 2 || !any) {
    const std::string why = argc > 2 ? "one FILTER at most, " + std::to_string(argc - 1) + " given"
                                     : "'" + filter + "' names none";
    std::fprintf(stderr,
                 "usage: accuracy_fixedpoint [FILTER]: FILTER a part of a function's name,"
                 " e.g. sqrt; %s\n",
                 why.c_str());
    return 2;
  }
  std::printf(
      "| function | inputs | n | max abs err (LSB) | mean abs err (LSB) | mean err (LSB) |\n");
  std::printf("|---|---|---:|---:|---:|---:|\n");
  for (const auto& c : cases) {
    if (!filter.empty() && c.name.find(filter) == std::string::npos) continue;
    const ErrStats s = c.run();
    std::printf("| `%s` | %s | %zu | %.7Lf | %.4Lf | %+.5Lf |\n", c.name.c_str(), c.inputs.c_str(),
                s.n, s.max_abs, s.mean_abs(), s.mean());
    std::fflush(stdout);
  }
  return tp::host::standard_output_written("accuracy_fixedpoint") ? 0 : 1;
}
