// The Kuijk-Blake shading methods (Kuijk & Blake; docs/KUIJK-BLAKE.md), one unit each:
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

#include "firmware/kb/kb_coherence.hpp"
#include "firmware/kb/kb_common.hpp"
#include "firmware/kb/kb_two_vector.hpp"
#include "firmware/method.hpp"

namespace tp::fw::kb {

// One term of the one-vector method on the current triangle.
struct OneVectorTerm {
  EdgeArcs v;                                // V along the three edges
  const cosn::CosnCoeffs* coeffs = nullptr;  // (a, b) of the term
  q1_30 weight[3];                           // Il_c·k·O_c·255/4096, before f(s)
};

// cos and sin of the angle from O beyond which a term is zero (plus a margin), for the
// per-triangle skip test of shade_kb_one_vector.cpp.
struct Support {
  q1_30 cos{}, sin{};
  bool possible = false;
};

// Where O comes from (see shade_kb_one_vector.cpp): the paper's fixed (0, 0, 1) (the default;
// continuous across edges), or the normalised mean of each triangle's vertex normals.
enum class OChoice { kPaper, kTriangleMean };

class KbOneVectorMethod final : public ShadingMethod {
 public:
  // skipping = false evaluates every term on every span (the image must not change: tested).
  // coherent = false sets every span up exactly (kb_coherence.hpp measures the difference).
  explicit KbOneVectorMethod(bool skipping, bool coherent = true, OChoice o = OChoice::kPaper)
      : skipping_(skipping), coherent_(coherent), o_choice_(o) {}
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
  void shade_span(const Span& s, Rgb8* out) override;
  static constexpr bool kReadsEdgePositions = true;

  // The two halves of shade_span, public so that the benchmark can time the span setup alone:
  // prepare_span builds the summed sections of the span, evaluate_span steps them.
  void prepare_span(const Span& s);
  void evaluate_span(Rgb8* out);

 private:
  void add_term(const Unit v[3], const cosn::CosnCoeffs& c, const Support& support,
                const q1_30 weight[3]);
  SpanParams exact_params(const OneVectorTerm& t, const EdgePos& l, const EdgePos& r) const;
  EdgePos edge_at_row(const EdgePos& like, std::int32_t row) const;
  void start_chunk(const Span& s);
  void add_span_term(const OneVectorTerm& t, std::int64_t phi_first, std::int64_t rate,
                     const std::int64_t scales[3], const Span& s);
  void add_exact_term(const OneVectorTerm& t, const Span& s);

