// The cases of the stress suite (docs/STABILITY.md, "Cases"): one table, each entry a seeded
// in-memory scene. Meshes are built here (or by host/meshes.hpp's generators) in model space;
// everything else is a Scene as a scene file would describe it.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "host/meshes.hpp"
#include "host/stress.hpp"

namespace tp::host::stress {

std::uint64_t Rng::next() {
  std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

double Rng::uniform(double lo, double hi) {
  return lo + (hi - lo) * static_cast<double>(next() >> 11) * 0x1.0p-53;
}

// A direction within half_angle of axis, uniform in angle and azimuth (not in solid angle: the
// cases want the cone's edge as often as its centre).
glm::dvec3 Rng::unit_in_cone(const glm::dvec3& axis, double half_angle_rad) {
  const glm::dvec3 a = glm::normalize(axis);
  const glm::dvec3 helper = std::abs(a.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(a, helper)), v = glm::cross(a, u);
  const double theta = uniform(0, half_angle_rad), phi = uniform(0, 2 * std::numbers::pi);
  return glm::normalize(std::cos(theta) * a +
                        std::sin(theta) * (std::cos(phi) * u + std::sin(phi) * v));
}

namespace {

using NormalAt = std::function<glm::dvec3(const glm::dvec3&)>;
constexpr double kPi = std::numbers::pi;

double radians(double deg) { return deg * kPi / 180.0; }

// Shortest round-trip-ish text of a parameter for the case descriptions ("1000", "1e-06").
std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// nx × ny quads over [lo, hi] in the plane z = 0, counter-clockwise seen from +z, two triangles
// per quad, normals from `normal` (normalised here).
Mesh grid(int nx, int ny, glm::dvec2 lo, glm::dvec2 hi, const NormalAt& normal) {
  Mesh m;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const glm::dvec3 p(lo.x + (hi.x - lo.x) * i / nx, lo.y + (hi.y - lo.y) * j / ny, 0.0);
      m.positions.push_back(p);
      m.normals.push_back(glm::normalize(normal(p)));
    }
  const auto at = [nx](int i, int j) { return static_cast<std::uint32_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

// One triangle with its own normals (CCW seen from +z).
Mesh triangle(const glm::dvec3 p[3], const glm::dvec3 n[3]) {
  Mesh m;
  for (int i = 0; i < 3; ++i) {
    m.positions.push_back(p[i]);
    m.normals.push_back(glm::normalize(n[i]));
  }
  m.triangles.push_back({0, 1, 2});
  return m;
}

// A disc of `count` slivers around the origin, radius r: each an apex angle of 2π/count.
Mesh sliver_fan(int count, double r) {
  Mesh m;
  const auto cap_normal = [](const glm::dvec3& p) {
    return glm::normalize(glm::dvec3(0.8 * p.x, 0.8 * p.y, 1.0));
  };
  m.positions.push_back({0, 0, 0});
  m.normals.push_back({0, 0, 1});
  for (int k = 0; k < count; ++k) {
    const double a = 2 * kPi * k / count;
    const glm::dvec3 p(r * std::cos(a), r * std::sin(a), 0);
    m.positions.push_back(p);
    m.normals.push_back(cap_normal(p));
  }
  for (int k = 0; k < count; ++k)
    m.triangles.push_back(
        {0, static_cast<std::uint32_t>(1 + k), static_cast<std::uint32_t>(1 + (k + 1) % count)});
  return m;
}

// Horizontal needles: strips [−1.1, 1.1] × [y, y + h], two triangles each, one every `pitch`.
Mesh needles(int count, double h, double pitch) {
  Mesh m;
  const auto normal = [](const glm::dvec3& p) {
    return glm::normalize(glm::dvec3(0.8 * p.x, 0.3 * std::sin(5 * p.y), 1.0));
  };
  for (int k = 0; k < count; ++k) {
    const double y = -pitch * count / 2 + pitch * k;
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    for (const glm::dvec3 p : {glm::dvec3(-1.1, y, 0), glm::dvec3(1.1, y, 0),
                               glm::dvec3(1.1, y + h, 0), glm::dvec3(-1.1, y + h, 0)}) {
      m.positions.push_back(p);
      m.normals.push_back(normal(p));
    }
    m.triangles.push_back({base, base + 1, base + 2});
    m.triangles.push_back({base, base + 2, base + 3});
  }
  return m;
}

// Triangles whose apex is k / 2^12 (k = 1..count) off the base line: at 256² that is k / 40 of
// a pixel, so the first ones snap to zero area (culled as degenerate) and the rest are
// slivers under a pixel high that cover a pixel centre here and there.
Mesh near_degenerate(int count) {
  Mesh m;
  for (int k = 1; k <= count; ++k) {
    const double y = -1.0 + 2.0 * k / (count + 1);
    const auto base = static_cast<std::uint32_t>(m.positions.size());
    for (const glm::dvec3 p :
         {glm::dvec3(-1.1, y, 0), glm::dvec3(1.1, y, 0), glm::dvec3(0.3, y + k * 0x1.0p-12, 0)}) {
      m.positions.push_back(p);
      m.normals.push_back(glm::normalize(glm::dvec3(0.5 * p.x, 0.2, 1.0)));
    }
    m.triangles.push_back({base, base + 1, base + 2});
  }
  return m;
}

// Normals that wander by up to `amp` (radians, roughly) around `axis` over the plane: smooth,
// with seeded phases, so that N·L of a grazing light changes sign inside triangles.
NormalAt wavy(Rng& rng, glm::dvec3 axis, double amp) {
  const double p1 = rng.uniform(0, 2 * kPi), p2 = rng.uniform(0, 2 * kPi);
  return [=](const glm::dvec3& p) {
    return glm::normalize(
        axis + glm::dvec3(amp * std::sin(2.1 * p.x + p1), amp * std::cos(1.7 * p.y + p2), 0.0));
  };
}

MeshSpec spec(Mesh mesh, const std::string& what, Transform t = {}) {
  MeshSpec s;
  s.generator = what;
  s.transform = t;
  s.mesh = std::move(mesh);
  return s;
}

Transform random_rotation(Rng& rng) {
  Transform t;
  t.rotate_axis = rng.unit_in_cone({0, 0, 1}, kPi);
  t.rotate_deg = rng.uniform(0, 360);
  return t;
}

Light directional(glm::dvec3 toward, glm::dvec3 colour = {1, 1, 1}) {
  return {LightKind::Directional, glm::normalize(toward), colour};
}
Light point(glm::dvec3 position, glm::dvec3 colour = {1, 1, 1}) {
  return {LightKind::Point, position, colour};
}

// The paper scenes' defaults: 256², orthographic ±1.25, the blue material, n = 20.
Scene base(const std::string& name, int width = 256, int height = 256) {
  Scene s;
  s.name = name;
  s.file = "stress:" + name;
  s.width = width;
  s.height = height;
  s.material.colour = {0.2, 0.4, 1.0};
  return s;
}

Scene sphere_scene(const std::string& name, Rng& rng, int subdivisions = 3) {
  Scene s = base(name);
  s.meshes.push_back(spec(octa_sphere(subdivisions), "octa-sphere", random_rotation(rng)));
  return s;
}

Case exponent_case(int n, bool quick) {
  const std::string name = "exponent-n" + std::to_string(n);
  return {name, "exponent", "sphere-512, a directional and a point light, n = " + std::to_string(n),
          quick, [name, n](Rng& rng) {
            Scene s = sphere_scene(name, rng);
            s.material.n = n;
            s.lights = {directional(rng.unit_in_cone({0.3, 0.4, 1}, 0.5), {0.7, 0.7, 0.7}),
                        point(3.0 * rng.unit_in_cone({-0.5, 0.3, 1}, 0.6), {0.5, 0.5, 0.5})};
            return s;
          }};
}

// A W × 32 viewport crossed by two triangles from edge to edge: spans of the full width, the
// normals turning ±53° across them, a narrow highlight (n = 40) somewhere on the way.
Case span_case(int width, bool quick) {
  const std::string name = "span-" + std::to_string(width);
  return {name, "span", "two triangles across a " + std::to_string(width) + " x 32 viewport", quick,
          [name, width](Rng& rng) {
            Scene s = base(name, width, 32);
            const double half_h = 32.0 / width;
            s.camera.left = -1;
            s.camera.right = 1;
            s.camera.bottom = -half_h;
            s.camera.top = half_h;
            const double tilt = rng.uniform(0.05, 0.15);
            s.meshes.push_back(spec(grid(1, 1, {-1.001, -2 * half_h}, {1.001, 2 * half_h},
                                         [tilt](const glm::dvec3& p) {
                                           return glm::dvec3(0.8 * p.x, tilt * (p.y > 0 ? 1 : -1),
                                                             0.6);
                                         }),
                                    "strip"));
            s.material.n = 40;
            s.lights = {directional({rng.uniform(-0.3, 0.3), 0.1, 1})};
            return s;
          }};
}

// Two triangles whose vertices lie ±40 viewport widths out (inside the guard band, 64, so not
// clipped) on a 4096 × 32 viewport: their edges are 2.5 times beyond what the Kuijk-Blake
// span setup's screen x (Q15.16 pixels, ±32,768) holds, so its span ends saturate.
Case guard_band_case() {
  return {"span-guard-band", "span",
          "two triangles reaching 40 widths beyond a 4096 x 32 viewport (guard band)", true,
          [](Rng& rng) {
            Scene s = base("span-guard-band", 4096, 32);
            const double half_h = 32.0 / 4096;
            s.camera.left = -1;
            s.camera.right = 1;
            s.camera.bottom = -half_h;
            s.camera.top = half_h;
            const double tilt = rng.uniform(0.05, 0.15);
            s.meshes.push_back(spec(grid(1, 1, {-40, -2 * half_h}, {40, 2 * half_h},
                                         [tilt](const glm::dvec3& p) {
                                           return glm::dvec3(0.02 * p.x, tilt * (p.y > 0 ? 1 : -1),
                                                             0.6);
                                         }),
                                    "strip"));
            s.material.n = 40;
            s.lights = {directional({rng.uniform(-0.3, 0.3), 0.1, 1})};
            return s;
          }};
}

Case grazing_case(double elevation_deg, bool quick) {
  const std::string name = "grazing-" + std::string(elevation_deg >= 1 ? "1" : "0.1") + "deg";
  return {name, "grazing",
          "wavy 8x8 grid (normals ±9°), a directional light " + name.substr(8) + " above it", quick,
          [name, elevation_deg](Rng& rng) {
            Scene s = base(name);
            s.meshes.push_back(
                spec(grid(8, 8, {-1.2, -1.2}, {1.2, 1.2}, wavy(rng, {0, 0, 1}, 0.16)), "grid"));
            const double e = radians(elevation_deg), a = rng.uniform(0, 2 * kPi);
            s.lights = {
                directional({std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)})};
            return s;
          }};
}

Case near_light_case(int percent, bool quick) {
  const std::string name = "near-light-" + std::to_string(percent) + "pct";
  return {name, "near-light",
          "Vlasic's triangle, a point light " + std::to_string(percent) +
              " % of its longest edge above it",
          quick, [name, percent](Rng& rng) {
            Scene s = base(name);
            s.meshes.push_back(spec(big_triangle(), "triangle"));
            const double size = std::sqrt(1.0 + 1.9 * 1.9);  // the longest edge
            const glm::dvec3 centroid(0, -0.8 / 3, 0);
            const glm::dvec3 offset(rng.uniform(-0.1, 0.1) * size, rng.uniform(-0.1, 0.1) * size,
                                    percent / 100.0 * size);
            s.lights = {point(centroid + offset)};
            return s;
          }};
}

Case scale_case(const std::string& name, double radius, bool quick) {
  return {name, "scale", "sphere-512 of radius " + number(radius) + " framed to fill", quick,
          [name, radius](Rng& rng) {
            Scene s = sphere_scene(name, rng);
            s.meshes.back().transform.scale = radius;
            const double e = 1.25 * radius;
            s.camera.left = s.camera.bottom = -e;
            s.camera.right = s.camera.top = e;
            s.camera.near = -2 * radius;
            s.camera.far = 2 * radius;
            s.lights = {directional(rng.unit_in_cone({-0.3, 0.2, 1}, 0.4), {0.6, 0.6, 0.6}),
                        point(radius * glm::dvec3(0.8, 1.0, 1.5), {0.6, 0.6, 0.6})};
            return s;
          }};
}

std::vector<Case> make_cases() {
  std::vector<Case> c;
  // n = 10^(k/2), k = 0..8: log-spaced 1 .. 10,000.
  for (const int n : {1, 3, 10, 32, 100, 316, 1000, 3162, 10000})
    c.push_back(exponent_case(n, n == 1 || n == 100 || n == 10000));
  c.push_back(span_case(1024, false));
  c.push_back(span_case(4096, true));
  c.push_back(guard_band_case());
  c.push_back(grazing_case(1.0, true));
  c.push_back(grazing_case(0.1, false));
  c.push_back({"terminator-exact", "grazing", "flat quad, N·L = 0 exactly everywhere (L ⟂ N)", true,
               [](Rng&) {
                 Scene s = base("terminator-exact");
                 s.meshes.push_back(spec(quad(1.2), "quad"));
                 s.lights = {directional({1, 0, 0})};
                 return s;
               }});
  c.push_back({"terminator-vertices", "grazing",
               "sphere-512, light along +y: the equator's vertices at N·L = 0 exactly", false,
               [](Rng&) {
                 Scene s = base("terminator-vertices");
                 s.meshes.push_back(spec(octa_sphere(3), "octa-sphere"));
                 s.lights = {directional({0, 1, 0})};
                 return s;
               }});
  for (const int pct : {1, 2, 5}) c.push_back(near_light_case(pct, pct != 2));
  c.push_back({"light-inside-centre", "near-light", "sphere-512, a point light at its centre",
               false, [](Rng& rng) {
                 Scene s = sphere_scene("light-inside-centre", rng);
                 s.lights = {point({0, 0, 0})};
                 return s;
               }});
  c.push_back({"light-inside-offset", "near-light",
               "sphere-512, a point light inside it, off centre (|p| < 0.6)", true, [](Rng& rng) {
                 Scene s = sphere_scene("light-inside-offset", rng);
                 s.lights = {point(rng.uniform(0.2, 0.6) * rng.unit_in_cone({0, 0, 1}, kPi))};
                 return s;
               }});
  c.push_back({"eye-near", "eye-near",
               "perspective eye 2 % of the radius above sphere-2048, 100° field of view", true,
               [](Rng& rng) {
                 Scene s = sphere_scene("eye-near", rng, 4);
                 s.camera.kind = CameraKind::Perspective;
                 s.camera.position = 1.02 * rng.unit_in_cone({0, 0, 1}, 0.5);
                 s.camera.target = {0, 0, 0};
                 s.camera.fov_y_deg = 100;
                 s.camera.near = 0.005;
                 s.camera.far = 5;
                 s.lights = {point({0.3, 0.5, 1.5})};
                 return s;
               }});
  c.push_back({"sliver-fan", "sliver", "a disc of 512 slivers (apex 0.7°, 1.4 px wide at the rim)",
               true, [](Rng& rng) {
                 Scene s = base("sliver-fan");
                 s.meshes.push_back(spec(sliver_fan(512, 1.1), "fan"));
                 s.lights = {directional(rng.unit_in_cone({0.2, 0.3, 1}, 0.4))};
                 return s;
               }});
  c.push_back({"sliver-needles", "sliver", "64 strips 0.6 px high, 550:1, across the viewport",
               false, [](Rng& rng) {
                 Scene s = base("sliver-needles");
                 s.meshes.push_back(spec(needles(64, 0.006, 0.035), "needles"));
                 s.lights = {directional(rng.unit_in_cone({0.2, 0.3, 1}, 0.4))};
                 return s;
               }});
  c.push_back({"sliver-degenerate", "sliver",
               "32 triangles whose apex is k/4096 (k = 1..32) off their base line", false,
               [](Rng& rng) {
                 Scene s = base("sliver-degenerate");
                 s.meshes.push_back(spec(near_degenerate(32), "degenerate"));
                 s.lights = {directional(rng.unit_in_cone({0.2, 0.3, 1}, 0.4))};
                 return s;
               }});
  c.push_back({"near-plane", "near-plane",
               "perspective eye 0.3 above a wavy floor that passes behind it (near-plane clips)",
               true, [](Rng& rng) {
                 Scene s = base("near-plane");
                 Transform floor;
                 floor.rotate_axis = {1, 0, 0};
                 floor.rotate_deg = -90;  // the grid's +z normal to +y, its y to −z
                 s.meshes.push_back(spec(
                     grid(16, 16, {-10, -5}, {10, 20}, wavy(rng, {0, 0, 1}, 0.2)), "floor", floor));
                 s.camera.kind = CameraKind::Perspective;
                 s.camera.position = {0, 0.3, 0};
                 s.camera.target = {0, 0, -1};
                 s.camera.fov_y_deg = 60;
                 s.camera.near = 0.05;
                 s.camera.far = 50;
                 s.lights = {point({rng.uniform(-0.5, 0.5), 1, -1.5}, {0.7, 0.7, 0.7}),
                             directional({0.3, 1, 0.2}, {0.4, 0.4, 0.4})};
                 return s;
               }});
  c.push_back(scale_case("scale-large", 1000, true));
  c.push_back(scale_case("scale-huge", 8000, false));
  c.push_back(scale_case("scale-small", 0.01, true));
  c.push_back(scale_case("scale-tiny", 0.001, false));
  c.push_back({"lights-16", "lights",
               "sphere-512, 8 directional and 8 point lights (0.05–0.12 each)", true, [](Rng& rng) {
                 Scene s = sphere_scene("lights-16", rng);
                 s.material.n = 30;
                 const auto colour = [&rng] {
                   return glm::dvec3(rng.uniform(0.05, 0.12), rng.uniform(0.05, 0.12),
                                     rng.uniform(0.05, 0.12));
                 };
                 for (int i = 0; i < 8; ++i)
                   s.lights.push_back(directional(rng.unit_in_cone({0, 0, 1}, 1.2), colour()));
                 for (int i = 0; i < 8; ++i)
                   s.lights.push_back(point(2.5 * rng.unit_in_cone({0, 0, 1}, 1.2), colour()));
                 return s;
               }});
  c.push_back({"normals-near-minus-o", "kuijk-blake",
               "front-facing 4x4 grid whose normals are within 5° of −O, lit from behind", true,
               [](Rng& rng) {
                 Scene s = base("normals-near-minus-o");
                 s.meshes.push_back(spec(
                     grid(4, 4, {-1.2, -1.2}, {1.2, 1.2}, wavy(rng, {0, 0, -1}, 0.08)), "grid"));
                 s.lights = {directional({0.3, 0.2, -1})};
                 return s;
               }});
  c.push_back({"antipodal-normals", "kuijk-blake",
               "a triangle whose base normals are 179° apart (±x, tilted 0.5° to +z)", true,
               [](Rng& rng) {
                 Scene s = base("antipodal-normals");
                 const glm::dvec3 p[3] = {{-1, -0.9, 0}, {1, -0.9, 0}, {0, 1, 0}};
                 const glm::dvec3 n[3] = {{-1, 0, 0.0087}, {1, 0, 0.0087}, {0, 0.2, 1}};
                 s.meshes.push_back(spec(triangle(p, n), "triangle"));
                 s.lights = {directional(rng.unit_in_cone({0.3, 0.3, 1}, 0.3))};
                 return s;
               }});
  const auto ab_case = [](const std::string& name, double a, double b, int n, bool quick) {
    return Case{name, "ab-range",
                "sphere-512, n = " + std::to_string(n) + ", (a, b) = (" + number(a) + ", " +
                    number(b) + ") given",
                quick, [=](Rng& rng) {
                  Scene s = sphere_scene(name, rng);
                  s.material.n = n;
                  s.material.a = a;
                  s.material.b = b;
                  s.lights = {directional(rng.unit_in_cone({0.3, 0.4, 1}, 0.4))};
                  return s;
                }};
  };
  c.push_back(ab_case("ab-min", 1e-6, 2e-6, 10000, false));
  c.push_back(ab_case("ab-max", 1.5, kPi / 2, 1, true));
  c.push_back(ab_case("ab-wide", 1e-6, kPi / 2, 20, false));
  return c;
}

}  // namespace

const std::vector<Case>& cases() {
  static const std::vector<Case> all = make_cases();
  return all;
}

}  // namespace tp::host::stress
