// Every error path returns its documented code, sets last_error(), and leaves the device
// exactly as it was: DeviceState, counters and every byte of device memory are compared.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <functional>
#include <limits>
#include <vector>

#include "helpers.hpp"

namespace tp::fw::test {
namespace {

struct Snapshot {
  std::vector<std::byte> memory;
  std::vector<std::byte> state;
  std::vector<std::byte> counters;
};
Snapshot snapshot(const Rig& r) {
  Snapshot s;
  s.memory = r.memory;
  s.state.resize(sizeof(DeviceState));
  std::memcpy(s.state.data(), &r.dev.state(), sizeof(DeviceState));
  s.counters.resize(sizeof(Counters));
  std::memcpy(s.counters.data(), &r.dev.counters(), sizeof(Counters));
  return s;
}

// A rig with a drawn frame, a mesh, lights and a material, so that there is state to disturb.
struct Loaded : Rig {
  Mesh mesh = octasphere(1);
  Loaded() : Rig(48, 40, 64, 256) {
    check(dev.set_projection(to_mat4(glm::perspective(1.0, 1.2, 0.5, 10.0))));
    check(dev.set_modelview(to_mat4(glm::translate(glm::dmat4(1), glm::dvec3(0, 0, -3)))));
    LightCmd l;
    l.index = 2;
    l.type = LightType::kPoint;
    l.color[0] = l.color[1] = l.color[2] = q16(1);
    l.position = Vec3q16{q16(1), q16(2), q16(3)};
    check(dev.set_light(l));
    check(dev.set_method(Method::kPhong));
    check(load(mesh));
    check(dev.clear(Rgb8{0, 0, 0}));
    check(draw_all(mesh));
  }
};

void expect_refused(const char* what, Error expected, const std::function<Error(Loaded&)>& cmd) {
  Loaded rig;
  const Snapshot before = snapshot(rig);
  EXPECT_EQ(cmd(rig), expected) << what;
  EXPECT_EQ(rig.dev.last_error(), expected) << what;
  const Snapshot after = snapshot(rig);
  EXPECT_TRUE(before.state == after.state) << what << ": state changed";
  EXPECT_TRUE(before.counters == after.counters) << what << ": counters changed";
  EXPECT_TRUE(before.memory == after.memory) << what << ": memory changed";
}

Mat4 with_entry(Mat4 m, int c, int r, std::int32_t raw) {
  m.m[c][r] = q15_16::from_raw(raw);
  return m;
}

TEST(Commands, TypedErrorsChangeNothing) {
  const Mat4 id = to_mat4(glm::dmat4(1));
  expect_refused("viewport 0", Error::kViewportTooLarge, [](Loaded& r) {
    return r.dev.set_viewport(ViewportCmd{0, 10});
  });
  expect_refused("viewport 4097", Error::kViewportTooLarge, [](Loaded& r) {
    return r.dev.set_viewport(ViewportCmd{4097, 10});
  });
  expect_refused("viewport format", Error::kBadArgument, [](Loaded& r) {
    return r.dev.set_viewport(ViewportCmd{10, 10, static_cast<PixelFormat>(7)});
  });
  expect_refused("viewport too large for memory", Error::kOutOfMemory, [](Loaded& r) {
    return r.dev.set_viewport(ViewportCmd{4096, 4096});
  });
  expect_refused("capacity too large for memory", Error::kOutOfMemory, [](Loaded& r) {
    return r.dev.set_buffer_capacity(BufferCapacityCmd{100000, 10});
  });
  expect_refused("modelview entry 2^14", Error::kOutOfRange,
                 [&](Loaded& r) { return r.dev.set_modelview(with_entry(id, 3, 0, 1 << 30)); });
  expect_refused("projection entry -2^14", Error::kOutOfRange,
                 [&](Loaded& r) { return r.dev.set_projection(with_entry(id, 1, 2, -(1 << 30))); });
  expect_refused("eye mode", Error::kBadArgument,
                 [](Loaded& r) { return r.dev.set_eye(static_cast<EyeMode>(2)); });
  const auto material = [](auto edit) {
    return [edit](Loaded& r) {
      MaterialCmd m;
      m.color[0] = m.color[1] = m.color[2] = q30(0.5);
      m.ka = q30(0.1);
      m.kd = q30(0.6);
      m.ks = q30(0.4);
      m.n = 20;
      edit(m);
      return r.dev.set_material(m);
    };
  };
  expect_refused("colour > 1", Error::kOutOfRange,
                 material([](MaterialCmd& m) { m.color[1] = q30(1.5); }));
  expect_refused("ka < 0", Error::kOutOfRange, material([](MaterialCmd& m) { m.ka = q30(-0.1); }));
  expect_refused("n = 0", Error::kOutOfRange, material([](MaterialCmd& m) { m.n = 0; }));
  expect_refused("n too large", Error::kOutOfRange,
                 material([](MaterialCmd& m) { m.n = kMaxExponent + 1; }));
  expect_refused("a >= b", Error::kOutOfRange, material([](MaterialCmd& m) {
                   m.a = q2_29::from_raw(1 << 28);
                   m.b = q2_29::from_raw(1 << 27);
                 }));
  const auto light = [](auto edit) {
    return [edit](Loaded& r) {
      LightCmd l;
      l.index = 0;
      l.type = LightType::kDirectional;
      l.color[0] = l.color[1] = l.color[2] = q16(1);
      l.direction = Vec3u{q30(0), q30(0), q30(1)};
      edit(l);
      return r.dev.set_light(l);
    };
  };
  expect_refused("light 16", Error::kTooManyLights,
                 light([](LightCmd& l) { l.index = kMaxLights; }));
  expect_refused("light type", Error::kBadArgument,
                 light([](LightCmd& l) { l.type = static_cast<LightType>(3); }));
  expect_refused("light colour < 0", Error::kOutOfRange,
                 light([](LightCmd& l) { l.color[2] = q16(-1); }));
  expect_refused("light colour > 16", Error::kOutOfRange,
                 light([](LightCmd& l) { l.color[0] = q16(17); }));
  expect_refused("direction not unit", Error::kNotUnit, light([](LightCmd& l) {
                   l.direction = Vec3u{q30(0), q30(0.1), q30(0.999)};
                 }));
  // The largest raw components: their squares summed overflowed a signed 64-bit integer
  // (undefined behaviour; found by fuzzing the command stream).
  expect_refused("direction of the largest components", Error::kNotUnit, light([](LightCmd& l) {
                   const auto most = q1_30::from_raw(std::numeric_limits<std::int32_t>::min());
                   l.direction = Vec3u{most, most, most};
                 }));
  expect_refused("point out of range", Error::kOutOfRange, light([](LightCmd& l) {
                   l.type = LightType::kPoint;
                   l.position = Vec3q16{q16(0), q16(20000), q16(0)};
                 }));
  // Ids that no method implements yet (update as methods land): 0, 10, 20 and ids past the
  // enum.
  for (std::uint32_t id : {0u, 10u, 20u, 99u})
    expect_refused("method", Error::kUnknownMethod,
                   [id](Loaded& r) { return r.dev.set_method(static_cast<Method>(id)); });
  expect_refused("vertices beyond capacity", Error::kIndexOutOfRange, [](Loaded& r) {
    std::vector<Vertex> v(4, vertex({0, 0, 0}, {0, 0, 1}));
    return r.dev.upload_vertices(62, v);
  });
  expect_refused("vertex normal not unit (after valid ones)", Error::kNotUnit, [](Loaded& r) {
    std::vector<Vertex> v(4, vertex({0.5, 0, 0}, {0, 0, 1}));
    v[3].normal.z = q30(0.9);
    return r.dev.upload_vertices(0, v);
  });
  expect_refused("vertex coordinate 2^14", Error::kOutOfRange, [](Loaded& r) {
    std::vector<Vertex> v(2, vertex({0.5, 0, 0}, {0, 0, 1}));
    v[1].position.x = q15_16::from_raw(1 << 30);
    return r.dev.upload_vertices(0, v);
  });
  expect_refused("indices beyond capacity", Error::kIndexOutOfRange, [](Loaded& r) {
    std::vector<std::uint32_t> i(10, 0);
    return r.dev.upload_indices(250, i);
  });
  // No gaps: a vertex slot below the count that no upload wrote held stale bytes (an index
  // region's words, say) that the draw used unvalidated, trusting coordinate_bound (found by
  // review, 2026-12-06). The same for index slots, and for empty uploads, which the stream
  // decoder always treated as changing nothing.
  expect_refused("vertices after a gap", Error::kIndexOutOfRange, [](Loaded& r) {
    std::vector<Vertex> v(1, vertex({0, 0, 0}, {0, 0, 1}));
    return r.dev.upload_vertices(static_cast<std::uint32_t>(r.mesh.positions.size()) + 1, v);
  });
  expect_refused("no vertices after a gap", Error::kIndexOutOfRange, [](Loaded& r) {
    return r.dev.upload_vertices(static_cast<std::uint32_t>(r.mesh.positions.size()) + 1, {});
  });
  expect_refused("indices after a gap", Error::kIndexOutOfRange, [](Loaded& r) {
    std::vector<std::uint32_t> i(3, 0);
    return r.dev.upload_indices(static_cast<std::uint32_t>(r.mesh.indices.size()) + 1, i);
  });
  expect_refused("no indices after a gap", Error::kIndexOutOfRange, [](Loaded& r) {
    return r.dev.upload_indices(static_cast<std::uint32_t>(r.mesh.indices.size()) + 3, {});
  });
  expect_refused("draw count % 3", Error::kBadArgument, [](Loaded& r) {
    return r.dev.draw(DrawCmd{0, 4});
  });
  expect_refused("draw beyond indices", Error::kIndexOutOfRange, [](Loaded& r) {
    return r.dev.draw(DrawCmd{static_cast<std::uint32_t>(r.mesh.indices.size()) - 3, 6});
  });
  expect_refused("draw range overflow", Error::kIndexOutOfRange, [](Loaded& r) {
    return r.dev.draw(DrawCmd{0xfffffffdu, 6});
  });
}

TEST(Commands, BadIndexAndTransformOverflowRefuseTheDraw) {
  Loaded rig;
  std::vector<std::uint32_t> i{0, 1, 60};
  ASSERT_EQ(rig.dev.upload_indices(0, i), Error::kOk);
  Snapshot before = snapshot(rig);
  EXPECT_EQ(rig.dev.draw(DrawCmd{0, 3}), Error::kIndexOutOfRange);
  EXPECT_TRUE(before.memory == snapshot(rig).memory);
  EXPECT_TRUE(before.counters == snapshot(rig).counters);
  // Entries of 16000 (inside the accepted < 2^14) map the vertex (0.707, 0.707, 0) to eye
  // x = 16000 * 2.41 > 2^15: not representable in Q15.16.
  ASSERT_EQ(rig.load(rig.mesh), Error::kOk);
  Mat4 big = to_mat4(glm::dmat4(1));
  for (int c = 0; c < 4; ++c) big.m[c][0] = q16(16000);
  ASSERT_EQ(rig.dev.set_modelview(big), Error::kOk);
  before = snapshot(rig);
  EXPECT_EQ(rig.draw_all(rig.mesh), Error::kOutOfRange);
  const Snapshot after = snapshot(rig);
  EXPECT_TRUE(before.memory == after.memory);
  EXPECT_TRUE(before.state == after.state);
  EXPECT_TRUE(before.counters == after.counters);
}

// A draw is refused only for the vertices its indices name. The driver keeps every mesh in one
// buffer, each drawn with its own model-view, so a vertex far out that only another mesh's draw
// names refused this one: two meshes that each rendered alone failed together (found by review,
// 2026-12-08).
TEST(Commands, AVertexTheDrawDoesNotNameDoesNotRefuseIt) {
  // Scaled by 2.5, the vertex at x = 16000 leaves Q15.16 in eye space (40000 > 2^15).
  const Mat4 mv =
      to_mat4(glm::scale(glm::translate(glm::dmat4(1), glm::dvec3(0, 0, -6)), glm::dvec3(2.5)));
  const Vertex far = vertex(glm::dvec3(16000, 0, 0), glm::dvec3(0, 0, 1));
  const auto frame = [&](bool far_vertex) {
    Loaded rig;
    Rig::check(rig.dev.set_modelview(mv));
    if (far_vertex)
      Rig::check(rig.dev.upload_vertices(static_cast<std::uint32_t>(rig.mesh.positions.size()),
                                         std::vector<Vertex>{far}));
    Rig::check(rig.dev.clear(Rgb8{0, 0, 0}));
    EXPECT_EQ(rig.draw_all(rig.mesh), Error::kOk) << (far_vertex ? "with" : "without");
    const FramebufferView fb = rig.dev.framebuffer();
    return std::vector<std::uint8_t>(fb.data, fb.data + std::size_t{fb.stride} * fb.height);
  };
  const std::vector<std::uint8_t> with = frame(true), without = frame(false);
  EXPECT_TRUE(with == without);
  EXPECT_TRUE(std::any_of(with.begin(), with.end(), [](std::uint8_t b) { return b != 0; }));
  // A draw that names it is refused, and changes nothing.
  Loaded rig;
  ASSERT_EQ(rig.dev.set_modelview(mv), Error::kOk);
  const auto far_id = static_cast<std::uint32_t>(rig.mesh.positions.size());
  ASSERT_EQ(rig.dev.upload_vertices(far_id, std::vector<Vertex>{far}), Error::kOk);
  const std::vector<std::uint32_t> tri{0, 1, far_id};
  ASSERT_EQ(rig.dev.upload_indices(0, tri), Error::kOk);
  const Snapshot before = snapshot(rig);
  EXPECT_EQ(rig.dev.draw(DrawCmd{0, 3}), Error::kOutOfRange);
  const Snapshot after = snapshot(rig);
  EXPECT_TRUE(before.memory == after.memory);
  EXPECT_TRUE(before.state == after.state);
  EXPECT_TRUE(before.counters == after.counters);
  // Under a model-view that keeps it in range the same draw is taken: every draw transforms its
  // vertices anew (eye x 16000, clip x about 24,400: within Q15.16).
  ASSERT_EQ(rig.dev.set_modelview(to_mat4(glm::translate(glm::dmat4(1), glm::dvec3(0, 0, -6)))),
            Error::kOk);
  EXPECT_EQ(rig.dev.draw(DrawCmd{0, 3}), Error::kOk);
}

// An empty upload at or below the count changes nothing, typed or streamed: the draw still
// ends at the indices uploaded (it raised the count to `first` before, making index slots no
// upload wrote drawable, in typed calls only).
TEST(Commands, EmptyUploadsChangeNothing) {
  Loaded typed, streamed;
  const auto nv = static_cast<std::uint32_t>(typed.mesh.positions.size());
  const auto ni = static_cast<std::uint32_t>(typed.mesh.indices.size());
  const Snapshot before = snapshot(typed);
  EXPECT_EQ(typed.dev.upload_vertices(nv, {}), Error::kOk);
  EXPECT_EQ(typed.dev.upload_indices(ni, {}), Error::kOk);
  EXPECT_TRUE(before.state == snapshot(typed).state);
  EXPECT_EQ(streamed.dev.execute(
                std::vector<std::uint32_t>{command_header(Opcode::kUploadVertices, 2), nv, 0,
                                           command_header(Opcode::kUploadIndices, 2), ni, 0}),
            Error::kOk);
  for (const Device* d : {&typed.dev, &streamed.dev}) {
    EXPECT_EQ(d->state().vertex_count, nv);
    EXPECT_EQ(d->state().index_count, ni);
  }
  EXPECT_EQ(typed.dev.draw(DrawCmd{ni, 3}), Error::kIndexOutOfRange);
  EXPECT_EQ(streamed.dev.draw(DrawCmd{ni, 3}), Error::kIndexOutOfRange);
}

TEST(Commands, NoViewportRefusesDrawAndClear) {
  std::vector<std::byte> mem(1 << 16);
  Device d(mem);
  EXPECT_EQ(d.clear(Rgb8{0, 0, 0}), Error::kNoViewport);
  EXPECT_EQ(d.draw(DrawCmd{0, 0}), Error::kNoViewport);
  EXPECT_EQ(d.framebuffer().data, nullptr);
  EXPECT_EQ(d.write_counts(), nullptr);
}

// memory_required(viewport, capacity, method) is exact: a block of that size takes the capacity,
// the method and the viewport, one byte less refuses the viewport (kOutOfMemory, nothing
// changed), and the two-argument form covers every method.
TEST(Commands, MemoryRequiredIsExactPerMethod) {
  const ViewportCmd vp{160, 120, PixelFormat::kRgb565, false};
  const BufferCapacityCmd cap{64, 192};
  for (const Method m : kImplementedMethods) {
    const std::size_t need = Device::memory_required(vp, cap, m);
    EXPECT_GT(Device::method_bytes(m), 0u);
    EXPECT_LE(need, Device::memory_required(vp, cap)) << static_cast<int>(m);
    // The block's start is 8-byte aligned here (vector storage), so no byte is skipped. The
    // method first (with no viewport yet its layout is small), then the viewport, which needs
    // the whole block.
    std::vector<std::byte> exact(need), short_by_one(need - 1);
    Device a(exact), b(short_by_one);
    for (Device* d : {&a, &b}) {
      EXPECT_EQ(d->set_buffer_capacity(cap), Error::kOk);
      EXPECT_EQ(d->set_method(m), Error::kOk) << static_cast<int>(m);
    }
    EXPECT_EQ(a.set_viewport(vp), Error::kOk) << static_cast<int>(m);
    std::vector<std::byte> before(sizeof(DeviceState));
    std::memcpy(before.data(), &b.state(), sizeof(DeviceState));
    EXPECT_EQ(b.set_viewport(vp), Error::kOutOfMemory) << static_cast<int>(m);
    EXPECT_EQ(std::memcmp(before.data(), &b.state(), sizeof(DeviceState)), 0);
  }
  // The buffers alone: the colour (2 bytes per pixel), the depth (4), one span of the viewport's
  // width, the vertices and their transformed and projected copies, the indices, each rounded up
  // to 8 bytes.
  const std::size_t pixels = 160 * 120;
  const auto align8 = [](std::size_t v) { return (v + 7) & ~std::size_t{7}; };
  const std::size_t buffers = align8(64 * sizeof(Vertex)) + align8(64 * sizeof(CachedVertex)) +
                              align8(192 * 4) + align8(pixels * 2) + align8(pixels * 4) +
                              align8(160 * sizeof(Rgb8));
  // Gouraud lights each vertex once per draw: its lit-vertex cache, one VertexLevels per vertex;
  // the other methods have none.
  EXPECT_EQ(
      Device::memory_required(vp, cap, Method::kGouraud),
      buffers + align8(64 * sizeof(VertexLevels)) + align8(Device::method_bytes(Method::kGouraud)));
  EXPECT_EQ(Device::memory_required(vp, cap, Method::kFlat),
            buffers + align8(Device::method_bytes(Method::kFlat)));
}

TEST(Commands, TinyMemoryNeverCrashes) {
  std::vector<std::byte> mem(16);
  Device d(mem);
  EXPECT_EQ(d.set_viewport(ViewportCmd{1, 1}), Error::kOutOfMemory);
  EXPECT_EQ(d.set_buffer_capacity(BufferCapacityCmd{1, 1}), Error::kOutOfMemory);
}

std::vector<std::uint32_t> stream_for(const Mesh& m, const glm::dmat4& proj, const glm::dmat4& mv) {
  std::vector<std::uint32_t> w;
  const auto raw = [](auto q) { return static_cast<std::uint32_t>(q.raw()); };
  const auto mat = [&](Opcode op, const glm::dmat4& g) {
    const Mat4 x = to_mat4(g);
    w.push_back(command_header(op, 16));
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) w.push_back(raw(x.m[c][r]));
  };
  w.insert(w.end(), {command_header(Opcode::kSetMethod, 1), 3});
  mat(Opcode::kSetProjection, proj);
  mat(Opcode::kSetModelView, mv);
  w.insert(w.end(), {command_header(Opcode::kSetLight, 11), 2, 2, raw(q16(1)), raw(q16(1)),
                     raw(q16(1)), 0, 0, 0, raw(q16(1)), raw(q16(2)), raw(q16(3))});
  w.push_back(command_header(Opcode::kUploadVertices,
                             2 + 6 * static_cast<std::uint32_t>(m.positions.size())));
  w.push_back(0);
  w.push_back(static_cast<std::uint32_t>(m.positions.size()));
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const Vertex v = vertex(m.positions[i], m.normals[i]);
    w.insert(w.end(), {raw(v.position.x), raw(v.position.y), raw(v.position.z), raw(v.normal.x),
                       raw(v.normal.y), raw(v.normal.z)});
  }
  w.push_back(
      command_header(Opcode::kUploadIndices, 2 + static_cast<std::uint32_t>(m.indices.size())));
  w.push_back(0);
  w.push_back(static_cast<std::uint32_t>(m.indices.size()));
  w.insert(w.end(), m.indices.begin(), m.indices.end());
  w.insert(w.end(),
           {command_header(Opcode::kClear, 1), 0, command_header(Opcode::kDraw, 2), 0,
            static_cast<std::uint32_t>(m.indices.size()), command_header(Opcode::kEndFrame, 0)});
  return w;
}

