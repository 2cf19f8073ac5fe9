// The numerical stress suite of `tinyphong stress` (docs/STABILITY.md): in-memory scenes that
// push the device's formats and the methods' approximations to their edges, each rendered by
// every method through the same path as `tinyphong render` (DeviceRenderer) and compared with
// the double reference (host/metrics.hpp), with the device's saturation counter and a verdict
// against the method's documented bound on that case.
//
// Cases are parameterised and seeded: the same seed gives the same scenes, bit for bit (the
// random parts come from a splitmix64 stream of the seed and the case name, not from the
// standard library's distributions, whose output is implementation-defined).
#pragma once

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "host/metrics.hpp"
#include "host/scene.hpp"

namespace tp::host::stress {

inline constexpr std::uint64_t kDefaultSeed = 20261202;

// A small deterministic random stream (splitmix64).
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next();
  double uniform(double lo, double hi);  // [lo, hi), 53 random bits
  glm::dvec3 unit_in_cone(const glm::dvec3& axis, double half_angle_rad);

 private:
  std::uint64_t state_;
};

struct Case {
  std::string name;    // unique, e.g. "exponent-n100"
  std::string family;  // the item it covers, e.g. "exponent"
  std::string what;    // one line: what is stressed
  bool quick = false;  // in the --quick subset (the CTest's)
  std::function<Scene(Rng&)> build;
};

// Every case, in table order (host/stress_cases.cpp).
const std::vector<Case>& cases();

// The documented bound of a method on a case (host/stress_bounds.cpp, mirrored in
// docs/STABILITY.md): measured, then pinned with a margin.
struct Bound {
  std::string_view case_name;
  std::string_view method;
  int max_abs = 0;                // levels
  double mean_abs = 0;            // levels
  std::uint64_t saturations = 0;  // per frame
};
std::optional<Bound> bound_of(std::string_view case_name, std::string_view method);
const std::vector<Bound>& bounds();
// Why a method is far from the reference on a case, where that is a known property of the
// method (or of the formats) rather than a defect; empty otherwise (host/stress_bounds.cpp).
std::string_view known_failure(std::string_view case_name, std::string_view method);

// The pixels that one image covers and the other does not, pinned per case at the default seed
// (host/stress_bounds.cpp): the device has one rasterizer, so its coverage is the same for every
// method, and it is the reference's except where an edge passes within the formats' rounding of
// a pixel centre (tiny, huge and degenerate triangles). Cases not listed: none either way.
struct CoverageBound {
  std::string_view case_name;
  long long only_reference = 0;  // covered by the reference alone
  long long only_evaluated = 0;  // covered by the device alone
};
CoverageBound coverage_bound(std::string_view case_name);

// The margin every bound carries over its measurement (the same as the scene-accuracy test's):
// max + 2 levels, mean × 1.05 + 0.05 levels; the saturation count exactly (the device is
// deterministic, so any change in it is a change in the firmware).
Bound pinned(std::string_view case_name, std::string_view method, int measured_max,
             double measured_mean, std::uint64_t measured_saturations);

enum class Verdict { kWithin, kExceeds, kNoBound };
std::string_view verdict_name(Verdict v);

struct Result {
  std::string case_name, method;
  Comparison error;  // device against the double reference
  std::uint64_t saturations = 0;
  std::optional<Bound> bound;
  CoverageBound coverage;          // the case's (coverage_bound)
  std::string_view known_failure;  // why the bound is large, where it is (stress::known_failure)
  Verdict verdict = Verdict::kNoBound;
  double seconds = 0;  // wall time of the device render
};

struct Options {
  bool quick = false;
  std::uint64_t seed = kDefaultSeed;
  std::vector<std::string> methods;  // empty: every method
  std::string case_filter;           // substring of the case name; empty: all
  std::string image_dir;  // when set: CASE.reference.png and CASE.METHOD.png written there
};

// The cases the options select (--quick, --cases), in table order; --list prints these.
std::vector<const Case*> selected_cases(const Options& options);

// Runs the selected cases; `progress` (may be empty) is called after each result.
std::vector<Result> run(const Options& options,
                        const std::function<void(const Result&)>& progress = {});

// Within: |error| at most the bound's, the saturation count the bound's exactly (fewer means a
// counted site stopped counting as much as more does), and no more pixels covered by one image
// alone than the case's coverage bound.
Verdict judge(const Comparison& error, std::uint64_t saturations, const std::optional<Bound>& b,
              const CoverageBound& coverage = {});

// One table per method (rows: cases) and a summary line; JSON: one object per result.
void print_tables(std::ostream& out, const std::vector<Result>& results);
void write_json(std::ostream& out, const std::vector<Result>& results, const Options& options);
// The bounds table of host/stress_bounds.cpp, pinned from these results (the full suite's).
void write_bounds_table(std::ostream& out, const std::vector<Result>& results);
bool all_within(const std::vector<Result>& results);

}  // namespace tp::host::stress
