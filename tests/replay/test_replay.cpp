// `tinyphong record` / `replay`: the recorded words of a frame, run through a fresh device,
// give the frame `render` gives, bit for bit (colour, coverage, counters), on every paper scene
// and every method; malformed streams and files are refused with the offset and the reason.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "host/command_stream.hpp"
#include "host/device_renderer.hpp"
#include "host/scene.hpp"
#include "tests/paper_scenes.hpp"

namespace tp::host {
namespace {

Scene scene_at(const std::string& name, const std::string& method, int w, int h) {
  Scene s = load_scene(std::string(TP_SCENES_DIR) + "/" + name + ".json");
  s.method = method;
  if (w > 0) {
    s.width = w;
    s.height = h;
  }
  return s;
}

struct Replayed {
  DeviceFrame frame;
  std::uint64_t hash = 0;
};

Replayed replay(const std::vector<std::uint32_t>& words) {
  const StreamReplay replay(words);
  return {read_frame(replay.device()), framebuffer_hash(replay.device().framebuffer())};
}

// Renders and records the same frame, replays the record, compares everything.
void expect_replay_equals_render(const std::string& name, const std::string& method, int w, int h,
                                 bool depth_buffer = true) {
  SCOPED_TRACE(name + " / " + method + " at " + std::to_string(w) + "x" + std::to_string(h) +
               (depth_buffer ? "" : ", no depth buffer"));
  Scene scene = scene_at(name, method, w, h);
  scene.depth_buffer = depth_buffer;
  DeviceRenderer renderer(scene.width, scene.height);
  renderer.set_scene(scene);
  const std::vector<std::uint32_t> words = renderer.record(0.0);
  const DeviceFrame rendered = renderer.render(0.0);
  const Replayed r = replay(words);
  ASSERT_EQ(r.frame.width, rendered.width);
  ASSERT_EQ(r.frame.height, rendered.height);
  EXPECT_TRUE(r.frame.rgb == rendered.rgb) << "colour differs";
  EXPECT_TRUE(r.frame.covered == rendered.covered) << "coverage differs";
  EXPECT_EQ(r.frame.counters, rendered.counters);
  EXPECT_EQ(r.hash, framebuffer_hash(renderer.device().framebuffer()));
  // Something was drawn: a replay of an empty frame would prove little.
  EXPECT_GT(std::count(rendered.covered.begin(), rendered.covered.end(), 1), 0);
}

TEST(Replay, PaperScenesAreTwentyFour) { EXPECT_EQ(paper_scenes().size(), 24u); }

// Every method on every paper scene at the target tests' size (tests/target).
TEST(Replay, EveryMethodEverySceneAt160x120) {
  for (const std::string& name : paper_scenes())
    for (const fw::MethodInfo& m : method_names())
      expect_replay_equals_render(name, std::string(m.name), 160, 120);
}

// The scenes' own resolutions (512x512, the teapot 640x480) for the main methods.
TEST(Replay, MainMethodsEverySceneAtOwnResolution) {
  for (const std::string& name : paper_scenes())
    for (const char* method : {"gouraud", "phong", "kb", "kb-adaptive"})
      expect_replay_equals_render(name, method, 0, 0);
}

// Without a depth buffer (`--no-depth-buffer`): the stream says so, replay sizes a smaller block
// and gives the render's frame; on the convex scenes the frame is the depth-buffered one, on the
// teapot (which hides parts of itself) it is not.
TEST(Replay, WithoutADepthBuffer) {
  for (const char* name : {"sphere-32", "sphere-512", "dodecahedron-30", "triangle", "teapot"})
    for (const char* method : {"gouraud", "phong", "kb", "kb-adaptive"}) {
      expect_replay_equals_render(name, method, 160, 120, false);
      Scene with = scene_at(name, method, 160, 120), without = with;
      without.depth_buffer = false;
      DeviceRenderer a(160, 120), b(160, 120);
      a.set_scene(with);
      b.set_scene(without);
      const std::size_t saved =
          memory_for_stream(a.record(0.0)).bytes - memory_for_stream(b.record(0.0)).bytes;
      // The depth buffer less one row; the write counts the host turns on for coverage (one byte
      // a pixel, read_frame) more.
      EXPECT_EQ(saved, (160u * 120u - 160u) * 4u - 160u * 120u) << name;
      const bool same = a.render(0.0).rgb == b.render(0.0).rgb;
      EXPECT_EQ(same, std::string(name) != "teapot") << name << " / " << method;
    }
}

// A small part's frame (`record --small-part`; docs/TARGET.md, "A small part"): the stream's
// set_viewport asks for RGB565 with no depth buffer and no write counts, and on a convex scene
// each pixel is the RGB888 frame's truncated to 5-6-5 bits (widened back by bit replication, as
// replay shows it).
TEST(Replay, ASmallPartsFrame) {
  const auto widened = [](std::uint8_t v, int bits) {
    const unsigned q = v >> (8 - bits);
    return static_cast<std::uint8_t>((q << (8 - bits)) | (q >> (2 * bits - 8)));
  };
  for (const char* name : {"sphere-40-l2", "dodecahedron-30"}) {
    Scene full = scene_at(name, "kb", 160, 120), part = full;
    part.depth_buffer = false;
    part.small_part_frame = true;
    DeviceRenderer a(160, 120), b(160, 120);
    a.set_scene(full);
    b.set_scene(part);
    const std::vector<std::uint32_t> words = b.record(0.0);
    ASSERT_GE(words.size(), 5u);
    EXPECT_EQ(words[0], fw::command_header(fw::Opcode::kSetViewport, 4)) << name;
    const std::vector<std::uint32_t> viewport(words.begin() + 1, words.begin() + 5);
    EXPECT_EQ(viewport, (std::vector<std::uint32_t>{160, 120, 1, 2})) << name;  // RGB565; bit 1
    const std::vector<std::uint8_t> rgb = a.render(0.0).rgb, small = replay(words).frame.rgb;
    ASSERT_EQ(small.size(), rgb.size()) << name;
    std::size_t differ = 0;
    for (std::size_t i = 0; i < rgb.size(); ++i)
      differ += small[i] != widened(rgb[i], i % 3 == 1 ? 6 : 5) ? 1 : 0;
    EXPECT_EQ(differ, 0u) << name;
  }
}

// A rotated frame (the server's animation) records the rotated model-view.
TEST(Replay, RotatedFrame) {
  const Scene scene = scene_at("teapot", "kb", 160, 120);
  DeviceRenderer renderer(scene.width, scene.height);
  renderer.set_scene(scene);
  const auto words = renderer.record(0.7);
  EXPECT_NE(words, renderer.record(0.0));
  EXPECT_EQ(replay(words).frame.rgb, renderer.render(0.7).rgb);
}

std::vector<std::uint32_t> triangle_stream() {
  DeviceRenderer renderer(160, 120);
  renderer.set_scene(scene_at("triangle", "gouraud", 160, 120));
  return renderer.record(0.0);
}

// The offsets of the command headers of a well-formed stream.
std::vector<std::size_t> headers(const std::vector<std::uint32_t>& w) {
  std::vector<std::size_t> at;
  for (std::size_t i = 0; i < w.size(); i += 1 + (w[i] >> 16)) at.push_back(i);
  return at;
}

StreamError failure_of(const std::vector<std::uint32_t>& words) {
  try {
    (void)replay(words);
  } catch (const StreamError& e) {
    return e;
  }
  ADD_FAILURE() << "the stream was accepted";
  return StreamError(0, 0, fw::Error::kOk);
}

TEST(Replay, TruncatedStreamNamesTheCommand) {
  auto words = triangle_stream();
  const auto at = headers(words);
  // Cut inside the last draw's payload: the draw header is then short of its payload.
  const std::size_t draw = at[at.size() - 2];
  ASSERT_EQ(words[draw] & 0xffffu, static_cast<std::uint32_t>(fw::Opcode::kDraw));
  words.resize(draw + 2);
  const StreamError e = failure_of(words);
  EXPECT_EQ(e.word_offset, draw);
  EXPECT_EQ(e.error, fw::Error::kBadLength);
  EXPECT_NE(std::string(e.what()).find("draw at word " + std::to_string(draw)), std::string::npos)
      << e.what();
}

TEST(Replay, UnknownOpcodeNamesTheOffset) {
  auto words = triangle_stream();
  const std::size_t third = headers(words)[2];
  words[third] = (words[third] & 0xffff0000u) | 99u;
  const StreamError e = failure_of(words);
  EXPECT_EQ(e.word_offset, third);
  EXPECT_EQ(e.error, fw::Error::kBadOpcode);
  EXPECT_NE(std::string(e.what()).find("unknown opcode 99"), std::string::npos) << e.what();
}

TEST(Replay, RefusedValueNamesTheDevicesError) {
  auto words = triangle_stream();
  words[1] = 5000;  // the viewport's width, beyond kMaxDimension
  const StreamError e = failure_of(words);
  EXPECT_EQ(e.word_offset, 0u);
  EXPECT_EQ(e.error, fw::Error::kViewportTooLarge);
  EXPECT_NE(std::string(e.what()).find("set_viewport at word 0"), std::string::npos) << e.what();
}

// One colour word changed changes the image's hash (what the target tests' mutant relies on).
TEST(Replay, ChangedClearColourChangesTheHash) {
  auto words = triangle_stream();
  const std::uint64_t original = replay(words).hash;
  for (std::size_t at : headers(words))
    if ((words[at] & 0xffffu) == static_cast<std::uint32_t>(fw::Opcode::kClear))
      words[at + 1] ^= 0x00800000u;
  EXPECT_NE(replay(words).hash, original);
}

// Streams of layout commands alone, as a hostile file may hold them.
std::vector<std::uint32_t> viewport(std::uint32_t w, std::uint32_t h, std::uint32_t flags = 0) {
  return {fw::command_header(fw::Opcode::kSetViewport, 4), w, h, 0u, flags};
}
std::vector<std::uint32_t> capacity(std::uint32_t vertices, std::uint32_t indices) {
  return {fw::command_header(fw::Opcode::kSetBufferCapacity, 2), vertices, indices};
}
std::vector<std::uint32_t> method(fw::Method m) {
  return {fw::command_header(fw::Opcode::kSetMethod, 1), static_cast<std::uint32_t>(m)};
}
std::vector<std::uint32_t> joined(std::initializer_list<std::vector<std::uint32_t>> parts) {
  std::vector<std::uint32_t> all;
  for (const auto& p : parts) all.insert(all.end(), p.begin(), p.end());
  return all;
}
std::size_t required(std::uint32_t w, std::uint32_t h, std::uint32_t vertices = 0,
                     std::uint32_t indices = 0, fw::Method m = fw::Method::kGouraud) {
  return fw::Device::memory_required(fw::ViewportCmd{w, h},
                                     fw::BufferCapacityCmd{vertices, indices}, m);
}

// A stream whose last command is not end_frame stops inside a frame, which `tinyphong replay`
// refuses (a file cut at a command's boundary replayed; found by review, 2026-12-07); an empty one
// has no frame; one that ends with end_frame, after one frame or after two, is whole.
TEST(ReplayFile, AWholeFrameEndsWithEndFrame) {
  const std::vector<std::uint32_t> end{fw::command_header(fw::Opcode::kEndFrame, 0)};
  EXPECT_EQ(unfinished_frame({}), "the stream is empty: no frame");
  EXPECT_EQ(unfinished_frame(joined({viewport(16, 16), method(fw::Method::kFlat)})),
            "the stream ends with set_method at word 5, not end_frame: no whole frame (a "
            "truncated file?)");
  EXPECT_EQ(unfinished_frame(joined({viewport(16, 16), end})), std::nullopt);
  EXPECT_EQ(unfinished_frame(joined({viewport(16, 16), end, viewport(8, 8), end})), std::nullopt);
  EXPECT_NE(unfinished_frame(joined({viewport(16, 16), end, viewport(8, 8)})), std::nullopt);
}

// The block follows the layout in stream order: a wide viewport and then a tall one need the
// larger of the two, not a viewport as wide as the one and as tall as the other (16 Mi pixels).
TEST(ReplayMemory, FollowsTheLayoutInStreamOrder) {
  const auto words = joined({viewport(4096, 1), viewport(1, 4096)});
  EXPECT_EQ(memory_for_stream(words).bytes, std::max(required(4096, 1), required(1, 4096)));
  EXPECT_EQ(memory_for_stream(words).over_at, StreamMemory::kNone);
  const StreamReplay r(words);
  EXPECT_EQ(r.device().state().viewport.height, 4096u);
}

// The method in force is the one sized for, not the largest of all.
TEST(ReplayMemory, SizesForTheMethodInForce) {
  const auto gouraud = joined({viewport(160, 120)});
  const auto flat = joined({viewport(160, 120), method(fw::Method::kFlat)});
  const auto adaptive = joined({viewport(160, 120), method(fw::Method::kKuijkBlakeAdaptive)});
  EXPECT_EQ(memory_for_stream(gouraud).bytes, required(160, 120));
  EXPECT_EQ(memory_for_stream(flat).bytes, required(160, 120));  // Gouraud's came first
  EXPECT_EQ(memory_for_stream(adaptive).bytes,
            required(160, 120, 0, 0, fw::Method::kKuijkBlakeAdaptive));
  EXPECT_GT(required(160, 120, 0, 0, fw::Method::kKuijkBlakeAdaptive), required(160, 120));
}

// A value the device refuses leaves the layout as it was, so it sizes nothing.
TEST(ReplayMemory, RefusedValuesSizeNothing) {
  const std::size_t fresh = memory_for_stream({}).bytes;
  EXPECT_EQ(fresh, required(0, 0));
  EXPECT_EQ(memory_for_stream(viewport(4097, 4096)).bytes, fresh);
  EXPECT_EQ(memory_for_stream(viewport(4096, 4096, 4)).bytes, fresh);  // an unknown flag
  // A width of 0 would need no more than a fresh device: the 1×1 viewport after it shows whether
  // the scan stopped there.
  EXPECT_EQ(memory_for_stream(joined({viewport(0, 4096), viewport(1, 1)})).bytes, fresh);
  const std::vector<std::uint32_t> format_2 = {fw::command_header(fw::Opcode::kSetViewport, 4),
                                               4096u, 4096u, 2u, 0u};
  EXPECT_EQ(memory_for_stream(format_2).bytes, fresh);
  EXPECT_EQ(memory_for_stream(capacity(1u << 25, 0)).bytes, fresh);
  EXPECT_EQ(memory_for_stream(capacity(0, (1u << 26) + 1)).bytes, fresh);
  EXPECT_EQ(memory_for_stream(method(static_cast<fw::Method>(1000))).bytes, fresh);
}

// Each state within the limit replays, though the largest viewport and the largest capacity of
// the stream together would not fit it.
TEST(ReplayMemory, EachStateWithinTheLimitReplays) {
  const auto words =
      joined({capacity(2000, 0), viewport(1, 1), capacity(0, 0), viewport(300, 300)});
  const std::size_t limit = std::max(required(0, 0, 2000, 0), required(300, 300));
  ASSERT_GT(required(300, 300, 2000, 0), limit);
  EXPECT_EQ(memory_for_stream(words, limit).bytes, limit);
  const StreamReplay r(words, limit);
  EXPECT_EQ(r.device().state().viewport.width, 300u);
}

// The first state over the limit fails at its command, with the device's out-of-memory error
// and the bytes it needs; the block is what the states before it need.
TEST(ReplayMemory, OverTheLimitFailsAtItsCommand) {
  const auto words = joined({viewport(64, 64), capacity(1000, 3000), viewport(1024, 1024)});
  const std::size_t limit = 1u << 20;
  const StreamMemory need = memory_for_stream(words, limit);
  EXPECT_EQ(need.bytes, required(64, 64, 1000, 3000));
  EXPECT_EQ(need.over_at, 8u);
  EXPECT_EQ(need.over_bytes, required(1024, 1024, 1000, 3000));
  try {
    const StreamReplay r(words, limit);
    ADD_FAILURE() << "a stream over the limit replayed";
  } catch (const StreamError& e) {
    EXPECT_EQ(e.word_offset, 8u);
    EXPECT_EQ(e.error, fw::Error::kOutOfMemory);
    EXPECT_NE(std::string(e.what()).find("set_viewport at word 8 failed: out of device memory (it "
                                         "needs " +
                                         std::to_string(need.over_bytes) +
                                         " bytes, more than replay's limit of 1048576)"),
              std::string::npos)
        << e.what();
  }
}

// A command that fails before the state over the limit is the one reported; where the device
// stops framing or refuses a layout, the scan stops too, so nothing after it is sized for.
TEST(ReplayMemory, AnEarlierFaultIsReportedFirst) {
  const std::size_t fresh = memory_for_stream({}).bytes;
  for (const auto& fault :
       {std::vector<std::uint32_t>{99u},                                               // opcode
        std::vector<std::uint32_t>{fw::command_header(fw::Opcode::kSetEye, 2), 0, 0},  // length
        viewport(4097, 1)}) {                                                          // value
    const auto words = joined({fault, capacity(1u << 24, 1u << 26)});
    EXPECT_EQ(memory_for_stream(words, StreamReplay::kMaxMemory).over_at, StreamMemory::kNone);
    EXPECT_EQ(memory_for_stream(joined({fault, capacity(1000, 0)})).bytes, fresh);
    const StreamError e = failure_of(words);
    EXPECT_EQ(e.word_offset, 0u);
    EXPECT_NE(e.error, fw::Error::kOutOfMemory);
  }
}

class TempFile {
 public:
  explicit TempFile(const std::string& name)
      : path_(std::filesystem::temp_directory_path() /
              (name + "-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()))) {}
  ~TempFile() { std::filesystem::remove(path_); }
  std::string str() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

TEST(ReplayFile, RoundTripsTheWords) {
  const auto words = triangle_stream();
  TempFile f("tp-replay-roundtrip.tpcmd");
  write_command_file(f.str(), words);
  EXPECT_EQ(std::filesystem::file_size(f.str()), 4 * words.size());
  EXPECT_EQ(read_command_file(f.str()), words);
  // Little-endian on disk: the first byte is the low byte of the first header.
  std::ifstream in(f.str(), std::ios::binary);
  EXPECT_EQ(in.get(), static_cast<int>(fw::Opcode::kSetViewport));
}

TEST(ReplayFile, PartialWordIsRefusedNamingTheFile) {
  const auto words = triangle_stream();
  TempFile f("tp-replay-partial.tpcmd");
  write_command_file(f.str(), words);
  std::filesystem::resize_file(f.str(), 4 * words.size() - 2);
  try {
    (void)read_command_file(f.str());
    ADD_FAILURE() << "a partial word was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(f.str()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not a whole number of 32-bit words"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace tp::host
