// The command-stream decoder: opcode + length + payload words, built on the typed calls, so
// the validation (and the "a failing command changes nothing" rule) is theirs.
#include <cstring>

#include "firmware/device.hpp"

namespace tp::fw {
namespace {

std::int32_t as_signed(std::uint32_t w) {
  std::int32_t v;
  std::memcpy(&v, &w, sizeof v);  // two's-complement bits, no implementation-defined cast
  return v;
}
q15_16 q16(std::uint32_t w) { return q15_16::from_raw(as_signed(w)); }
q1_30 q30(std::uint32_t w) { return q1_30::from_raw(as_signed(w)); }

Mat4 matrix(std::span<const std::uint32_t> p) {
  Mat4 m;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) m.m[c][r] = q16(p[static_cast<std::size_t>(4 * c + r)]);
  return m;
}

// Booleans must be 0 or 1: anything else is a malformed command.
bool flag(std::uint32_t w, bool& out) {
  out = w == 1;
  return w <= 1;
}

}  // namespace

Error Device::execute(std::span<const std::uint32_t> words) {
  consumed_ = 0;
  while (consumed_ < words.size()) {
    const std::uint32_t header = words[consumed_];
    const std::uint32_t op = header & 0xffffu, len = header >> 16;
    if (!known_opcode(op)) return fail(Error::kBadOpcode);
    if (len > words.size() - consumed_ - 1) return fail(Error::kBadLength);
    const auto opcode = static_cast<Opcode>(op);
    const std::uint32_t expected = payload_words(opcode);
    if (expected != kVariablePayload && len != expected) return fail(Error::kBadLength);
    const Error e = execute_one(opcode, words.subspan(consumed_ + 1, len));
    if (e != Error::kOk) return e;
    consumed_ += 1 + std::size_t{len};
  }
  return ok();
}

Error Device::execute_one(Opcode op, std::span<const std::uint32_t> p) {
  switch (op) {
    case Opcode::kSetViewport: {
      ViewportCmd c;
      if (!decode_viewport(p, c)) return fail(Error::kBadArgument);
      return set_viewport(c);
    }
    case Opcode::kSetBufferCapacity: return set_buffer_capacity(BufferCapacityCmd{p[0], p[1]});
    case Opcode::kSetModelView: return set_modelview(matrix(p));
    case Opcode::kSetProjection: return set_projection(matrix(p));
    case Opcode::kSetEye: return set_eye(static_cast<EyeMode>(p[0]));
    case Opcode::kSetMaterial: {
      MaterialCmd m;
      for (int c = 0; c < 3; ++c) m.color[c] = q30(p[static_cast<std::size_t>(c)]);
      m.ka = q30(p[3]);
      m.kd = q30(p[4]);
      m.ks = q30(p[5]);
      m.n = p[6];
      m.a = q2_29::from_raw(as_signed(p[7]));
      m.b = q2_29::from_raw(as_signed(p[8]));
      return set_material(m);
    }
    case Opcode::kSetLight: {
      LightCmd l;
      l.index = p[0];
      l.type = static_cast<LightType>(p[1]);
      for (int c = 0; c < 3; ++c) l.color[c] = q16(p[static_cast<std::size_t>(2 + c)]);
      l.direction = Vec3u{q30(p[5]), q30(p[6]), q30(p[7])};
      l.position = Vec3q16{q16(p[8]), q16(p[9]), q16(p[10])};
      return set_light(l);
    }
    case Opcode::kSetMethod: return set_method(static_cast<Method>(p[0]));
    case Opcode::kSetCulling: {
      bool on = false;
      return flag(p[0], on) ? set_culling(on) : fail(Error::kBadArgument);
    }
    case Opcode::kSetDepthTest: {
      bool on = false;
      return flag(p[0], on) ? set_depth_test(on) : fail(Error::kBadArgument);
    }
    case Opcode::kSetBudget: return set_budget(p[0]);
    case Opcode::kUploadVertices: {
      if (p.size() < 2 || (p.size() - 2) % 6 != 0 || (p.size() - 2) / 6 != p[1])
        return fail(Error::kBadLength);
      // Validate everything first, through the typed call, in chunks on the stack (no heap):
      // a failing chunk would leave earlier chunks applied, so check all before uploading.
      // Chunks of 8 vertices (192 bytes): 64 made this the deepest frame of a draw's stack on the
      // Cortex-M (1.6 KB; docs/TARGET.md, "Stack").
      constexpr std::size_t kChunk = 8;
      Vertex buf[kChunk];
      for (int pass = 0; pass < 2; ++pass) {
        if (std::uint64_t{p[0]} + p[1] > state_.capacity.max_vertices || p[0] > state_.vertex_count)
          return fail(Error::kIndexOutOfRange);  // upload_vertices' own checks, before any write
        for (std::uint32_t done = 0; done < p[1];) {
          const std::uint32_t n = p[1] - done < kChunk ? p[1] - done : kChunk;
          for (std::uint32_t i = 0; i < n; ++i) {
            const auto w = p.subspan(2 + 6 * std::size_t{done + i}, 6);
            buf[i] = Vertex{Vec3q16{q16(w[0]), q16(w[1]), q16(w[2])},
                            Vec3u{q30(w[3]), q30(w[4]), q30(w[5])}};
          }
          if (pass == 0) {
            // Dry run: validate without writing by uploading nothing but checking each vertex.
            for (std::uint32_t i = 0; i < n; ++i) {
              const Error e = validate_vertex(buf[i]);
              if (e != Error::kOk) return fail(e);
            }
          } else {
            (void)upload_vertices(p[0] + done, std::span<const Vertex>(buf, n));
          }
          done += n;
        }
      }
      return ok();
    }
    case Opcode::kUploadIndices: {
      if (p.size() < 2 || p.size() - 2 != p[1]) return fail(Error::kBadLength);
      return upload_indices(p[0], p.subspan(2));
    }
    case Opcode::kClear:
      // 0x00RRGGBB: a top byte set is a malformed command, as a flag beyond its bits is.
      if (p[0] > 0xffffffu) return fail(Error::kBadArgument);
      return clear(Rgb8{static_cast<std::uint8_t>(p[0] >> 16), static_cast<std::uint8_t>(p[0] >> 8),
                        static_cast<std::uint8_t>(p[0])});
    case Opcode::kDraw: return draw(DrawCmd{p[0], p[1]});
    case Opcode::kEndFrame: return end_frame();
  }
  return fail(Error::kBadOpcode);
}

}  // namespace tp::fw
