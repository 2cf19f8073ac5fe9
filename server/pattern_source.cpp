#include "server/pattern_source.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace tp::server {

PatternSource::PatternSource() {
  s_.scene = "pattern";
  s_.method = "gradient";
  s_.lights.push_back({false, {1, 1.5, 1}, {1, 1, 1}});
}

std::vector<MethodEntry> PatternSource::methods() const {
  return {{"gradient", "a test pattern: colour gradients", "no lighting"},
          {"rings", "a test pattern: rings", "no lighting"},
          {"flat", "a test pattern: one colour", "no lighting"}};
}
std::vector<std::string> PatternSource::scenes() const { return {"pattern"}; }

Result PatternSource::apply(const ViewSettings& s) {
  const auto m = methods();
  if (std::none_of(m.begin(), m.end(), [&](const MethodEntry& e) { return e.name == s.method; }))
    return Result::failure("unknown method '" + s.method + "'");
  s_ = s;
  return Result::success();
}

Result PatternSource::load_scene(const std::string& name) {
  if (name != "pattern") return Result::failure("unknown scene '" + name + "'");
  return Result::success();
}

Image render_pattern(const ViewSettings& s, double rotation, int bias) {
  Image img;
  img.width = s.width;
  img.height = s.height;
  const auto n = static_cast<std::size_t>(s.width) * static_cast<std::size_t>(s.height);
  img.rgb.resize(3 * n);
  img.covered.assign(n, 1);
  const double c = std::cos(rotation), sn = std::sin(rotation);
  for (int y = 0; y < s.height; ++y) {
    for (int x = 0; x < s.width; ++x) {
      const double u = (x + 0.5) / s.width - 0.5, v = (y + 0.5) / s.height - 0.5;
      const double ru = c * u - sn * v, rv = sn * u + c * v;
      double t = 0;
      if (s.method == "gradient")
        t = 0.5 + ru;
      else if (s.method == "rings")
        t = 0.5 + 0.5 * std::cos(40 * std::hypot(ru, rv));
      else
        t = 0.5;
      const auto i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(s.width) +
                          static_cast<std::size_t>(x));
      for (int k = 0; k < 3; ++k) {
        const double level = std::clamp(
            255.0 * t * s.color[static_cast<std::size_t>(k)] * (0.5 + 0.5 * (rv + 0.5)) + bias, 0.0,
            255.0);
        img.rgb[i + static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(std::lround(level));
      }
    }
  }
  return img;
}

RenderedFrame PatternSource::render(double rotation) {
  const auto t0 = std::chrono::steady_clock::now();
  RenderedFrame f;
  f.image = render_pattern(s_, rotation, 0);
  ++frames_;
  const auto px = static_cast<std::uint64_t>(s_.width) * static_cast<std::uint64_t>(s_.height);
  f.counters = {{"frames", frames_}, {"pixels_written", px}, {"method_" + s_.method, 1}};
  f.render_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return f;
}

std::function<Image()> PatternSource::reference_task(double rotation) {
  return [s = s_, rotation] { return render_pattern(s, rotation, 2); };
}

}  // namespace tp::server