  bool skipping_;
  bool coherent_;
  OChoice o_choice_;
  const Triangle* tri_ = nullptr;
  bool x_may_saturate_ = false;  // may_saturate_x(*tri_): span ends checked (and counted)
  Counters* counters_ = nullptr;
  Unit o_{};
  MaterialCoeffs coeffs_;
  Support diffuse_support_{}, specular_support_{};  // made with coeffs_
  // Memos of pure per-vertex functions (exact: the same inputs give the same bits). Neighbouring
  // triangles share vertices, and a directional light with the eye at infinity has one H.
  struct RotationMemo {
    Unit n{}, o{};
    Rotation r{};
    bool valid = false;
  };
  static constexpr int kRotationMemo = 8;
  RotationMemo rotation_memo_[kRotationMemo];
  int rotation_next_ = 0;
  struct HalfwayMemo {
    Unit l{}, e{}, h{};
    bool valid = false;
  };
  HalfwayMemo halfway_memo_[kMaxLights];
  // Per vertex (normal, eye-space position, O, eye mode): the eye direction and, per light
  // (keyed on its type, direction and position), the rotated vectors V of both terms. A vertex
  // shared by neighbouring triangles is set up once while it stays in the memo.
  struct VertexLight {
    LightType type = LightType::kOff;
    Vec3u direction{};
    Vec3q16 position{};
    Unit vd{}, vs{};
    bool valid = false;
  };
  struct VertexMemo {
    Unit n{}, o{};
    Vec3q16 p{};
    EyeMode eye = EyeMode::kInfinite;
    Rotation r{};
    Unit e{};
    VertexLight light[kMaxLights];
    bool valid = false;
  };
  static constexpr int kVertexMemo = 16;
  VertexMemo vertex_memo_[kVertexMemo];
  int vertex_next_ = 0;
  VertexMemo& vertex_of(const ShadeVertex& v, const Unit& o, const ShadeContext& ctx);
  Rotation rotation_of(const Unit& n, const Unit& o);
  Unit halfway_of(std::size_t light, const Unit& l, const Unit& e);
  int terms_ = 0;
  OneVectorTerm term_[kMaxTerms];
  std::int64_t ambient_[3] = {0, 0, 0};
  Rgb8 ambient_rgb_{0, 0, 0};
  SpanSections sections_;
  // Coherence state (kb_coherence.hpp): the chunk of rows being interpolated.
  std::uint32_t chunk_key_ = 0;
  std::int32_t chunk_row_ = 0, chunk_last_ = -1;  // next row expected, last row of the chunk
  bool chunk_exact_ = true;
  QuadY quad_[kMaxTerms][kParams];
  SpanParams sample_[kMaxTerms];  // the last chunk's last exact sample, per term
  std::uint32_t sample_key_ = 0;
  std::int32_t sample_row_ = -2;
};

// Eq. 2: per span and term the two factor angles u (along N's circle, relative to L's
// longitude) and v (L's latitude off N's circle) are linear in x; f(u)·f(v) per pixel, each
// factor forward-differenced (cosn segments), multiplied per pixel (the paper's "multiplication
// per pixel" option; per span it would be a quartic).
class KbDecompositionMethod final : public ShadingMethod {
 public:
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
  void shade_span(const Span& s, Rgb8* out) override;
  static constexpr bool kReadsEdgePositions = true;

 private:
  // The two halves of shade_span (as in KbOneVectorMethod): prepare_span builds each term's
  // factor segments for the span, evaluate_span steps them.
  void prepare_span(const Span& s);
  void evaluate_span(const Span& s, Rgb8* out);
  struct Factor {  // one forward-differenced f along the span
    cosn::CosnSegment seg[kMaxTermSegments];
    int count = 0, next = 0;
    cosn::QuadState st;
  };
  struct Term {
    Factor u, v;
    const q1_30* weight = nullptr;
  };
  TwoVectorTriangle t_;
  MaterialCoeffs coeffs_;
  int terms_ = 0;
  Term term_[kMaxTerms];
};

// Eq. 1: per span the great circles of N and of L (H), their intersection S, the angle γ
// between them and the start angles n, l; per pixel two CORDIC rotations and
//   cos α = cos(n + n_t)·cos(l + l_t) + sin(n + n_t)·sin(l + l_t)·cos γ,
// then max(0, cos α) and cos^n α exactly (repeated squaring): the family's exact baseline.
class KbExactMethod final : public ShadingMethod {
 public:
  bool setup(const Triangle& tri, const ShadeContext& ctx) override;
  void shade_span(const Span& s, Rgb8* out) override;
  static constexpr bool kReadsEdgePositions = true;

 private:
  // The two halves of shade_span (as in KbOneVectorMethod): prepare_span sets up each term's
  // angles and steps for the span, evaluate_span runs eq. 1 per pixel.
  void prepare_span(const Span& s);
  void evaluate_span(const Span& s, Rgb8* out);
  struct Term {
    std::int64_t n = 0, dn = 0, l = 0, dl = 0;  // angle_t raw, n/l wrapped to [−π, π]
    q1_30 cos_gamma{};
    const q1_30* weight = nullptr;
    bool specular = false;
  };
  TwoVectorTriangle t_;
  std::uint32_t exponent_ = 1;
  int terms_ = 0;
  Term term_[kMaxTerms];
};

}  // namespace tp::fw::kb
