#include "clothlab/analysis/local_solve_bound.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace clothlab::analysis {

LocalSolveBound local_solve_bound(const ClothModel& model) {
  std::vector<LocalSolveBound> springs;
  for (std::size_t s = 0; s < model.spring_count(); ++s) {
    if (model.family[s] != CLOTHLAB_SPRING_STRUCTURAL || !(model.ks[s] > 0)) continue;
    LocalSolveBound spring;
    spring.particle_mass = (model.masses[model.first[s]] + model.masses[model.second[s]]) / 2;
    spring.stiffness = model.ks[s];
    spring.dt_max = std::sqrt(spring.particle_mass / spring.stiffness);
    springs.push_back(spring);
  }
  if (springs.empty()) return {0, 0, std::numeric_limits<double>::infinity()};
  const auto median = springs.begin() + static_cast<std::ptrdiff_t>(springs.size() / 2);
  std::nth_element(
      springs.begin(), median, springs.end(),
      [](const LocalSolveBound& l, const LocalSolveBound& r) { return l.dt_max < r.dt_max; });
  return *median;
}

uint32_t LocalSolveBound::substeps_per_frame(double frame_rate) const {
  // A frame's step over the bound, rounded up; a relative 1e-9 keeps an exact ratio whole.
  const double ratio = 1.0 / (frame_rate * dt_max);
  return static_cast<uint32_t>(std::max(1.0, std::ceil(ratio * (1.0 - 1e-9))));
}

}  // namespace clothlab::analysis
