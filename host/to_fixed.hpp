// Float -> fixed conversion for the host -> device path. Every value is checked against the
// target format's range and reported by name when it does not fit, never wrapped or silently
// saturated. Rounding is to nearest, ties away from zero (std::round), the same rule as
// tp::fx::convert, so a double that is exactly a Q value converts exactly.
#pragma once

#include <array>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "fixedpoint/q.hpp"

namespace tp::host {

struct ConversionIssue {
  std::string quantity;  // e.g. "light 2 position.x"
  double value;
  double min, max;     // the representable range of the target format
  std::string format;  // e.g. "Q15.16"

  std::string message() const {
    std::ostringstream s;
    s.precision(10);
    s << quantity << " = " << value << " does not fit " << format << " (allowed [" << min << ", "
      << max << "])";
    return s.str();
  }
};

// Collects every issue of a batch of conversions, so the user sees them all at once.
class ConversionReport {
 public:
  void add(ConversionIssue issue) { issues_.push_back(std::move(issue)); }
  bool ok() const { return issues_.empty(); }
  const std::vector<ConversionIssue>& issues() const { return issues_; }
  std::string to_string() const {
    std::string s;
    for (const auto& i : issues_) s += i.message() + "\n";
    return s;
  }

 private:
  std::vector<ConversionIssue> issues_;
};

class FixedRangeError : public std::runtime_error {
 public:
  explicit FixedRangeError(const ConversionReport& r) : std::runtime_error(r.to_string()) {}
};

template <tp::fx::QType Qt>
std::string q_format_name() {
  return "Q" + std::to_string(Qt::int_bits) + "." + std::to_string(Qt::frac_bits);
}
template <tp::fx::QType Qt>
constexpr double q_min() {
  return static_cast<double>(Qt::min_raw) / static_cast<double>(Qt::one_raw);
}
template <tp::fx::QType Qt>
constexpr double q_max() {
  return static_cast<double>(Qt::max_raw) / static_cast<double>(Qt::one_raw);
}

// Nearest representable value, or nullopt (and an issue in `report`) when v is not finite or
// rounds outside [Qt::min, Qt::max].
template <tp::fx::QType Qt>
std::optional<Qt> to_fixed(double v, std::string_view quantity, ConversionReport& report) {
  const double raw = std::isfinite(v) ? std::round(std::ldexp(v, Qt::frac_bits)) : 0.0;
  if (!std::isfinite(v) || raw < static_cast<double>(Qt::min_raw) ||
      raw > static_cast<double>(Qt::max_raw)) {
    report.add({std::string(quantity), v, q_min<Qt>(), q_max<Qt>(), q_format_name<Qt>()});
    return std::nullopt;
  }
  return Qt::from_raw(static_cast<typename Qt::storage_type>(raw));
}

// Single conversion that throws FixedRangeError naming the quantity.
template <tp::fx::QType Qt>
Qt to_fixed_or_throw(double v, std::string_view quantity) {
  ConversionReport r;
  const auto q = to_fixed<Qt>(v, quantity, r);
  if (!q) throw FixedRangeError(r);
  return *q;
}

// A vector, component by component ("name.x", "name.y", "name.z").
template <tp::fx::QType Qt>
std::optional<std::array<Qt, 3>> to_fixed3(const glm::dvec3& v, std::string_view quantity,
                                           ConversionReport& report) {
  std::array<Qt, 3> out{};
  bool ok = true;
  static constexpr const char* axis[3] = {".x", ".y", ".z"};
  for (int i = 0; i < 3; ++i) {
    const auto q = to_fixed<Qt>(v[i], std::string(quantity) + axis[i], report);
    if (q) out[static_cast<std::size_t>(i)] = *q;
    ok = ok && q.has_value();
  }
  if (!ok) return std::nullopt;
  return out;
}

// Back to double (for tests and diagnostics).
template <tp::fx::QType Qt>
double to_double(Qt q) {
  return std::ldexp(static_cast<double>(q.raw()), -Qt::frac_bits);
}

}  // namespace tp::host
