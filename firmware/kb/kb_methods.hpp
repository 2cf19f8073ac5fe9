// The Kuijk-Blake shading methods (DESIGN §7), one unit each:
//   KbOneVectorMethod      eq. 4: V = R(N→O)·L per vertex (H for specular), V alone slerped;
//                          per span cos^n α = f(φ)·f(s), summed sections (shade_kb_one_vector.cpp)
//   KbDecompositionMethod  eq. 2: N and L (H) slerped separately; per span
//                          cos α = cos(n1 + t(n2−n1))·cos(l1 + t(l2−l1)), f of each factor,
//                          multiplied per pixel (shade_kb_decomposition.cpp)
//   KbExactMethod          eq. 1: N and L (H) slerped separately, cos α per pixel by CORDIC,
//                          max(0, cos α) and cos^n α exactly (shade_kb_exact.cpp)
// All three: point lights, finite eye and up to 16 lights (each light's L and H computed at the
// vertices and interpolated angularly, as the paper does); screen-linear interpolation.
#pragma once

#include <cstdint>

#include "firmware/kb/kb_common.hpp"
#include "firmware/method.hpp"

namespace tp::fw::kb {

// One term of the one-vector method on the current triangle.
struct OneVectorTerm {
  EdgeArcs v;                 // V along the three edges
  const cosn::CosnCoeffs* coeffs = nullptr;  // (a, b) of the term
  q1_30 weight[3];            // Il_c·k·O_c·255/4096, before f(s)
};

// Where O comes from (see shade_kb_one_vector.cpp): the paper's fixed (0, 0, 1), or the
// normalised mean of the triangle's vertex normals (the default).
enum class OChoice { kPaper, kTriangleMean };

class KbOneVectorMethod final : public ShadingMethod {
 public:
  // skipping = false evaluates every term on every span (the image must not change: tested).
  explicit KbOneVectorMethod(bool skipping, OChoice o = OChoice::kPaper)
      : skipping_(skipping), o_choice_(o) {}
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
  void shade_span(const Span& s, Rgb8* out) override;

 private:
  void add_term(const Unit v[3], const cosn::CosnCoeffs& c, angle_t support_angle,
                const q1_30 weight[3]);

  bool skipping_;
  OChoice o_choice_;
  const Triangle* tri_ = nullptr;
  Counters* counters_ = nullptr;
  Unit o_{};
  cosn::CosnCoeffs diffuse_{}, specular_{};
  int terms_ = 0;
  OneVectorTerm term_[kMaxTerms];
  std::int64_t ambient_[3] = {0, 0, 0};
  Rgb8 ambient_rgb_{0, 0, 0};
  SpanSections sections_;
};

}  // namespace tp::fw::kb
