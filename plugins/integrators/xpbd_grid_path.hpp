// xpbd's path on the grid: the plan built at prepare (xpbd_grid_plan.hpp) and the grid sweep
// (xpbd_grid_sweep.hpp) of the SIMD target that runs here (simd_entry.hpp; the wider targets'
// copies in xpbd_grid_sweep_target.cpp). float64 runs the plugin's own copy: the wider targets'
// copies are float32 only, as the lane kernels are.
#pragma once

#include <clothlab/plugin.h>

#include <clothlab/sdk.hpp>
#include <cstdint>
#include <string_view>
#include <type_traits>
#include <utility>

#include "simd_entry.hpp"
#include "xpbd_grid.hpp"
#include "xpbd_grid_plan.hpp"
#include "xpbd_grid_sweep.hpp"
#include "xpbd_substep.hpp"

namespace clothlab::builtin {

using FloatGridSweep = bool (*)(GridPlan<float>&, const Substep<float>&, int);

#if defined(CLOTHLAB_SIMD_WITH_AVX2)
bool sweep_float_grid_avx2(GridPlan<float>& plan, const Substep<float>& s, int threads);
#endif
#if defined(CLOTHLAB_SIMD_WITH_AVX512)
bool sweep_float_grid_avx512(GridPlan<float>& plan, const Substep<float>& s, int threads);
#endif

inline FloatGridSweep choose_float_grid_sweep() {
  return simd_entry<FloatGridSweep>(sweep_grid<float>, CLOTHLAB_AVX2_ENTRY(sweep_float_grid_avx2),
                                    CLOTHLAB_AVX512_ENTRY(sweep_float_grid_avx512));
}

template <class Real>
class GridPath {
 public:
  // From `prepare`: the plan for up to `threads` threads, and the target's sweep.
  void prepare(GridLayout layout, int iterations, uint32_t tether_slots, const Real* inverse_mass,
               uint32_t particle_count, int threads) {
    plan_.prepare(std::move(layout), iterations, tether_slots, inverse_mass, particle_count,
                  threads);
    if constexpr (std::is_same_v<Real, float>) float_sweep_ = choose_float_grid_sweep();
  }

  // Whether run may compute the external accelerations itself (see GridPlan).
  bool computes_external_ahead() const { return plan_.computes_external_ahead(); }

  // One substep on `threads` threads, computing the external accelerations as it goes where
  // `external.forces` is set; false when a velocity came out non-finite. Throws sdk::Error when
  // an external acceleration call failed.
  bool run(const Substep<Real>& s, int threads, const ExternalAhead<Real>& external = {}) {
    plan_.external = external;
    plan_.external_status.store(CLOTHLAB_OK, std::memory_order_relaxed);
    bool finite;
    if constexpr (std::is_same_v<Real, float>)
      finite = float_sweep_(plan_, s, threads);
    else
      finite = sweep_grid(plan_, s, threads);
    sdk::check(static_cast<clothlab_status>(plan_.external_status.load()),
               "external acceleration failed");
    return finite;
  }

 private:
  GridPlan<Real> plan_;
  FloatGridSweep float_sweep_ = nullptr;  // the SIMD target's
};

}  // namespace clothlab::builtin
