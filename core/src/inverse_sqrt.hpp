// 1/sqrt(s), or 0 where s is 0: the one transcendental of the spring and wind kernels,
// per lane type. A spring of zero length, or a degenerate triangle, has no direction
// and exerts no force.
#pragma once

#include <cmath>

#include "float_lanes.hpp"
#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

template <class Real>
inline Real inverse_sqrt_or_zero(Real s) {
  return s > Real(0) ? Real(1) / std::sqrt(s) : Real(0);
}

#if defined(CLOTHLAB_FLOAT_LANES)
// The hardware estimate refined by one Newton step, y (3 - s y^2) / 2: to within about 2 ulp
// from AVX-512's 14-bit estimate, 3 ulp from AVX2's 12-bit one. A sqrt and a divide per lane
// bounded the kernels before (perf: a third of a step). Below the smallest normal float the
// estimate is not reliable, so such lanes count as zero length (a spring shorter than 1e-19);
// NaN stays NaN, so a broken state still shows as non-finite accelerations.
inline Floats inverse_sqrt_or_zero(Floats s) {
  const Floats y = inverse_sqrt_estimate(not_less(s, broadcast(FLT_MIN)), s);  // else 0
  const Floats half_s_y = broadcast(0.5f) * s * y;
  return y * fused_negated_multiply_add(half_s_y, y, broadcast(1.5f));
}
#endif

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
