// The attached particles a scenario gives (clothlab/ext/attachments.h) and the path of their
// targets, checked as the host and the conformance runner check them before a run.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace clothlab {

struct ClothModel;

// Fills the targets at time t: 3 positions and 3 velocities per attached particle.
using AttachmentTargetReader =
    std::function<void(double t, std::vector<double>& positions, std::vector<double>& velocities)>;

// Throws std::invalid_argument for a particle index past the cloth ("attachment 0: particle = 9,
// allowed 0 .. 8 (the cloth's rows x cols particles)").
void check_attached_particles(std::span<const uint32_t> particles, uint32_t particle_count);

// Reads the targets at every step start t = k dt, k = 0 .. steps, and at samples_per_step - 1
// evenly spaced times inside each step (where integrators with substeps ask), and throws
// std::invalid_argument naming the attachment, the time and the value for a target that is not
// finite, or that moves between two consecutive times farther than twice the interval times its
// faster velocity there allows (a jump).
void check_attachment_path(std::span<const uint32_t> particles, const AttachmentTargetReader& read,
                           double dt, uint64_t steps, uint32_t samples_per_step = 1);

// How far an attached particle's target at t = 0 may lie from where the particle starts, as a
// share of the rest length of its shortest spring: the host moves the particle there before the
// first step, and farther would start the cloth stretched.
inline constexpr double max_attachment_start_offset = 0.1;

// Throws std::invalid_argument for an attached particle whose target at t = 0 (`targets`, 3 per
// attachment) lies farther from its start (`positions`, 3 per particle of `model`) than
// max_attachment_start_offset of its shortest spring ("attachment 0 (particle 5): target at
// t = 0 s lies 0.7 m from the particle's start, allowed at most 0.01 m (0.1 of its shortest
// spring's rest length, 0.1 m)").
void check_attachment_start(std::span<const uint32_t> particles, std::span<const double> targets,
                            std::span<const double> positions, const ClothModel& model);

}  // namespace clothlab
