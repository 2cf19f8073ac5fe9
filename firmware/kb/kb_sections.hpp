// Summed quadratic sections (Kuijk-Blake section 2, last paragraphs; docs/KUIJK-BLAKE.md): every
// term (a light's diffuse or specular f along the span, times its per-channel weight) is a
// piecewise quadratic in x with break points where φ crosses ±a, ±b. Their sum is again
// piecewise quadratic with the union of the break points, so the whole span is ONE
// forward-differenced quadratic per colour channel: two additions per channel per pixel plus
// one comparison per merged segment, whatever the number of lights.
//
// Exactness: each term's pieces come from cosn::make_segments (Q.S states, exact integer
// polynomials per piece). At a term's break point the running sum receives
// cosn::jump(prev, next) = next.state − prev.state advanced to next.x, so at every pixel the
// running state equals the sum of the terms' direct evaluations, bit for bit (tested over
// spans of 4,096 pixels in tests/kb/test_kb_sections.cpp).
//
// Units: a channel's value v (cosn's state format Q.S, S = cosn::kStateFrac = 44) is
// 255·I/4096, so the output level round(255·I) is round(v / 2^(S − 12)), a shift: the per-term
// scale Il_c·k·O_c·f(s)·255/4096 <= 16·255/4096 < 1 fits cosn's q1_30 scale. Sum bound: 16 lights ×
// 2 terms × 2^S = 2^49 for the value; the differences are bounded per term in cosn_fd.hpp and
// checked here (kSafeBound) — a span whose terms could overflow the sum is evaluated pixel by pixel
// from the direct evaluations instead.
//
// Skipping: a segment where every term sits on a zero piece (|φ| >= b) has exactly the
// ambient state (zero pieces have zero state, and the running sum is exact), so it is filled
// with the ambient colour without stepping — bit-identical to stepping it.
#pragma once

#include <cstdint>

#include "firmware/cosn_fd.hpp"
#include "firmware/types.hpp"
#include "fixedpoint/cordic.hpp"
#include "fixedpoint/divide.hpp"

namespace tp::fw::kb {

inline constexpr int kMaxTerms = 2 * static_cast<int>(kMaxLights);
inline constexpr int kLevelShift = cosn::kStateFrac - 12;  // v = 255·I / 2^12 in Q.S
// Per-term magnitude budget: 32 terms of at most 2^57 each stay below 2^62.
inline constexpr std::int64_t kSafeBound = std::int64_t{1} << 57;

// 255·I in Q.S units of 1/4096 -> 8-bit level: clamp(round(v / 2^(S − 12)), 0, 255).
constexpr std::uint8_t level_of(std::int64_t v) {
  if (v <= 0) return 0;
  const std::int64_t l = (v + (std::int64_t{1} << (kLevelShift - 1))) >> kLevelShift;
  return static_cast<std::uint8_t>(l > 255 ? 255 : l);
}

// One term's pieces on the span, per channel (the break points do not depend on the scale, so
// the three channels share x and piece).
inline constexpr int kMaxTermSegments = 2 * cosn::kMaxSegments;
inline constexpr std::int64_t kPiRaw = fx::pi().raw();
inline constexpr std::int64_t kTwoPiRawS = fx::two_pi_raw();

struct TermSegments {
  cosn::CosnSegment seg[3][kMaxTermSegments];
  int count = 0;
};

// Fills one term: f along θ(x) = θ0 + x·dθ with a per-channel scale (Q1.30, in [0, 1]),
// θ0 in [−π, π]. Channels with the same scale as the previous one (white lights) reuse its
// segments. When θ leaves [−π, π] inside the span (V passes the point opposite S, possible
// only with more than ~90° of rotation on a span), the span is cut where it does and the rest
// continues at θ − 2π (cos φ is 2π-periodic; f is zero near ±π since b < π): cosn's
// precondition |θ| <= π then holds on both parts, and a term has at most 2 × 5 segments.
constexpr int make_one_channel(const cosn::CosnCoeffs& coeffs, fx::angle_t theta0,
                               fx::angle_t dtheta, cosn::scale_t scale, int length,
                               cosn::CosnSegment* out) {
  const std::int64_t t0 = theta0.raw();
  // cosn saturates dθ to ±1 rad per pixel; use the same step here.
  const std::int64_t dt_in = length > 1 ? dtheta.raw() : 0;
  const std::int64_t dt = dt_in > cosn::kMaxDThetaRaw
                              ? cosn::kMaxDThetaRaw
                              : (dt_in < -cosn::kMaxDThetaRaw ? -cosn::kMaxDThetaRaw : dt_in);
  const std::int64_t end = t0 + dt * (length - 1);
  if (end <= kPiRaw && end >= -kPiRaw)
    return cosn::make_segments(coeffs, theta0, dtheta, scale, length, out);
  // First pixel past ±π.
  const std::int64_t k = dt > 0 ? fx::idiv(kPiRaw - t0, dt) + 1 : fx::idiv(t0 + kPiRaw, -dt) + 1;
  const int first = cosn::make_segments(coeffs, theta0, dtheta, scale, static_cast<int>(k), out);
  const std::int64_t t1 = t0 + dt * k + (dt > 0 ? -kTwoPiRawS : kTwoPiRawS);
  cosn::CosnSegment* rest = out + first;
  const int second = cosn::make_segments(coeffs, fx::angle_t::from_raw_sat(t1), dtheta, scale,
                                         length - static_cast<int>(k), rest);
  for (int i = 0; i < second; ++i) rest[i].x += static_cast<std::int32_t>(k);
  return first + second;
}

constexpr void make_term(TermSegments& t, const cosn::CosnCoeffs& coeffs, fx::angle_t theta0,
                         fx::angle_t dtheta, const cosn::scale_t scale[3], int length) {
  t.count = make_one_channel(coeffs, theta0, dtheta, scale[0], length, t.seg[0]);
  for (int c = 1; c < 3; ++c) {
    if (scale[c] == scale[c - 1]) {
      for (int i = 0; i < t.count; ++i) t.seg[c][i] = t.seg[c - 1][i];
    } else {
      (void)make_one_channel(coeffs, theta0, dtheta, scale[c], length, t.seg[c]);
    }
  }
}

constexpr bool is_zero_piece(int piece) { return piece == 0 || piece == 4; }

class SpanSections {
 public:
  struct Stats {
    std::uint32_t segments = 0;        // merged segments evaluated (or filled)
    std::uint32_t ambient_pixels = 0;  // pixels filled without evaluation
    bool direct = false;               // fell back to direct evaluation (overflow guard)
  };

