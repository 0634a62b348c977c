// The Galerkin products of the multigrid set-up (multigrid_galerkin.hpp) of the SIMD target
// that runs here: the plugin's own copy (its build's flags) or, in a portable build, a wider
// target's (multigrid_galerkin_target.cpp), chosen as xpbd chooses its grid sweep
// (xpbd_grid_path.hpp): the widest the CPU runs, or the one CLOTHLAB_SIMD names.
#pragma once

#include <clothlab/plugin.h>

#include <clothlab/sdk/error.hpp>
#include <clothlab/sdk/simd_target.hpp>

#include "multigrid_block_table.hpp"
#include "multigrid_galerkin.hpp"
#include "multigrid_level.hpp"
#include "multigrid_transfer.hpp"

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

// Throws sdk::Error (invalid argument) with the choice's one-line reason when CLOTHLAB_SIMD
// names a target that cannot run here.
inline GalerkinProducts choose_galerkin_products() {
  const sdk::SimdChoice choice = sdk::choose_simd_target(sdk::kBuiltSimdTargets);
  if (choice.target.empty()) throw sdk::Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, choice.error);
#if defined(CLOTHLAB_SIMD_WITH_AVX512)
  if (choice.target == "avx512") return galerkin_products_avx512();
#endif
#if defined(CLOTHLAB_SIMD_WITH_AVX2)
  if (choice.target == "avx2") return galerkin_products_avx2();
#endif
  return galerkin_products_baseline();
}

}  // namespace clothlab::builtin
