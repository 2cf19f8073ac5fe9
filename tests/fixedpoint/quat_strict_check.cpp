// fixedpoint/quat.hpp instantiated under the firmware's warnings (tp_strict: -Werror
// -Wconversion -Wsign-conversion -Wshadow), in the formats the firmware uses, plus constant
// evaluation (static_assert) of one case per function: constexpr and UB-free at compile time.
#include "fixedpoint/quat.hpp"

namespace tp::fx::strict_check {

using qv30 = Vec3<q1_30>;
using qq30 = Quat<q1_30>;
inline constexpr qv30 kX{q1_30::one(), q1_30::zero(), q1_30::zero()};
inline constexpr qv30 kY{q1_30::zero(), q1_30::one(), q1_30::zero()};
static_assert(rotation_between<q1_30>(kX, kX) == identity<q1_30>());
static_assert(rotation_between<q1_30>(kX, kY).w.raw() == 759250125);  // 2^30 cos 45
static_assert(rotate<q1_30>(rotation_between<q1_30>(kX, neg_sat(kX)), kX) == neg_sat(kX));
static_assert(multiply<q1_30>(identity<q1_30>(), conjugate(identity<q1_30>())) ==
              identity<q1_30>());
static_assert(normalize<q1_30>(qq30{q1_30::zero(), q1_30::zero(), q1_30::zero(), q1_30::zero()}) ==
              identity<q1_30>());

int use_quat(qv30 a, qv30 b, Vec3<q15_16> p, Vec3<q1_14> s) {
  const qq30 q = normalize<q1_30>(
      multiply<q1_30>(rotation_between<q1_30>(a, b), conjugate(rotation_between<q1_30>(b, a))));
  const Quat<q1_14> q14 = rotation_between<q1_14>(s, s);
  return rotate<q15_16>(q, p).x.raw() + rotate<q1_30>(q, a).y.raw() + rotate<q1_14>(q14, s).z.raw();
}

}  // namespace tp::fx::strict_check
