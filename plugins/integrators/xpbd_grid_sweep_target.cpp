// xpbd's float grid sweep as one SIMD target's entry point, sweep_float_grid_<target>
// (xpbd_grid_path.hpp), compiled once per wider target of a portable build.
#include "simd_namespace.hpp"
#include "xpbd_grid_sweep.hpp"

namespace clothlab::builtin {

bool CLOTHLAB_SIMD_ENTRY(sweep_float_grid)(GridPlan<float>& plan, const Substep<float>& s,
                                           int threads) {
  return sweep_grid(plan, s, threads);
}

}  // namespace clothlab::builtin
