// The device's saturation counter (firmware/counters.hpp, Counters::saturations) is zero on every
// paper scene (scenes/*.json, the light variants included) with every method: the paper scenes
// need no overflow guard to fire. docs/STABILITY.md lists the sites it counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "host/device_renderer.hpp"
#include "host/scene.hpp"
#include "tests/paper_scenes.hpp"

namespace tp::host {
namespace {

std::uint64_t saturations(const CounterSnapshot& counters) {
  for (const auto& [name, value] : counters)
    if (name == "saturations") return value;
  ADD_FAILURE() << "no saturations counter";
  return 0;
}

class PaperScene : public testing::TestWithParam<std::string> {};

TEST_P(PaperScene, NoSaturationWithAnyMethod) {
  Scene scene = load_scene(std::string(TP_SCENES_DIR) + "/" + GetParam() + ".json");
  DeviceRenderer device(scene.width, scene.height);
  for (const auto& m : method_names()) {
    scene.method = std::string(m.name);
    device.set_scene(scene);
    const DeviceFrame frame = device.render();
    EXPECT_EQ(saturations(frame.counters), 0u) << GetParam() << " with " << m.name;
  }
}

TEST(PaperScenes, AreFound) { EXPECT_GE(paper_scenes().size(), 24u); }

INSTANTIATE_TEST_SUITE_P(All, PaperScene, testing::ValuesIn(paper_scenes()),
                         [](const testing::TestParamInfo<std::string>& info) {
                           std::string n = info.param;
                           std::replace(n.begin(), n.end(), '-', '_');
                           return n;
                         });

}  // namespace
}  // namespace tp::host
