// A synthetic frame source for transport tests (--source pattern): cheap, deterministic,
// animated; not the device. Its "reference" is the same pattern with a small offset.
#pragma once
#include "server/frame_source.hpp"

namespace tp::server {

class PatternSource : public FrameSource {
 public:
  PatternSource();
  const ViewSettings& settings() const override { return s_; }
  Result apply(const ViewSettings& s) override;
  Result load_scene(const std::string& name) override;
  std::vector<MethodEntry> methods() const override;
  std::vector<std::string> scenes() const override;
  RenderedFrame render(double rotation_radians) override;
  std::function<Image()> reference_task(double rotation_radians) override;

 private:
  ViewSettings s_;
  std::uint64_t frames_ = 0;
};

Image render_pattern(const ViewSettings& s, double rotation, int bias);

}  // namespace tp::server
