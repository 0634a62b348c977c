// The Galerkin products of the multigrid set-up (multigrid_galerkin.hpp) of the SIMD target
// that runs here (simd_entry.hpp; the wider targets' copies in multigrid_galerkin_target.cpp).
#pragma once

#include "multigrid_block_table.hpp"
#include "multigrid_galerkin.hpp"
#include "multigrid_level.hpp"
#include "multigrid_transfer.hpp"
#include "simd_entry.hpp"

namespace clothlab::builtin {

#if defined(CLOTHLAB_SIMD_WITH_AVX2)
GalerkinProducts galerkin_products_avx2();
#endif
#if defined(CLOTHLAB_SIMD_WITH_AVX512)
GalerkinProducts galerkin_products_avx512();
#endif

// The plugin's own copy.
inline GalerkinProducts galerkin_products_baseline() {
  return {[](const GridTransfer& transfer, const GridLevel& fine, GridLevel& coarse, int threads) {
            galerkin(transfer, fine, coarse, threads);
          },
          galerkin_from_table};
}

inline GalerkinProducts choose_galerkin_products() {
  using Make = GalerkinProducts (*)();
  return simd_entry<Make>(galerkin_products_baseline, CLOTHLAB_AVX2_ENTRY(galerkin_products_avx2),
                          CLOTHLAB_AVX512_ENTRY(galerkin_products_avx512))();
}

}  // namespace clothlab::builtin
