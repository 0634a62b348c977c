// The multigrid set-up's Galerkin products as one SIMD target's entry point,
// galerkin_products_<target> (multigrid_galerkin_path.hpp), compiled once per wider target of
// a portable build.
#include "multigrid_galerkin.hpp"
#include "simd_namespace.hpp"

namespace clothlab::builtin {

GalerkinProducts CLOTHLAB_SIMD_ENTRY(galerkin_products)() {
  return {[](const GridTransfer& transfer, const GridLevel& fine, GridLevel& coarse, int threads) {
            galerkin(transfer, fine, coarse, threads);
          },
          galerkin_from_table};
}

}  // namespace clothlab::builtin