TEST(CommandStream, RendersTheSameFrameAsTypedCalls) {
  Loaded typed;
  Rig streamed(48, 40, 64, 256);
  const auto words = stream_for(typed.mesh, glm::perspective(1.0, 1.2, 0.5, 10.0),
                                glm::translate(glm::dmat4(1), glm::dvec3(0, 0, -3)));
  ASSERT_EQ(streamed.dev.execute(words), Error::kOk);
  EXPECT_EQ(streamed.dev.words_consumed(), words.size());
  EXPECT_EQ(streamed.dev.counters().frames, 1u);
  const FramebufferView a = typed.dev.framebuffer(), b = streamed.dev.framebuffer();
  ASSERT_EQ(a.stride * a.height, b.stride * b.height);
  EXPECT_EQ(std::memcmp(a.data, b.data, a.stride * a.height), 0);
  EXPECT_GT(streamed.dev.counters().pixels_written, 100u);
}

void expect_stream_refused(const char* what, Error expected, std::vector<std::uint32_t> words,
                           std::size_t consumed = 0) {
  Loaded rig;
  const Snapshot before = snapshot(rig);
  EXPECT_EQ(rig.dev.execute(words), expected) << what;
  EXPECT_EQ(rig.dev.last_error(), expected) << what;
  EXPECT_EQ(rig.dev.words_consumed(), consumed) << what;
  const Snapshot after = snapshot(rig);
  EXPECT_TRUE(before.state == after.state) << what;
  EXPECT_TRUE(before.counters == after.counters) << what;
  EXPECT_TRUE(before.memory == after.memory) << what;
}

