#include "firmware/geometry.hpp"

#include <bit>

#include "firmware/vecmath.hpp"
#include "fixedpoint/arith.hpp"
#include "fixedpoint/vec3.hpp"
#include "fixedpoint/wide.hpp"

namespace tp::fw {
namespace {

using fx::round_shift_right;
using wide = std::int64_t;

bool fits_q15_16(wide raw) { return raw >= q15_16::min_raw && raw <= q15_16::max_raw; }

// Row i of M times (a, b, c, d) where d is 1 (positions) or 0 (normals), exact in 64 bits
// (input bound in geometry.hpp). Result has F_M + F_in fraction bits.
wide row_times(const Mat4& m, int i, wide a, wide b, wide c, wide d_scaled) {
  return m.m[0][i].raw() * a + m.m[1][i].raw() * b + m.m[2][i].raw() * c +
         wide{m.m[3][i].raw()} * d_scaled;
}

// Signed distance to plane p (>= 0 inside), raw Q15.16 in 64 bits.
wide plane_distance(const ClipVertex& v, int p) {
  const wide x = v.clip[0], y = v.clip[1], z = v.clip[2], w = v.clip[3];
  switch (p) {
    case 0: return z + w;   // near: z >= -w
    case 1: return w - 16;  // w >= 2^-12
    case 2: return kGuardBand * w - x;
    case 3: return kGuardBand * w + x;
    case 4: return kGuardBand * w - y;
    default: return kGuardBand * w + y;
  }
}

std::int32_t lerp_raw(std::int32_t a, std::int32_t b, q1_30 t) {
  const wide d = wide{b} - a;  // |d| < 2^32, t <= 2^30: product < 2^62
  return static_cast<std::int32_t>(a + round_shift_right(d * t.raw(), 30));
}

// The point where edge in -> out crosses plane p: t = d_in / (d_in - d_out) in [0, 1).
ClipVertex intersect(const ClipVertex& in, const ClipVertex& out, wide d_in, wide d_out) {
  const q1_30 t = fx::div<q1_30>(fx::int_q::from_raw(d_in), fx::int_q::from_raw(d_in - d_out));
  ClipVertex r;
  for (int k = 0; k < 4; ++k) r.clip[k] = lerp_raw(in.clip[k], out.clip[k], t);
  const auto lerp_q = [&](auto a, auto b) {
    return decltype(a)::from_raw(lerp_raw(a.raw(), b.raw(), t));
  };
  r.eye = {lerp_q(in.eye.x, out.eye.x), lerp_q(in.eye.y, out.eye.y), lerp_q(in.eye.z, out.eye.z)};
  // Unit normals lerp to a vector of length >= cos(angle/2) > 0 unless antipodal; renormalise.
  r.normal = normalize_wide(lerp_raw(in.normal.x.raw(), out.normal.x.raw(), t),
                            lerp_raw(in.normal.y.raw(), out.normal.y.raw(), t),
                            lerp_raw(in.normal.z.raw(), out.normal.z.raw(), t));
  return r;
}

int clip_against(int plane, const ClipVertex* in, int n, ClipVertex* out) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const ClipVertex& a = in[i];
    const ClipVertex& b = in[(i + 1) % n];
    const wide da = plane_distance(a, plane), db = plane_distance(b, plane);
    if (da >= 0) out[m++] = a;
    if ((da >= 0) != (db >= 0)) {
      out[m++] = da >= 0 ? intersect(a, b, da, db) : intersect(b, a, db, da);
    }
  }
  return m;
}

}  // namespace

int homogeneous_orientation(const ClipVertex v[3]) {
  // Cofactor expansion along (x, y, w); each 2x2 minor of raw values below 2^31 is below
  // 2^63, each term below 2^94, the sum below 2^96: exact in 128 bits.
  const auto minor = [&](int c0, int c1, int i, int j) {
    return wide{v[i].clip[c0]} * v[j].clip[c1] - wide{v[j].clip[c0]} * v[i].clip[c1];
  };
  fx::Sum128 det;
  det.add_product(v[0].clip[0], minor(1, 3, 1, 2));
  det.add_product(-wide{v[0].clip[1]}, minor(0, 3, 1, 2));
  det.add_product(v[0].clip[3], minor(0, 1, 1, 2));
  return det.sign();
}

bool transform_position(const Mat4& mv, const Mat4& proj, const Vertex& in, ClipVertex& out) {
  const wide px = in.position.x.raw(), py = in.position.y.raw(), pz = in.position.z.raw();
  wide eye[3];
  for (int i = 0; i < 3; ++i) {
    eye[i] = round_shift_right(row_times(mv, i, px, py, pz, wide{1} << 16), 16);
    if (!fits_q15_16(eye[i])) return false;
  }
  for (int i = 0; i < 4; ++i) {
    // P entries < 2^30 raw, eye < 2^31 raw: three products < 3 * 2^61 < 2^63.
    const wide c = round_shift_right(row_times(proj, i, eye[0], eye[1], eye[2], wide{1} << 16), 16);
    if (!fits_q15_16(c)) return false;
    out.clip[i] = static_cast<std::int32_t>(c);
  }
  out.eye = {q15_16::from_raw(static_cast<std::int32_t>(eye[0])),
             q15_16::from_raw(static_cast<std::int32_t>(eye[1])),
             q15_16::from_raw(static_cast<std::int32_t>(eye[2]))};
  return true;
}

