#include "host/stress.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ostream>

#include <nlohmann/json.hpp>

#include "host/cli_options.hpp"
#include "host/device_renderer.hpp"
#include "host/image_io.hpp"

namespace tp::host::stress {

namespace {

// FNV-1a of the case name: each case draws from its own stream, so adding a case or changing
// one's draws leaves the others' scenes as they were.
std::uint64_t name_hash(std::string_view s) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const char c : s) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

std::uint64_t counter(const CounterSnapshot& counters, std::string_view name) {
  for (const auto& [n, v] : counters)
    if (n == name) return v;
  return 0;
}

std::vector<std::string> selected_methods(const Options& o) {
  if (!o.methods.empty()) return each_once(o.methods);
  std::vector<std::string> all;
  for (const auto& m : method_names()) all.emplace_back(m.name);
  return all;
}

}  // namespace

std::vector<const Case*> selected_cases(const Options& options) {
  std::vector<const Case*> chosen;
  for (const Case& c : cases()) {
    if (options.quick && !c.quick) continue;
    if (options.case_filter.empty() || c.name.find(options.case_filter) != std::string::npos)
      chosen.push_back(&c);
  }
  return chosen;
}

std::string_view verdict_name(Verdict v) {
  switch (v) {
    case Verdict::kWithin: return "within";
    case Verdict::kExceeds: return "EXCEEDS";
    case Verdict::kNoBound: return "NO BOUND";
  }
  return "?";
}

std::optional<Bound> bound_of(std::string_view case_name, std::string_view method) {
  for (const Bound& b : bounds())
    if (b.case_name == case_name && b.method == method) return b;
  return std::nullopt;
}

Bound pinned(std::string_view case_name, std::string_view method, int measured_max,
             double measured_mean, std::uint64_t measured_saturations) {
  // The mean rounded up to 0.001 level, as printed.
  const double mean = std::ceil((measured_mean * 1.05 + 0.05) * 1000.0) / 1000.0;
  return {case_name, method, measured_max + 2, mean, measured_saturations};
}

Verdict judge(const Comparison& error, std::uint64_t saturations, const std::optional<Bound>& b,
              const CoverageBound& coverage) {
  if (!b) return Verdict::kNoBound;
  const bool within = error.max_abs <= b->max_abs && error.mean_abs <= b->mean_abs &&
                      saturations == b->saturations &&
                      error.only_reference <= coverage.only_reference &&
                      error.only_evaluated <= coverage.only_evaluated;
  return within ? Verdict::kWithin : Verdict::kExceeds;
}

std::vector<Result> run(const Options& options,
                        const std::function<void(const Result&)>& progress) {
  for (const std::string& m : options.methods) (void)method_from_name(m);  // throws, naming them
  const std::vector<std::string> methods = selected_methods(options);
  std::vector<Result> results;
  for (const Case* chosen : selected_cases(options)) {
    const Case& c = *chosen;
    Rng rng(options.seed ^ name_hash(c.name));
    Scene scene = c.build(rng);
    DeviceRenderer device(scene.width, scene.height);
    device.set_scene(scene);
    const ReferenceFrame ref = device.render_reference();  // the method does not change it
    const Image8 ref_image = ref.image();
    const std::string image_base =
        options.image_dir.empty() ? "" : options.image_dir + "/" + c.name;
    if (!image_base.empty()) write_png(image_base + ".reference.png", ref_image);
    for (const std::string& m : methods) {
      scene.method = m;
      device.set_scene(scene);
      const auto start = std::chrono::steady_clock::now();
      const DeviceFrame frame = device.render();
      const auto stop = std::chrono::steady_clock::now();
      if (!image_base.empty()) write_png(image_base + "." + m + ".png", frame.image());
      Result r;
      r.case_name = c.name;
      r.method = m;
      r.error = compare(ref_image, ref.covered, frame.image(), frame.covered);
      r.saturations = counter(frame.counters, "saturations");
      r.bound = bound_of(c.name, m);
      r.coverage = coverage_bound(c.name);
      r.known_failure = known_failure(c.name, m);
      r.verdict = judge(r.error, r.saturations, r.bound, r.coverage);
      r.seconds = std::chrono::duration<double>(stop - start).count();
      if (progress) progress(r);
      results.push_back(std::move(r));
    }
  }
  return results;
}

