// The method registry: one row per shading method — its command id, the name the CLI, scene
// files, server and page spell, a description, what it does with point lights, a finite eye and
// several lights, and how the device lays out and constructs its state. Every other list of
// methods is derived from this table (docs/CONVENTIONS.md, "Methods"): a new method is its own
// file plus one row (and its id in types.hpp, the command stream's number for it).
//
// The firmware reads the table only in constant expressions (device.cpp derives its slot array
// from it at compile time), so the names and descriptions are not linked into the firmware's
// image; the host reads them at run time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <new>
#include <string_view>
#include <type_traits>

#include "firmware/kb/kb_adaptive.hpp"
#include "firmware/kb/kb_methods.hpp"
#include "firmware/method.hpp"
#include "firmware/methods.hpp"
#include "firmware/types.hpp"

namespace tp::fw {

// How a method treats a feature of the scene:
//   kExact        the method evaluates the true vectors (L toward a point light, V toward a
//                 finite eye) at every point where it evaluates the lighting, or, for several
//                 lights, sums every light's contribution as it would one light's;
//   kApproximated it computes them at some points (vertices, the centroid) and interpolates or
//                 holds them between, or merges the lights; the description says how.
enum class Fidelity : std::uint8_t { kExact, kApproximated };

struct MethodCapabilities {
  Fidelity point_lights = Fidelity::kExact;
  Fidelity finite_eye = Fidelity::kExact;
  Fidelity many_lights = Fidelity::kExact;
};

// What a method class declares of itself (firmware/method.hpp, "What a method class declares"),
// one bit each: the device keeps a row of these per linked method.
struct MethodTraits {
  bool lights_vertices : 1 = false;
  bool object_centre : 1 = false;
  bool reads_edge_positions : 1 = false;
  bool skips_hidden_pixels : 1 = false;
  bool colours_linear : 1 = false;
};

// Where a method's state lives: its bytes in the block's method region, and how to construct it
// there (device.cpp); and its traits.
struct MethodSlot {
  std::size_t bytes = 0;
  ShadingMethod* (*construct)(void* where) = nullptr;
  MethodTraits traits;
};

namespace detail {
template <class T, auto... kArgs>
ShadingMethod* construct_at(void* where) {
  static_assert(alignof(T) <= 8, "the block's regions are 8-byte aligned");
  static_assert(std::is_trivially_destructible_v<T>,
                "a method's region is reused without running a destructor");
  return ::new (where) T(kArgs...);
}
}  // namespace detail

// The slot of method class T, constructed with kArgs (a mode, a flag).
template <class T, auto... kArgs>
constexpr MethodSlot slot_of() {
  MethodTraits traits;
  if constexpr (requires { T::kLightsVertices; }) traits.lights_vertices = T::kLightsVertices;
  if constexpr (requires { T::kNeedsObjectCentre; }) traits.object_centre = T::kNeedsObjectCentre;
  if constexpr (requires { T::kReadsEdgePositions; })
    traits.reads_edge_positions = T::kReadsEdgePositions;
  if constexpr (requires { T::kSkipsHiddenPixels; })
    traits.skips_hidden_pixels = T::kSkipsHiddenPixels;
  if constexpr (requires { T::kColoursLinear; }) traits.colours_linear = T::kColoursLinear;
  return MethodSlot{sizeof(T), detail::construct_at<T, kArgs...>, traits};
}

struct MethodInfo {
  Method id;
  std::string_view name;  // fixed: scripts, scene files and the benchmark refer to it
  std::string_view description;
  MethodCapabilities caps;
  MethodSlot slot;
  // A verification variant (the same method with its skips disabled) names the method whose
  // image it must reproduce byte for byte; Method{} (0) for the others.
  Method same_image_as{};
  // The method's image depends on set_budget's error budget (ShadeContext::budget_levels): the
  // CLI says so when --budget is given for a method that does not read it.
  bool reads_budget = false;
};

inline constexpr Fidelity kExact = Fidelity::kExact;
inline constexpr Fidelity kApprox = Fidelity::kApproximated;

// The rows, in the order the CLI lists them and the benchmark's columns run.
inline constexpr MethodInfo kMethodTable[] = {
    {Method::kFlat,
     "flat",
     "one Blinn-Phong evaluation per triangle, at the centroid",
     {kExact, kExact, kExact},
     slot_of<FlatMethod>()},
    {Method::kGouraud,
     "gouraud",
     "lighting at the vertices, colour interpolated",
     {kExact, kExact, kExact},
     slot_of<GouraudMethod>()},
    {Method::kPhong,
     "phong",
     "exact per-pixel Blinn-Phong in fixed point",
     {kExact, kExact, kExact},
     slot_of<PhongMethod>()},
    {Method::kDuff,
     "duff",
     "Duff: Phong's screen-linear normal, N·L and N·H over |N| forward-differenced, one square "
     "root and one division per pixel; L and H per triangle, at its centroid",
     {kApprox, kApprox, kExact},
     slot_of<DuffMethod>()},
    {Method::kBishopWeimer,
     "bishop-weimer",
     "Bishop-Weimer fast Phong: second-order Taylor expansions of Duff's N·L/|N| and N·H/|N| "
     "about the triangle's centre, forward-differenced; the lights' diffuse summed into one "
     "polynomial per channel (a light whose terminator crosses the triangle apart), the power "
     "by table lookup; L and H at the centroid",
     {kApprox, kApprox, kApprox},
     slot_of<BishopWeimerMethod>()},
    {Method::kBishopWeimerFinite,
     "bishop-weimer-finite",
     "Bishop-Weimer's finite-eye extension: N·H/(|N||H|) with H interpolated from the vertices' "
     "halfway vectors, and a point light's N·L/(|N||L|) with L from the vertices, each expanded "
     "to second order about the centre; otherwise bishop-weimer (same pixel loop)",
     {kApprox, kApprox, kApprox},
     slot_of<BishopWeimerFiniteMethod>()},
    {Method::kBrown,
     "brown",
     "Brown's Bézier-triangle highlights: diffuse and ambient as Gouraud; per light, N·H as a "
     "quadratic Bézier triangle through six cosines (vertices and renormalised edge midpoints, "
     "H at each), perspective-correct barycentrics, the power replaced by a smoothstep fitted "
     "to n; lights culled per triangle by the convex hull",
     {kApprox, kApprox, kExact},
     slot_of<BrownMethod, true>()},
    {Method::kBrownNoSkip,
     "brown-noskip",
     "brown without its convex-hull culling (same image)",
     {kApprox, kApprox, kExact},
     slot_of<BrownMethod, false>(),
     Method::kBrown},
    {Method::kGouraudSubdivided,
     "gouraud-subdivided",
     "Gouraud on the triangle cut into four at its edge midpoints (Vlasic's comparison for "
     "quadratic): lighting at the six points, colour interpolated per sub-triangle",
     {kExact, kExact, kExact},
     slot_of<GouraudSubdividedMethod>()},
    {Method::kQuadratic,
     "quadratic",
     "Vlasic's quadratic shading: lighting at the vertices and edge midpoints, the colour's "
     "quadratic by his eq. 4.2 at perspective-correct (s, t), forward-differenced where (s, t) "
     "are affine",
     {kExact, kExact, kExact},
     slot_of<QuadraticMethod, false>()},
    {Method::kQuadraticScreen,
     "quadratic-screen",
     "quadratic with screen-linear (s, t) under perspective too: forward-differenced everywhere "
     "(the same image in orthographic views)",
     {kExact, kExact, kExact},
     slot_of<QuadraticMethod, true>()},
    {Method::kEnvmap,
     "envmap",
     "Vlasic's sphere environment map: diffuse and ambient as Gouraud; the specular part from "
     "one RGB texture of all lights' highlights, indexed by the reflected view vector at the "
     "vertices, coordinates interpolated in screen space; a point light's direction from the "
     "object's centre",
     {kApprox, kApprox, kExact},
     slot_of<EnvmapMethod>()},
    {Method::kBlinnMap,
     "blinn-map",
     "Vlasic's Blinn map: per light, the normal's coordinates in the planes perpendicular to L "
     "and H (u axis from the camera's up vector) at the vertices, interpolated in screen space, "
     "index a diffuse and a specular texture",
     {kApprox, kApprox, kExact},
     slot_of<BlinnMapMethod, false>()},
    {Method::kQuadraticBlinnMap,
     "quadratic-blinn-map",
     "blinn-map with the coordinates at the vertices and edge midpoints, interpolated "
     "quadratically (Vlasic eq. 4.2) at perspective-correct (s, t)",
     {kApprox, kApprox, kExact},
     slot_of<BlinnMapMethod, true>()},
    {Method::kKuijkBlake,
     "kb",
     "Kuijk-Blake one-vector angular interpolation (eq. 4); L and H at the vertices, slerped",
     {kApprox, kApprox, kExact},
     slot_of<kb::KbOneVectorMethod, true>()},
    {Method::kKuijkBlakeNoSkip,
     "kb-noskip",
     "kb with every skip disabled (same image)",
     {kApprox, kApprox, kExact},
     slot_of<kb::KbOneVectorMethod, false>(),
     Method::kKuijkBlake},
    {Method::kKuijkBlakeDecomposition,
     "kb-decomposition",
     "Kuijk-Blake decomposition (eq. 2): product of two forward-differenced f; L and H at the "
     "vertices, slerped",
     {kApprox, kApprox, kExact},
     slot_of<kb::KbDecompositionMethod>()},
    {Method::kKuijkBlakeExact,
     "kb-exact",
     "Kuijk-Blake exact angular interpolation (eq. 1), per-pixel CORDIC; L and H at the "
     "vertices, slerped",
     {kApprox, kApprox, kExact},
     slot_of<kb::KbExactMethod>()},
    {Method::kKuijkBlakeAdaptive,
     "kb-adaptive",
     "Kuijk-Blake per triangle under an error budget (1 level unless set): quadratic, "
     "subdivision or per pixel, within the budget of the exact evaluation",
     {kExact, kExact, kExact},
     slot_of<kb::KbAdaptiveMethod, kb::AdaptiveMode::kAdaptive>(),
     /*same_image_as=*/Method{},
     /*reads_budget=*/true},
    {Method::kKuijkBlakeAdaptiveNoSkip,
     "kb-adaptive-noskip",
     "kb-adaptive with every skip disabled (same image)",
     {kExact, kExact, kExact},
     slot_of<kb::KbAdaptiveMethod, kb::AdaptiveMode::kNoSkip>(),
     Method::kKuijkBlakeAdaptive,
     /*reads_budget=*/true},
    {Method::kKuijkBlakeAdaptiveExact,
     "kb-adaptive-exact",
     "kb-adaptive's exact evaluation at every pixel (the reference of its error budget)",
     {kExact, kExact, kExact},
     slot_of<kb::KbAdaptiveMethod, kb::AdaptiveMode::kExactOnly>()},
};

// Every id of Method is below this (the device's slot array is indexed by id).
inline constexpr std::uint32_t kMethodIdLimit = 32;

// The row of id, or null: in a constant expression in the firmware, at run time in the host.
constexpr const MethodInfo* find_method(Method id) {
  for (const MethodInfo& row : kMethodTable)
    if (row.id == id) return &row;
  return nullptr;
}
constexpr const MethodInfo* find_method(std::string_view name) {
  for (const MethodInfo& row : kMethodTable)
    if (row.name == name) return &row;
  return nullptr;
}

namespace detail {
constexpr bool has_row(Method id) {
  for (const MethodInfo& row : kMethodTable)
    if (row.id == id) return true;
  return false;
}
// The table's own invariants, checked when it is compiled: ids in range and distinct, names
// distinct and non-empty, every row with a constructible state, a verified method in the table.
constexpr bool registry_is_consistent() {
  for (std::size_t i = 0; i < std::size(kMethodTable); ++i) {
    const MethodInfo& a = kMethodTable[i];
    const auto id = static_cast<std::uint32_t>(a.id);
    if (id == 0 || id >= kMethodIdLimit || a.name.empty() || a.description.empty()) return false;
    // (slot_of always sets the constructor. Comparisons of addresses with null are not
    // constant expressions under GCC's sanitizers, so the checks here use none.)
    if (a.slot.bytes == 0) return false;
    if (a.same_image_as != Method{} && !has_row(a.same_image_as)) return false;
    for (std::size_t j = i + 1; j < std::size(kMethodTable); ++j)
      if (kMethodTable[j].id == a.id || kMethodTable[j].name == a.name) return false;
  }
  return true;
}
static_assert(registry_is_consistent(), "method registry: an id or name twice, or an empty row");
}  // namespace detail

}  // namespace tp::fw
