#include "clothlab/analysis/local_solve_bound.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace clothlab::analysis {

LocalSolveBound local_solve_bound(const Scene& scene) {
  LocalSolveBound bound;
  const double particles = static_cast<double>(scene.rows) * scene.cols;
  bound.particle_mass = scene.total_mass / particles;
  bound.stiffness = scene.structural.ks;
  bound.dt_max = bound.stiffness > 0 ? std::sqrt(bound.particle_mass / bound.stiffness)
                                     : std::numeric_limits<double>::infinity();
  return bound;
}

uint32_t LocalSolveBound::substeps_per_frame(double frame_rate) const {
  // A frame's step over the bound, rounded up; a relative 1e-9 keeps an exact ratio whole.
  const double ratio = 1.0 / (frame_rate * dt_max);
  return static_cast<uint32_t>(std::max(1.0, std::ceil(ratio * (1.0 - 1e-9))));
}

}  // namespace clothlab::analysis
