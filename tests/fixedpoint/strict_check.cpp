// Instantiates the fixed-point templates in the formats the firmware uses, compiled with
// tp_strict (see CMakeLists.txt); also constant-evaluates a few results (static_assert), which
// proves constexpr-friendliness and catches UB at compile time.
#include "fixedpoint/arith.hpp"
#include "fixedpoint/sqrt.hpp"
#include "fixedpoint/vec3.hpp"

namespace tp::fx::strict_check {

using v30 = Vec3<q1_30>;
static_assert(div<q15_16>(q15_16::from_int(1), q15_16::from_int(4)).raw() == 16384);
static_assert(div<q15_16>(q15_16::from_int(-1), q15_16::zero()) == q15_16::min());
static_assert(sqrt<q1_30>(q1_30::from_ratio(1, 4)).raw() == (1 << 29));
static_assert(rsqrt<q15_16>(q15_16::from_int(4)).raw() == (1 << 15));
static_assert(rsqrt<q15_16>(q15_16::zero()) == q15_16::max());
static_assert(normalize<q1_30>(v30{q1_30::zero(), q1_30::from_int(-1), q1_30::zero()}) ==
              v30{q1_30::zero(), q1_30::from_int(-1), q1_30::zero()});
static_assert(dot<q1_30>(v30{q1_30::one(), q1_30::one(), q1_30::one()},
                         v30{q1_30::one(), q1_30::one(), q1_30::one()}) == q1_30::max());

int use_all(v30 a, v30 b, q15_16 s) {
  const auto c = cross<q1_30>(a, b);
  const auto n = normalize<q1_30>(add_sat(c, sub_sat(a, neg_sat(b))));
  v30 m{};
  const bool ok = try_normalize(scale<q1_30>(n, s), m);
  return ok ? dot<q15_16>(m, a).raw() + sqrt<q15_16>(s).raw() + rsqrt<q1_30>(s).raw() +
                  div<q1_14>(a.x, s).raw()
            : 0;
}

}  // namespace tp::fx::strict_check

#include "fixedpoint/cordic.hpp"
namespace tp::fx::strict_check {
static_assert(atan2(q15_16::zero(), q15_16::zero()) == angle_t::zero());
static_assert(to_polar(q15_16::from_int(3), q15_16::from_int(4)).magnitude == q15_16::from_int(5));
int use_trig(angle_t a, q1_30 c) { return sin_cos(a).sin.raw() + acos_unit(c).raw(); }
}  // namespace tp::fx::strict_check