TEST(CommandStream, MalformedCommandsChangeNothing) {
  expect_stream_refused("opcode 0", Error::kBadOpcode, {0});
  expect_stream_refused("opcode 17", Error::kBadOpcode, {17});
  expect_stream_refused("budget 0", Error::kBadArgument,
                        {command_header(Opcode::kSetBudget, 1), 0});
  expect_stream_refused("budget 17", Error::kBadArgument,
                        {command_header(Opcode::kSetBudget, 1), kMaxBudgetLevels + 1});
  expect_stream_refused("short eye", Error::kBadLength, {command_header(Opcode::kSetEye, 0)});
  expect_stream_refused("long eye", Error::kBadLength, {command_header(Opcode::kSetEye, 2), 0, 0});
  expect_stream_refused("truncated payload", Error::kBadLength,
                        {command_header(Opcode::kSetModelView, 16), 1, 2});
  expect_stream_refused(
      "vertex count mismatch", Error::kBadLength,
      {command_header(Opcode::kUploadVertices, 8), 0, 2, 0, 0, 0, 0, 0, 1u << 30});
  expect_stream_refused("index count mismatch", Error::kBadLength,
                        {command_header(Opcode::kUploadIndices, 3), 0, 2, 1});
  expect_stream_refused("flag 2", Error::kBadArgument, {command_header(Opcode::kSetCulling, 1), 2});
  expect_stream_refused("viewport flag 5", Error::kBadArgument,
                        {command_header(Opcode::kSetViewport, 4), 8, 8, 0, 5});
  expect_stream_refused("viewport flag 4", Error::kBadArgument,
                        {command_header(Opcode::kSetViewport, 4), 8, 8, 0, 4});
  expect_stream_refused("viewport flag 2^31", Error::kBadArgument,
                        {command_header(Opcode::kSetViewport, 4), 8, 8, 0, 1u << 31});
  expect_stream_refused("clear 0x01000000", Error::kBadArgument,
                        {command_header(Opcode::kClear, 1), 0x01000000u});
  expect_stream_refused("clear 0xffffffff", Error::kBadArgument,
                        {command_header(Opcode::kClear, 1), 0xffffffffu});
  expect_stream_refused("method 10 (unassigned)", Error::kUnknownMethod,
                        {command_header(Opcode::kSetMethod, 1), 10});
  expect_stream_refused(
      "vertices after a gap", Error::kIndexOutOfRange,
      {command_header(Opcode::kUploadVertices, 8), 60, 1, 0, 0, 0, 0, 0, 1u << 30});
  expect_stream_refused("no indices after a gap", Error::kIndexOutOfRange,
                        {command_header(Opcode::kUploadIndices, 2), 250, 0});
  // A vertex upload whose second chunk holds a bad normal: the first 64 vertices must not land.
  std::vector<std::uint32_t> up{command_header(Opcode::kUploadVertices, 2 + 6 * 64), 0, 64};
  for (int i = 0; i < 64; ++i) up.insert(up.end(), {0, 0, 0, 0, 0, i == 63 ? 5u : (1u << 30)});
  expect_stream_refused("bad normal in a long upload", Error::kNotUnit, up);
  // Commands before the failing one stay applied; the failing one does not.
  Loaded rig;
  const std::vector<std::uint32_t> w{command_header(Opcode::kSetCulling, 1), 0,
                                     command_header(Opcode::kSetEye, 1), 7};
  EXPECT_EQ(rig.dev.execute(w), Error::kBadArgument);
  EXPECT_EQ(rig.dev.words_consumed(), 2u);
  EXPECT_FALSE(rig.dev.state().cull_back_faces);
  EXPECT_EQ(rig.dev.state().shading.eye, EyeMode::kInfinite);
  // A valid budget is the shading state's, from 1 (after construction) up to kMaxBudgetLevels.
  EXPECT_EQ(rig.dev.state().shading.budget_levels, 1u);
  EXPECT_EQ(rig.dev.execute(std::vector<std::uint32_t>{command_header(Opcode::kSetBudget, 1),
                                                       kMaxBudgetLevels}),
            Error::kOk);
  EXPECT_EQ(rig.dev.state().shading.budget_levels, kMaxBudgetLevels);
}

