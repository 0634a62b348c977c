// 1/sqrt(s), the one transcendental of the spring and wind kernels, per lane type:
// inverse_sqrt_or_zero is 0 where s is 0 (a spring of zero length, or a degenerate triangle,
// has no direction); scaled_inverse_sqrt, for kernels whose result is a multiple of the vector
// whose squared length is s, is finite there, so that multiple is 0;
// unclamped_scaled_inverse_sqrt, for kernels that mask those lanes themselves, is not.
#pragma once

#include <cmath>

#include "float_lanes.hpp"
#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

// scaled_inverse_sqrt(s) is the lane type's scale / sqrt(s), kScalarInverseSqrtScale for a
// scalar and kLanesInverseSqrtScale for Floats: a kernel that folds the scale into its
// constants saves the multiply by it (a power of two, so folding it is exact).
inline constexpr float kScalarInverseSqrtScale = 1.0f;

template <class Real>
inline Real inverse_sqrt_or_zero(Real s) {
  return s > Real(0) ? Real(1) / std::sqrt(s) : Real(0);
}

template <class Real>
inline Real scaled_inverse_sqrt(Real s) {
  return inverse_sqrt_or_zero(s);
}

#if defined(CLOTHLAB_FLOAT_LANES)
// The hardware estimate y refined by one Newton step, y (3 - s y^2) = 2 / sqrt(s): to within
// about 2 ulp from AVX-512's 14-bit estimate, 3 ulp from AVX2's 12-bit one. The step's factor
// 1/2 is the scale 2 left to the caller. A sqrt and a divide per lane bounded the kernels
// before (perf: a third of a step). NaN stays NaN, so a broken state still shows as non-finite
// accelerations.
inline constexpr float kLanesInverseSqrtScale = 2.0f;

inline Floats twice_refined_inverse_sqrt(Floats s, Floats y) {
  return y * fused_negated_multiply_add(s * y, y, broadcast(3.0f));
}

// Below the smallest normal float the estimate is not reliable, so such lanes count as zero
// length (a spring shorter than 1e-19).
inline Floats inverse_sqrt_or_zero(Floats s) {
  const Floats y = inverse_sqrt_estimate(not_less(s, broadcast(FLT_MIN)), s);  // else 0
  return broadcast(0.5f) * twice_refined_inverse_sqrt(s, y);  // the bits of y (1.5 - s y^2 / 2)
}

// Below the smallest normal float the estimate is held at 1/sqrt(FLT_MIN) = 2^63, which keeps
// the result finite and positive (between 2^64 and 3 2^63) where s is 0 or below FLT_MIN: one
// instruction, where the mask of inverse_sqrt_or_zero takes two and a register.
inline Floats scaled_inverse_sqrt(Floats s) {
  const Floats y = lane_min(broadcast(0x1p63f), inverse_sqrt_estimate(s));
  return twice_refined_inverse_sqrt(s, y);
}

// For kernels that mask the lanes below the smallest normal float out of everything computed
// from the result (xpbd_row_kernel.hpp): scaled_inverse_sqrt without the clamp, so infinite
// or NaN in those lanes (0 times infinity raises the invalid flag there; nothing traps it),
// and with scaled_inverse_sqrt's bits wherever its clamp does not act (s above FLT_MIN by more
// than the estimate's error).
inline Floats unclamped_scaled_inverse_sqrt(Floats s) {
  return twice_refined_inverse_sqrt(s, inverse_sqrt_estimate(s));
}
#endif

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
