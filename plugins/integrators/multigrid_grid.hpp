// The cloth's grid as the multigrid hierarchy sees it (implicit_euler's preconditioner,
// projective_dynamics' global solve): the layout from clothlab.grid/1 (particle r * cols + c),
// the level sizes, the pinned particles as Dirichlet nodes and the check that every spring
// stays within a level's reach. Errors are one-line sdk::Errors naming the setting that asked
// for the multigrid.
#pragma once

#include <algorithm>
#include <clothlab/sdk.hpp>
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "multigrid_hierarchy.hpp"

namespace clothlab::builtin {

template <class Real>
sdk::Grid grid_of(const sdk::System<Real>& system, const std::string& setting) {
  const std::optional<sdk::Grid> grid = system.grid();
  // Unsupported rather than invalid: the setting is fine, this scene lacks what it needs.
  if (!grid)
    throw sdk::Error(CLOTHLAB_ERROR_UNSUPPORTED,
                     setting +
                         " needs a cloth laid out as a grid (clothlab.grid/1); this scene "
                         "is not one");
  if (uint64_t{grid->rows()} * grid->cols() != system.particle_count())
    throw sdk::Error(CLOTHLAB_ERROR_INVALID_ARGUMENT,
                     setting + ": the grid's " + std::to_string(grid->rows()) + " x " +
                         std::to_string(grid->cols()) + " is not the particle count " +
                         std::to_string(system.particle_count()));
  return *grid;
}

// The level sizes (plan_levels) of the system's grid, its errors as sdk::Errors.
template <class Real>
std::vector<GridSize> plan_grid_levels(const sdk::System<Real>& system, long coarsest_particles,
                                       const std::string& setting,
                                       int coarsening = kMinCoarsening) {
  const sdk::Grid grid = grid_of(system, setting);
  try {
    return plan_levels(grid.rows(), grid.cols(), coarsest_particles, coarsening);
  } catch (const std::invalid_argument& error) {
    throw sdk::Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, setting + ": " + error.what());
  }
}

// 1 for every particle outside the active ranges (the pins), per particle.
template <class Real>
std::vector<uint8_t> fixed_particles(const sdk::System<Real>& system) {
  std::vector<uint8_t> fixed(system.particle_count(), 1);
  for (const clothlab_range& range : system.active())
    std::fill(fixed.begin() + range.begin, fixed.begin() + range.end, 0);
  return fixed;
}

// Every spring joins particles at most GridLevel::reach spacings apart along each axis.
template <class Real>
void check_spring_reach(const sdk::System<Real>& system, long cols, const std::string& setting) {
  const sdk::Topology topology = system.topology();
  for (uint32_t s = 0; s < topology.spring_count(); ++s) {
    const long a = topology.first()[s], b = topology.second()[s];
    if (std::abs(a / cols - b / cols) > GridLevel::reach ||
        std::abs(a % cols - b % cols) > GridLevel::reach)
      throw sdk::Error(CLOTHLAB_ERROR_INVALID_ARGUMENT,
                       setting + ": spring " + std::to_string(s) + " joins particles " +
                           std::to_string(a) + " and " + std::to_string(b) +
                           ", more than 2 grid spacings apart");
  }
}

}  // namespace clothlab::builtin