bool all_within(const std::vector<Result>& results) {
  return std::all_of(results.begin(), results.end(),
                     [](const Result& r) { return r.verdict == Verdict::kWithin; });
}

namespace {

std::string row(const Result& r) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "  %-22s %5d %8.3f %6llu |", r.case_name.c_str(), r.error.max_abs,
                r.error.mean_abs, static_cast<unsigned long long>(r.saturations));
  std::string line = buf;
  if (r.bound) {
    std::snprintf(buf, sizeof buf, " %5d %8.3f %6llu |", r.bound->max_abs, r.bound->mean_abs,
                  static_cast<unsigned long long>(r.bound->saturations));
    line += buf;
  } else {
    line += "     —        —      — |";
  }
  line += " " + std::string(verdict_name(r.verdict));
  if (r.error.only_reference > r.coverage.only_reference ||
      r.error.only_evaluated > r.coverage.only_evaluated) {
    std::snprintf(buf, sizeof buf,
                  " (coverage: %lld reference-only, %lld device-only pixels; bound %lld, %lld)",
                  r.error.only_reference, r.error.only_evaluated, r.coverage.only_reference,
                  r.coverage.only_evaluated);
    line += buf;
  }
  if (!r.known_failure.empty()) line += "  (" + std::string(r.known_failure) + ")";
  return line;
}

}  // namespace

void print_tables(std::ostream& out, const std::vector<Result>& results) {
  std::vector<std::string> methods;
  for (const Result& r : results)
    if (std::find(methods.begin(), methods.end(), r.method) == methods.end())
      methods.push_back(r.method);
  for (const std::string& m : methods) {
    out << "== " << m << "\n"
        << "  case                     max     mean    sat | bound:max     mean    sat | verdict\n";
    for (const Result& r : results)
      if (r.method == m) out << row(r) << "\n";
  }
  const auto bad = std::count_if(results.begin(), results.end(),
                                 [](const Result& r) { return r.verdict != Verdict::kWithin; });
  out << results.size() << (results.size() == 1 ? " result, " : " results, ") << bad
      << " outside their documented bound\n"
      << "(max, mean: |error| against the double reference in 8-bit levels over the pixels both "
         "cover; sat: the device's saturation counter for the frame; a bound also holds the "
         "pixels one image alone covers to the case's count)\n";
}

void write_json(std::ostream& out, const std::vector<Result>& results, const Options& options) {
  nlohmann::json j;
  j["seed"] = options.seed;
  j["quick"] = options.quick;
  j["results"] = nlohmann::json::array();
  for (const Result& r : results) {
    nlohmann::json e = {{"case", r.case_name},
                        {"method", r.method},
                        {"max_abs", r.error.max_abs},
                        {"mean_abs", r.error.mean_abs},
                        {"color_correctness", r.error.color_correctness},
                        {"covered_both", r.error.covered_both},
                        {"only_reference", r.error.only_reference},
                        {"only_evaluated", r.error.only_evaluated},
                        {"saturations", r.saturations},
                        {"verdict", verdict_name(r.verdict)},
                        {"seconds", r.seconds}};
    if (!r.known_failure.empty()) e["known_failure"] = std::string(r.known_failure);
    if (r.bound)
      e["bound"] = {{"max_abs", r.bound->max_abs},
                    {"mean_abs", r.bound->mean_abs},
                    {"saturations", r.bound->saturations},
                    {"only_reference", r.coverage.only_reference},
                    {"only_evaluated", r.coverage.only_evaluated}};
    j["results"].push_back(e);
  }
  out << j.dump(1) << "\n";
}

void write_bounds_table(std::ostream& out, const std::vector<Result>& results) {
  char buf[200];
  for (const Result& r : results) {
    const Bound b = pinned(r.case_name, r.method, r.error.max_abs, r.error.mean_abs, r.saturations);
    std::snprintf(buf, sizeof buf, "      {\"%s\", \"%s\", %d, %.3f, %llu},\n", r.case_name.c_str(),
                  r.method.c_str(), b.max_abs, b.mean_abs,
                  static_cast<unsigned long long>(b.saturations));
    out << buf;
  }
}

}  // namespace tp::host::stress