// The counts and ranges of draws and uploads come from the stream: each is checked (in 64-bit
// arithmetic where first + count could wrap), never used to index memory unchecked.
TEST(CommandStream, DrawAndUploadRangesAreCheckedNotTrusted) {
  expect_stream_refused("draw range wraps", Error::kIndexOutOfRange,
                        {command_header(Opcode::kDraw, 2), 0xfffffffdu, 6});
  expect_stream_refused("draw count 2^32 - 1", Error::kIndexOutOfRange,
                        {command_header(Opcode::kDraw, 2), 0, 0xffffffffu});
  expect_stream_refused("draw count not a multiple of 3", Error::kBadArgument,
                        {command_header(Opcode::kDraw, 2), 0, 4});
  expect_stream_refused("index upload wraps", Error::kIndexOutOfRange,
                        {command_header(Opcode::kUploadIndices, 3), 0xffffffffu, 1, 0});
  expect_stream_refused(
      "vertex upload past the capacity", Error::kIndexOutOfRange,
      {command_header(Opcode::kUploadVertices, 8), 0xffffffffu, 1, 0, 0, 0, 0, 0, 1u << 30});
  expect_stream_refused(
      "vertex count 2^32 - 1 with one vertex", Error::kBadLength,
      {command_header(Opcode::kUploadVertices, 8), 0, 0xffffffffu, 0, 0, 0, 0, 0, 1u << 30});
  expect_stream_refused("payload of 65535 words, 2 present", Error::kBadLength,
                        {command_header(Opcode::kDraw, 0xffff), 0, 3});
}

