// The air's part of ForcePipeline's cell stages (force_pipeline.hpp): the drag and lift of a
// cell row (air_kernel.hpp), added to the shares the wind stage and the external pass gather.
#include "air_kernel.hpp"
#include "force_pipeline.hpp"
#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

template <class Real>
void ForcePipeline<Real>::add_air(const Real* x, const Real* below, const Real* v,
                                  const Real* v_below, std::size_t position_span, Real* first,
                                  Real* second, std::size_t span) const {
  AirRow<Real> job{};
  job.x = x;
  job.below = below;
  job.v = v;
  job.v_below = v_below;
  job.first = first;
  job.second = second;
  job.position_span = position_span;
  job.span = span;
  job.cells = cols_ - 1;
  for (int k = 0; k < 3; ++k) job.wind[k] = air_wind_[k];
  job.drag_twelfth = air_drag_twelfth_;
  job.lift_twelfth = air_lift_twelfth_;
  add_air_row_forces(job);
}

template void ForcePipeline<float>::add_air(const float*, const float*, const float*, const float*,
                                            std::size_t, float*, float*, std::size_t) const;
template void ForcePipeline<double>::add_air(const double*, const double*, const double*,
                                             const double*, std::size_t, double*, double*,
                                             std::size_t) const;

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
