// Double-precision model of the Kuijk-Blake span geometry, for the tests of firmware/kb.
// Written from the geometry (not from the firmware code): slerp by the textbook formula,
// S as the normalised projection of O onto the span's plane, φ as a signed angle about the
// plane's pole, so that a shared mistake is unlikely.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/glm.hpp>

#include "firmware/kb/kb_geometry.hpp"

namespace tp::kbtest {

using glm::dvec3;

inline double to_d(fx::q1_30 v) { return std::ldexp(static_cast<double>(v.raw()), -30); }
inline double to_d(fx::angle_t v) { return std::ldexp(static_cast<double>(v.raw()), -29); }
inline double to_d(fw::kb::dangle_t v) { return std::ldexp(static_cast<double>(v.raw()), -40); }
inline dvec3 to_d(const fw::kb::Unit& v) { return {to_d(v.x), to_d(v.y), to_d(v.z)}; }

inline fx::q1_30 q30(double v) {
  return fx::q1_30::from_raw(static_cast<std::int32_t>(std::llround(std::ldexp(v, 30))));
}
inline fw::kb::Unit unit(dvec3 v) {
  v = glm::normalize(v);
  return {q30(v.x), q30(v.y), q30(v.z)};
}
inline fx::angle_t ang(double v) {
  return fx::angle_t::from_raw(static_cast<std::int32_t>(std::llround(std::ldexp(v, 29))));
}

// Equal-angle interpolation: sin((1−t)θ)/sin θ · a + sin(tθ)/sin θ · b.
inline dvec3 slerp(dvec3 a, dvec3 b, double t) {
  // atan2 of |a×b| and a·b: acos loses half the digits near 0 and π.
  const double th = std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
  if (th < 1e-12) return a;
  return (std::sin((1 - t) * th) * a + std::sin(t * th) * b) / std::sin(th);
}

// Rotation taking unit n onto O = (0, 0, 1), applied to v (Rodrigues).
inline dvec3 rotate_n_to_o(dvec3 n, dvec3 v) {
  const dvec3 o{0, 0, 1};
  const dvec3 axis = glm::cross(n, o);
  const double s = glm::length(axis), c = glm::dot(n, o);
  if (s < 1e-15) return c > 0 ? v : dvec3{v.x, -v.y, -v.z};  // antipodal: π about x
  const dvec3 k = axis / s;
  return v * c + glm::cross(k, v) * s + k * glm::dot(k, v) * (1 - c);
}

// The span circle in double: s = angle(O, S), φ(V) signed from S about the pole P.
struct CircleD {
  double s = 0, phi_left = 0, theta = 0;
};
inline CircleD circle(dvec3 vl, dvec3 vr) {
  CircleD c;
  const dvec3 o{0, 0, 1};
  c.theta = std::atan2(glm::length(glm::cross(vl, vr)), glm::dot(vl, vr));
  const dvec3 pole = glm::cross(vl, vr);
  if (glm::length(pole) < 1e-12) {
    c.phi_left = std::atan2(std::hypot(vl.x, vl.y), vl.z);
    return c;
  }
  const dvec3 p = glm::normalize(pole);
  const dvec3 proj = o - glm::dot(o, p) * p;
  if (glm::length(proj) < 1e-12) {  // O is the pole
    c.s = std::numbers::pi / 2;
    return c;
  }
  const dvec3 s = glm::normalize(proj);
  c.s = std::atan2(std::fabs(glm::dot(o, p)), glm::dot(o, s));
  c.phi_left = std::atan2(glm::dot(glm::cross(s, vl), p), glm::dot(s, vl));
  return c;
}

}  // namespace tp::kbtest
