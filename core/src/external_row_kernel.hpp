// The external pass's accelerations of one grid row from the wind shares of the cells
// (wind_kernel.hpp): particle c of the row is corner a of cell c and b of cell c - 1 of its
// row, c' of cell c and d of cell c - 1 of the row above, so
//   F = (first_above[c] + second_above[c] + second_above[c - 1])
//     + (first_own[c] + first_own[c - 1] + second_own[c - 1]),
// grouped as the force pass's accumulators group them (same bits), and a = F w + g where
// the inverse mass w is not 0, else 0.
//
// Written twice like the other row kernels: a portable `omp simd` loop, and a block of SIMD
// lanes per iteration for float (the compiler vectorises the loop at 256 bits only).
#pragma once

#include <cstddef>
#include <limits>
#include <type_traits>

#include "float_lanes.hpp"
#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

// Share rows hold their components share_span apart (zeros left of column 0 and in
// column cols - 1, which starts no cell); out holds them out_span apart.
template <class Real>
struct ExternalRow {
  const Real* first_above;
  const Real* second_above;
  const Real* first_own;
  const Real* second_own;
  std::size_t share_span;
  const Real* inverse_mass;
  Real* out;
  std::size_t out_span;
  std::size_t cols;
  Real gravity[3];
};

// Returns the sum of 0 * a: NaN exactly when some a is not finite.
template <class Real>
inline Real external_row_accelerations_portable(const ExternalRow<Real>& row) {
  const Real* __restrict inverse_mass = row.inverse_mass;
  Real probe = 0;
  for (std::size_t k = 0; k < 3; ++k) {
    const std::size_t component = k * row.share_span;
    const Real* __restrict first_above = row.first_above + component;
    const Real* __restrict second_above = row.second_above + component;
    const Real* __restrict first_own = row.first_own + component;
    const Real* __restrict second_own = row.second_own + component;
    Real* __restrict out = row.out + k * row.out_span;
    const Real g = row.gravity[k];
#pragma omp simd reduction(+ : probe)
    for (std::size_t c = 0; c < row.cols; ++c) {
      const Real from_above = first_above[c] + second_above[c] + second_above[c - 1];
      const Real from_row = first_own[c] + first_own[c - 1] + second_own[c - 1];
      const Real force = from_above + from_row;
      const Real value = inverse_mass[c] > Real(0) ? force * inverse_mass[c] + g : Real(0);
      out[c] = value;
      probe += value * Real(0);
    }
  }
  return probe;
}

#if defined(CLOTHLAB_FLOAT_LANES)
inline float external_row_accelerations_lanes(const ExternalRow<float>& row) {
  Floats probe = zero_floats();
  const Floats zero = zero_floats();
  // One sweep over the columns, the three components in turn: the inverse mass is loaded and
  // compared once per block, and the pointers stay in registers (stores through out could
  // alias row, so read through it they would be loaded again each block).
  const std::size_t share_span = row.share_span, out_span = row.out_span;
  const float* const first_above = row.first_above;
  const float* const second_above = row.second_above;
  const float* const first_own = row.first_own;
  const float* const second_own = row.second_own;
  const float* const inverse_mass = row.inverse_mass;
  float* const out = row.out;
  const Floats g[3] = {broadcast(row.gravity[0]), broadcast(row.gravity[1]),
                       broadcast(row.gravity[2])};
  const auto block = [&](std::size_t c, auto lanes) {
    const Floats weight = lanes.load(inverse_mass + c);
    const LaneMask moving = greater(weight, zero);
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t at = c + k * share_span;
      const Floats from_above = lanes.load(first_above + at) + lanes.load(second_above + at) +
                                lanes.load(second_above + at - 1);
      const Floats from_row = lanes.load(first_own + at) + lanes.load(first_own + at - 1) +
                              lanes.load(second_own + at - 1);
      const Floats force = from_above + from_row;
      const Floats value = keep(moving, fused_multiply_add(force, weight, g[k]));
      lanes.store(out + c + k * out_span, value);
      probe = fused_multiply_add(value, zero, probe);
    }
  };
  // out aliases no input.
  for_each_whole_lane_block(0, row.cols, block);
  // NaN in some lane exactly when some value was not finite.
  return no_lane(unordered(probe, probe)) ? 0.0f : std::numeric_limits<float>::quiet_NaN();
}
#endif

template <class Real>
inline Real external_row_accelerations(const ExternalRow<Real>& row) {
#if defined(CLOTHLAB_FLOAT_LANES)
  if constexpr (std::is_same_v<Real, float>) return external_row_accelerations_lanes(row);
#endif
  return external_row_accelerations_portable(row);
}

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