Vec3u transform_normal(const Mat4& mv, const Vertex& in) {
  const wide nx = in.normal.x.raw(), ny = in.normal.y.raw(), nz = in.normal.z.raw();
  return normalize_wide(row_times(mv, 0, nx, ny, nz, 0), row_times(mv, 1, nx, ny, nz, 0),
                        row_times(mv, 2, nx, ny, nz, 0));
}

bool transform_vertex(const Mat4& mv, const Mat4& proj, const Vertex& in, ClipVertex& out) {
  if (!transform_position(mv, proj, in, out)) return false;
  out.normal = transform_normal(mv, in);
  return true;
}

namespace {

// |round_shift_right(row_times(m, i, ...), 16)| for inputs of magnitude at most in[0..2] (and 1
// for the fourth), raw, rounded up; saturated at 2^63 (then nothing fits anyway).
std::uint64_t row_bound(const Mat4& m, int i, const std::uint64_t in[3]) {
  const auto mag = [](std::int32_t v) {
    return v < 0 ? std::uint64_t{0} - static_cast<std::uint64_t>(std::int64_t{v})
                 : static_cast<std::uint64_t>(v);
  };
  std::uint64_t sum = mag(m.m[3][i].raw()) << 16;  // < 2^48
  for (int j = 0; j < 3; ++j) {
    if (in[j] >= (std::uint64_t{1} << 32)) return std::uint64_t{1} << 63;
    // Each term < 2^31 · 2^32 = 2^63 and the sum below 2^63 before it: no wrap, and the sum is
    // checked again after each term.
    sum += mag(m.m[j][i].raw()) * in[j];
    if (sum >= (std::uint64_t{1} << 63)) return std::uint64_t{1} << 63;
  }
  return (sum >> 16) + 1;
}

}  // namespace

bool transform_cannot_fail(const Mat4& mv, const Mat4& proj, std::uint32_t coordinate_bound) {
  const std::uint64_t b[3] = {coordinate_bound, coordinate_bound, coordinate_bound};
  std::uint64_t eye[3];
  for (int i = 0; i < 3; ++i) {
    eye[i] = row_bound(mv, i, b);
    if (eye[i] > static_cast<std::uint64_t>(q15_16::max_raw)) return false;
  }
  for (int i = 0; i < 4; ++i)
    if (row_bound(proj, i, eye) > static_cast<std::uint64_t>(q15_16::max_raw)) return false;
  return true;
}

std::uint32_t outside_planes(const ClipVertex& v) {
  std::uint32_t mask = 0;
  for (int p = 0; p < kClipPlanes; ++p)
    if (plane_distance(v, p) < 0) mask |= 1u << p;
  return mask;
}

ClipClass classify(const ClipVertex in[3]) {
  const std::uint32_t a = outside_planes(in[0]), b = outside_planes(in[1]),
                      c = outside_planes(in[2]);
  if ((a & b & c) != 0) return ClipClass::kOutside;
  return (a | b | c) == 0 ? ClipClass::kInside : ClipClass::kCrossing;
}

ClipResult clip_triangle(const ClipVertex in[3], ClipVertex out[kMaxClipVertices]) {
  switch (classify(in)) {
    case ClipClass::kOutside: return ClipResult{0, true};
    case ClipClass::kInside:
      for (int i = 0; i < 3; ++i) out[i] = in[i];
      return ClipResult{3, false};
    case ClipClass::kCrossing: break;
  }
  return ClipResult{clip_crossing(in, out), true};
}

int clip_crossing(const ClipVertex in[3], ClipVertex out[kMaxClipVertices]) {
  ClipVertex tmp[kMaxClipVertices];
  for (int i = 0; i < 3; ++i) tmp[i] = in[i];
  int n = 3;
  for (int p = 0; p < kClipPlanes && n > 0; ++p) {
    n = clip_against(p, tmp, n, out);
    for (int i = 0; i < n; ++i) tmp[i] = out[i];
  }
  return n;
}

ShadeVertex project(const ClipVertex& v, std::int32_t width, std::int32_t height) {
  const wide x = v.clip[0], y = v.clip[1], w = v.clip[3];
  // |x|, |y| <= 64 w (guard band), w < 2^31: numerators below 65 * 2^31 * 8 * 4096 < 2^53.
  ShadeVertex s;
  s.sx = static_cast<std::int32_t>(
      fx::div<fx::int_q>(fx::int_q::from_raw((x + w) * 8 * width), fx::int_q::from_raw(w)).raw());
  s.sy = static_cast<std::int32_t>(
      fx::div<fx::int_q>(fx::int_q::from_raw((w - y) * 8 * height), fx::int_q::from_raw(w)).raw());
  // NDC z with 30 fraction bits, saturated to [-2, 2): beyond the far plane depth is clamped.
  s.z =
      fx::div<fx::Q<1, 30, std::int64_t>>(q15_16::from_raw(v.clip[2]), q15_16::from_raw(v.clip[3]))
          .raw();
  s.w = q15_16::from_raw(v.clip[3]);
  s.eye = v.eye;
  s.normal = v.normal;
  return s;
}

void cache_vertex(const Mat4& mv, const Mat4& proj, const Vertex& in, std::int32_t width,
                  std::int32_t height, CachedVertex& out) {
  (void)transform_position(mv, proj, in, out.v);
  out.outside = outside_planes(out.v);
  if (out.outside != 0) return;
  const ShadeVertex s = project(out.v, width, height);
  out.sx = s.sx;
  out.sy = s.sy;
  out.z = s.z;
}

}  // namespace tp::fw