  // A span of `length` pixels (1..4096) whose constant part is ambient[c] (Q.S, 255·I/4096).
  constexpr void begin(int length, const std::int64_t ambient[3]) {
    length_ = length;
    count_ = 0;
    terms_count_ = 0;
    safe_ = true;
    for (int c = 0; c < 3; ++c) ambient_[c] = ambient[c];
  }

  // The next term's storage, filled in place by the caller (cosn::make_segments per
  // channel), then taken into the sum by commit(). At most kMaxTerms terms per span.
  constexpr TermSegments& next_term() { return terms_[terms_count_]; }
  constexpr void commit() {
    const TermSegments& t = terms_[terms_count_++];
    for (int i = 0; i < t.count; ++i) {
      Event& e = events_[count_++];
      e.x = t.seg[0][i].x;
      const bool now = !is_zero_piece(t.seg[0][i].piece);
      const bool before = i > 0 && !is_zero_piece(t.seg[0][i - 1].piece);
      e.active = (now ? 1 : 0) - (before ? 1 : 0);
      for (int c = 0; c < 3; ++c) {
        safe_ = safe_ && bounded(t.seg[c][i].st);
        e.d[c] = i == 0 ? t.seg[c][0].st : cosn::jump(t.seg[c][i - 1], t.seg[c][i]);
      }
    }
  }
  constexpr int terms() const { return terms_count_; }

  // Writes the span's colours; returns what it did (for the counters).
  constexpr Stats evaluate(Rgb8* out, bool skip_zero_segments) {
    if (!safe_) {
      for (int x = 0; x < length_; ++x) out[x] = direct_pixel(x);
      return Stats{1, 0, true};
    }
    return run(LevelSink{out}, skip_zero_segments);
  }

  // The running Q.S values per pixel (tests: bit-exactness of the forward differencing).
  // Spans refused by the overflow guard are evaluated directly (Stats::direct).
  constexpr Stats evaluate_raw(std::int64_t* r, std::int64_t* g, std::int64_t* b) {
    if (!safe_) {
      for (int x = 0; x < length_; ++x)
        RawSink{r, g, b}.put(x, direct_raw(x, 0), direct_raw(x, 1), direct_raw(x, 2));
      return Stats{1, 0, true};
    }
    return run(RawSink{r, g, b}, false);
  }

  // Direct evaluation of the summed polynomial of channel c at pixel x (Q.S): the ambient
  // plus every term's own polynomial at x (tests; the overflow fallback).
  constexpr std::int64_t direct_raw(int x, int c) const {
    std::int64_t v = ambient_[c];
    for (int j = 0; j < terms_count_; ++j) v += cosn::eval_at(terms_[j].seg[c], terms_[j].count, x);
    return v;
  }
  constexpr Rgb8 direct_pixel(int x) const {
    return Rgb8{level_of(direct_raw(x, 0)), level_of(direct_raw(x, 1)), level_of(direct_raw(x, 2))};
  }

