#include <algorithm>
#include <clothlab/core/attachment_path.hpp>
#include <clothlab/core/cloth_model.hpp>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "value_text.hpp"

namespace clothlab {
namespace {

// Slack for rounding in a path that stands still or barely moves (m).
constexpr double jump_tolerance = 1e-9;

std::string owner(std::span<const uint32_t> particles, std::size_t index) {
  return "attachment " + std::to_string(index) + " (particle " + std::to_string(particles[index]) +
         ")";
}

double norm_at(const std::vector<double>& values, std::size_t index) {
  return std::hypot(values[3 * index], values[3 * index + 1], values[3 * index + 2]);
}

void read_finite(std::span<const uint32_t> particles, const AttachmentTargetReader& read, double t,
                 std::vector<double>& positions, std::vector<double>& velocities) {
  positions.assign(3 * particles.size(), 0.0);
  velocities.assign(3 * particles.size(), 0.0);
  read(t, positions, velocities);
  static constexpr const char* axes[] = {"x", "y", "z"};
  for (std::size_t i = 0; i < positions.size(); ++i)
    for (const auto& [name, values] :
         {std::pair{"position", &positions}, std::pair{"velocity", &velocities}})
      if (!std::isfinite((*values)[i]))
        throw std::invalid_argument(owner(particles, i / 3) +
                                    ": target at t = " + detail::shortest_text(t) + " s: " + name +
                                    "." + axes[i % 3] + " = " +
                                    detail::shortest_text((*values)[i]) + ", allowed finite");
}

}  // namespace

void check_attached_particles(std::span<const uint32_t> particles, uint32_t particle_count) {
  for (std::size_t k = 0; k < particles.size(); ++k)
    if (particles[k] >= particle_count)
      throw std::invalid_argument(
          "attachment " + std::to_string(k) + ": particle = " + std::to_string(particles[k]) +
          ", allowed 0 .. " + std::to_string(particle_count - 1) + " (the cloth's particles)");
}

void check_attachment_path(std::span<const uint32_t> particles, const AttachmentTargetReader& read,
                           double dt, uint64_t steps, uint32_t samples_per_step) {
  if (particles.empty()) return;
  const uint32_t samples = std::max<uint32_t>(samples_per_step, 1);
  const double interval = dt / samples;
  const char* const interval_name = samples == 1 ? "the step" : "the substep";
  std::vector<double> x0, v0, x1, v1;
  read_finite(particles, read, 0.0, x0, v0);
  for (uint64_t step = 0; step < steps; ++step)
    for (uint32_t sample = 1; sample <= samples; ++sample) {
      // Step starts as k dt exactly, the times between from the step's start.
      const double t = sample == samples ? static_cast<double>(step + 1) * dt
                                         : static_cast<double>(step) * dt + sample * interval;
      read_finite(particles, read, t, x1, v1);
      for (std::size_t k = 0; k < particles.size(); ++k) {
        const double moved = std::hypot(x1[3 * k] - x0[3 * k], x1[3 * k + 1] - x0[3 * k + 1],
                                        x1[3 * k + 2] - x0[3 * k + 2]);
        const double allowed =
            2.0 * interval * std::max(norm_at(v0, k), norm_at(v1, k)) + jump_tolerance;
        if (!(moved <= allowed))
          throw std::invalid_argument(
              owner(particles, k) + ": target jumps " + detail::shortest_text(moved) +
              " m between t = " + detail::shortest_text(t - interval) + " and " +
              detail::shortest_text(t) + " s, allowed a continuous path (at most " +
              detail::shortest_text(allowed) + " m: twice " + interval_name +
              " times its velocity there)");
      }
      std::swap(x0, x1);
      std::swap(v0, v1);
    }
}

void check_attachment_start(std::span<const uint32_t> particles, std::span<const double> targets,
                            std::span<const double> positions, const ClothModel& model) {
  for (std::size_t k = 0; k < particles.size(); ++k) {
    const uint32_t i = particles[k];
    double shortest = std::numeric_limits<double>::infinity();
    for (uint32_t a = model.adjacency_offsets[i]; a < model.adjacency_offsets[i + 1]; ++a)
      shortest = std::min(shortest, model.rest_length[model.adjacent_springs[a]]);
    if (!std::isfinite(shortest)) continue;  // no spring to stretch
    const double offset =
        std::hypot(targets[3 * k] - positions[3 * i], targets[3 * k + 1] - positions[3 * i + 1],
                   targets[3 * k + 2] - positions[3 * i + 2]);
    const double allowed = max_attachment_start_offset * shortest;
    if (!(offset <= allowed))
      throw std::invalid_argument(
          owner(particles, k) + ": target at t = 0 s lies " + detail::shortest_text(offset) +
          " m from the particle's start, allowed at most " + detail::shortest_text(allowed) +
          " m (" + detail::shortest_text(max_attachment_start_offset) +
          " of its shortest spring's rest length, " + detail::shortest_text(shortest) +
          " m): start the cloth where its attachments hold it");
  }
}

}  // namespace clothlab