TEST(Framebuffer, Rgb565KeepsTopBitsOfRgb888) {
  Rig a(40, 30, 64, 256, false, PixelFormat::kRgb888),
      b(40, 30, 64, 256, false, PixelFormat::kRgb565);
  const Mesh m = octasphere(1);
  for (Rig* r : {&a, &b}) {
    ASSERT_EQ(r->dev.set_projection(to_mat4(glm::ortho(-1.5, 1.5, -1.2, 1.2, -3.0, 3.0))),
              Error::kOk);
    ASSERT_EQ(r->dev.set_method(Method::kPhong), Error::kOk);
    LightCmd l;
    l.index = 0;
    l.type = LightType::kDirectional;
    l.color[0] = l.color[1] = l.color[2] = q16(1);
    l.direction = Vec3u{q30(0), q30(0.6), q30(0.8)};
    ASSERT_EQ(r->dev.set_light(l), Error::kOk);
    ASSERT_EQ(r->dev.clear(Rgb8{0, 0, 0}), Error::kOk);
    ASSERT_EQ(r->load(m), Error::kOk);
    ASSERT_EQ(r->draw_all(m), Error::kOk);
  }
  const FramebufferView fa = a.dev.framebuffer(), fb = b.dev.framebuffer();
  ASSERT_EQ(fb.stride, 80u);
  int lit = 0;
  for (std::uint32_t i = 0; i < 40 * 30; ++i) {
    const std::uint8_t* p = fa.data + 3 * i;
    const unsigned v = fb.data[2 * i] | (fb.data[2 * i + 1] << 8);
    EXPECT_EQ(v, ((p[0] >> 3u) << 11) | ((p[1] >> 2u) << 5) | (p[2] >> 3u));
    lit += p[1] > 0 ? 1 : 0;
  }
  EXPECT_GT(lit, 200);
}

}  // namespace
}  // namespace tp::fw::test