 private:
  struct Event {
    std::int32_t x = 0;
    std::int32_t active = 0;  // change in the number of terms on a non-zero piece
    cosn::QuadState d[3];
  };

  static constexpr std::int64_t mag(std::int64_t v) { return v < 0 ? -v : v; }
  static constexpr bool bounded(const cosn::QuadState& s) {
    return mag(s.v) < kSafeBound && mag(s.d1) < kSafeBound && mag(s.d2) < kSafeBound;
  }

  struct LevelSink {
    Rgb8* out;
    constexpr void put(int x, std::int64_t r, std::int64_t g, std::int64_t b) const {
      out[x] = Rgb8{level_of(r), level_of(g), level_of(b)};
    }
    constexpr void fill(int x, int end, const std::int64_t v[3]) const {
      const Rgb8 c{level_of(v[0]), level_of(v[1]), level_of(v[2])};
      for (; x < end; ++x) out[x] = c;
    }
  };
  struct RawSink {
    std::int64_t *r, *g, *b;
    constexpr void put(int x, std::int64_t vr, std::int64_t vg, std::int64_t vb) const {
      r[x] = vr, g[x] = vg, b[x] = vb;
    }
    constexpr void fill(int x, int end, const std::int64_t v[3]) const {
      for (; x < end; ++x) put(x, v[0], v[1], v[2]);
    }
  };

  template <class Sink>
  constexpr Stats run(const Sink& sink, bool skip_zero_segments) {
    Stats stats;
    sort_events();
    const auto ev = [this](int k) -> const Event& { return events_[order_[k] & 0xffffu]; };
    cosn::QuadState acc[3];
    for (int c = 0; c < 3; ++c) acc[c] = {ambient_[c], 0, 0};
    int active = 0, i = 0, x = 0;
    while (x < length_) {
      for (; i < count_ && ev(i).x <= x; ++i) {  // break points at x: change the sum
        const Event& e = ev(i);
        active += e.active;
        for (int c = 0; c < 3; ++c) {
          acc[c].v += e.d[c].v;
          acc[c].d1 += e.d[c].d1;
          acc[c].d2 += e.d[c].d2;
        }
      }
      const int end = i < count_ && ev(i).x < length_ ? ev(i).x : length_;
      ++stats.segments;
      if (active == 0 && skip_zero_segments) {
        // Every term is on a zero piece: the state is exactly (ambient, 0, 0).
        sink.fill(x, end, ambient_);
        stats.ambient_pixels += static_cast<std::uint32_t>(end - x);
        x = end;
        continue;
      }
      step_run(sink, acc, x, end);
      x = end;
    }
    return stats;
  }

  // The per-pixel inner loop: two additions per channel per pixel.
  template <class Sink>
  static constexpr void step_run(const Sink& sink, cosn::QuadState acc[3], int x, int end) {
    std::int64_t r = acc[0].v, g = acc[1].v, b = acc[2].v;
    std::int64_t dr = acc[0].d1, dg = acc[1].d1, db = acc[2].d1;
    const std::int64_t ddr = acc[0].d2, ddg = acc[1].d2, ddb = acc[2].d2;
    for (; x < end; ++x) {
      sink.put(x, r, g, b);
      r += dr, dr += ddr;
      g += dg, dg += ddg;
      b += db, db += ddb;
    }
    acc[0] = {r, dr, ddr};
    acc[1] = {g, dg, ddg};
    acc[2] = {b, db, ddb};
  }

  // Events in x order: an insertion sort of 32-bit keys (x << 16 | index; x < 4096, index <
  // 320), stable, so that a term's events keep their order; the events themselves stay put.
  constexpr void sort_events() {
    for (int i = 0; i < count_; ++i)
      order_[i] = static_cast<std::uint32_t>(events_[i].x) << 16 | static_cast<std::uint32_t>(i);
    for (int i = 1; i < count_; ++i) {
      const std::uint32_t k = order_[i];
      int j = i - 1;
      while (j >= 0 && order_[j] > k) {
        order_[j + 1] = order_[j];
        --j;
      }
      order_[j + 1] = k;
    }
  }

  int length_ = 0, count_ = 0, terms_count_ = 0;
  bool safe_ = true;
  std::int64_t ambient_[3] = {0, 0, 0};
  Event events_[kMaxTerms * kMaxTermSegments];
  std::uint32_t order_[kMaxTerms * kMaxTermSegments] = {};
  TermSegments terms_[kMaxTerms];
};

}  // namespace tp::fw::kb
