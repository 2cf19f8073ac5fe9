// The firmware built for two lights (TP_MAX_LIGHTS=2, firmware/types.hpp), as a port for a part
// with little RAM builds it (docs/TARGET.md, "A small part"; the Cortex-M images of m3-Os-tiny
// render the paper scenes with at most two lights bit for bit as the 16-light x86 device does).
// Here: the command stream keeps its 16 light slots, the ones past the build's are off and stay
// off, and the method states shrink with the light count.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "helpers.hpp"

namespace tp::fw::test {
namespace {

static_assert(kMaxLights == 2, "this test is built with TP_MAX_LIGHTS=2");
static_assert(kProtocolLights == 16);

LightCmd directional(std::uint32_t index) {
  LightCmd l;
  l.index = index;
  l.type = LightType::kDirectional;
  l.color[0] = l.color[1] = l.color[2] = q16(1);
  l.direction = Vec3u{q30(0), q30(0), q30(1)};
  return l;
}

struct Lit : Rig {
  Mesh mesh = octasphere(2);
  Lit() : Rig(48, 40, 256, 1024) {
    check(dev.set_projection(to_mat4(glm::perspective(1.0, 1.2, 0.5, 10.0))));
    check(dev.set_modelview(to_mat4(glm::translate(glm::dmat4(1), glm::dvec3(0, 0, -3)))));
    check(dev.set_light(directional(0)));
    LightCmd point = directional(1);
    point.type = LightType::kPoint;
    point.position = Vec3q16{q16(1), q16(2), q16(3)};
    check(dev.set_light(point));
    check(dev.set_method(Method::kKuijkBlake));
    check(load(mesh));
  }
  std::vector<std::byte> state() const {
    std::vector<std::byte> s(sizeof(DeviceState));
    std::memcpy(s.data(), &dev.state(), sizeof(DeviceState));
    return s;
  }
};

TEST(TwoLights, ASlotPastTheBuildsLightsIsRefusedLitAndChangesNothing) {
  Lit r;
  const std::vector<std::byte> before = r.state();
  const std::vector<std::byte> memory = r.memory;
  EXPECT_EQ(r.dev.set_light(directional(2)), Error::kTooManyLights);
  EXPECT_EQ(r.dev.last_error(), Error::kTooManyLights);
  EXPECT_EQ(r.dev.set_light(directional(15)), Error::kTooManyLights);
  EXPECT_TRUE(r.state() == before) << "a refused set_light changed the device's state";
  EXPECT_TRUE(r.memory == memory) << "a refused set_light changed the device's memory";
}

TEST(TwoLights, ASlotPastTheBuildsLightsIsAcceptedOff) {
  Lit r;
  const std::uint64_t revision = r.dev.state().shading.revision;
  for (std::uint32_t i = 2; i < kProtocolLights; ++i) {
    LightCmd off;
    off.index = i;
    EXPECT_EQ(r.dev.set_light(off), Error::kOk) << "slot " << i;
  }
  // Each counts as a change, as it does in a full build: the same revisions either way.
  EXPECT_EQ(r.dev.state().shading.revision, revision + (kProtocolLights - 2));
  // The two lights the build holds are untouched, and the frame is drawn with them.
  EXPECT_EQ(r.dev.state().shading.lights[0].type, LightType::kDirectional);
  EXPECT_EQ(r.dev.state().shading.lights[1].type, LightType::kPoint);
  ASSERT_EQ(r.dev.clear(Rgb8{0, 0, 0}), Error::kOk);
  ASSERT_EQ(r.draw_all(r.mesh), Error::kOk);
  EXPECT_GT(r.dev.counters().pixels_written, 500u);
}

TEST(TwoLights, TheProtocolsSlotsEndAt16) {
  Lit r;
  LightCmd off;
  off.index = kProtocolLights;
  EXPECT_EQ(r.dev.set_light(off), Error::kTooManyLights);
  // A bad type is refused as such in every slot, held or not.
  LightCmd bad = directional(5);
  bad.type = static_cast<LightType>(3);
  EXPECT_EQ(r.dev.set_light(bad), Error::kBadArgument);
}

// kb's state holds its per-span sections and memos for every light: 83,680 bytes on x86-64 with
// 16 lights, 12,112 with two (measured 2026-12-05, GCC 12: -fdump-lang-class). The bounds: the
// two-light figures with about 5 % to spare; the 16-light ones in parentheses.
TEST(TwoLights, MethodStatesShrinkWithTheLights) {
  EXPECT_LE(Device::method_bytes(Method::kKuijkBlake), 12'700u);              // 12,112 (83,680)
  EXPECT_LE(Device::method_bytes(Method::kKuijkBlakeDecomposition), 3'650u);  // 3,472 (26,096)
  EXPECT_LE(Device::method_bytes(Method::kPhong), 750u);                      // 712 (2,880)
  EXPECT_LE(sizeof(Device), 740u);                                            // 696 (1,256)
}

}  // namespace
}  // namespace tp::fw::test
