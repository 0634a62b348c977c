// The springs of one colour that start in one grid row, as xpbd's row kernel
// (xpbd_row_kernel.hpp) projects them; the same type for every SIMD target's copy of the kernel.
#pragma once

#include <cstddef>
#include <cstdint>

namespace clothlab::builtin {

template <class Real>
struct ColorRow {
  const Real* x;
  Real* displacement;
  const Real* inverse_mass;
  // The colour's multipliers, n of them; the springs of a row keep theirs at indices from
  // `first` on, below the next row's. Read unless `fresh`, written when `keep_lambda`.
  Real* lambda;
  std::size_t stride;
  std::size_t first;   // particle of the row's first spring start (column col_begin)
  std::size_t count;   // columns col_begin .. col_end
  std::size_t offset;  // partner = start + offset
  // Columns kept: all, or ((column >> alternation_shift) & 1) == parity for in-row
  // stencils (shift 0: step 1, shift 1: step 2); columns counted from 0 (col_begin is 0
  // for in-row stencils).
  bool alternates;
  uint32_t alternation_shift;
  uint32_t parity;
  Real rest;
  Real stiffness;  // ks h^2
  Real damping;    // kd h
  bool fresh;
  bool keep_lambda;
  // Every particle of the grid but those behind positions [varied_begin, varied_end) (from
  // `first`; a spring's start there, or its partner) has the inverse mass uniform_weight,
  // which is not 0: a run of springs outside needs neither the weights nor their
  // denominator (the lane kernels use this). uniform_weight 0: no such value.
  Real uniform_weight;
  std::size_t varied_begin, varied_end;
};

}  // namespace clothlab::builtin
