// What every SIMD target's copy of the multigrid Galerkin products (multigrid_galerkin.hpp)
// shares: the host's block table of the definite Jacobian as the preconditioner reads it
// (multigrid_preconditioner.hpp), D^-1's store, and the copies' entry points.
#pragma once

#include <clothlab/ext/jacobian.h>

#include <cstddef>
#include <cstdint>

#include "multigrid_level.hpp"
#include "multigrid_transfer.hpp"

namespace clothlab::builtin {

// A symmetric 3x3 block's row-major entry k as one of its 6 upper entries.
inline constexpr std::size_t kSymmetricEntry[9] = {0, 1, 2, 1, 3, 4, 2, 4, 5};

// The fine smoother's m_i D_i^-1 of particle i (`inverse` D_i^-1, row-major): its 6 upper
// entries, n apart, into `jacobi`, or `single` where that is set.
inline void store_jacobi(uint32_t i, double mass, const double* inverse, std::size_t n,
                         double* jacobi, float* single) {
  for (std::size_t k = 0; k < 9; ++k) {
    if (k / 3 > k % 3) continue;  // the lower entries are the upper's
    const double value = mass * inverse[k];
    if (single)
      single[kSymmetricEntry[k] * n + i] = static_cast<float>(value);
    else
      jacobi[kSymmetricEntry[k] * n + i] = value;
  }
}

struct BlockTable {
  const double* values;                   // 9 per slot of the pattern
  const clothlab_block_pattern* pattern;  // the host's
  const uint32_t* transposed;             // per slot, its transpose's slot
  const uint8_t* window_places;           // per slot, its column's place in the row's window
  const uint32_t* diagonal_slots;         // per row, its diagonal block's slot
  const double* mass;                     // per particle, 0 where pinned
  std::size_t particles;
  double* jacobi;        // store_jacobi's, or
  float* jacobi_single;  // this where it is set
  double* row_bounds;    // per fine row of nodes, its part of lambda_max
};

// One SIMD target's Galerkin products (multigrid_galerkin_path.hpp).
struct GalerkinProducts {
  // coarse = R fine P from the fine level's own blocks.
  void (*levels)(const GridTransfer&, const GridLevel& fine, GridLevel& coarse, int threads);
  // galerkin_from_table.
  void (*table)(const BlockTable&, const GridTransfer&, const GridLevel& fine, GridLevel& coarse,
                int threads);
};

}  // namespace clothlab::builtin
