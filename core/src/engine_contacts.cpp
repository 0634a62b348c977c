// The host extension clothlab.contacts/1 of the engine (clothlab/ext/contacts.h), and what the
// host reads of the cloth's contacts: the deepest penetration, the particles inside, the
// particles that crossed a collider.
#include <clothlab/ext/contacts.h>

#include <algorithm>
#include <clothlab/core/contact.hpp>
#include <cmath>

#include "engine_state.hpp"

namespace clothlab::detail {

// The host sets the colliders at each step's start with their motion over the step: the
// positions then are where each particle's path over the step begins. Against these poses,
// from the scenario and not from any motion, the last step's paths are judged for crossings.
template <class Real>
void EngineState<Real>::set_colliders(std::span<const Collider> colliders, double t) {
  particles_crossed_ = 0;
  if (colliders.size() == step_colliders_.size() && step_start_x_.size() == x_.size()) {
    const Real* const px = x_.data();
    const Real* const start = step_start_x_.data();
    const std::size_t s = stride_;
    for (const clothlab_range& range : active_)
      for (std::size_t i = range.begin; i < range.end; ++i)
        if (crossed_a_collider(step_colliders_, colliders,
                               {start[i], start[s + i], start[2 * s + i]},
                               {px[i], px[s + i], px[2 * s + i]}))
          ++particles_crossed_;
  }
  step_colliders_.assign(colliders.begin(), colliders.end());
  colliders_.assign(colliders.begin(), colliders.end());
  moved_colliders_.assign(colliders.begin(), colliders.end());
  step_start_time_ = t;
  if (colliders_.empty()) return;
  for (AlignedBuffer<Real>* buffer : {&path_start_, &step_start_x_}) {
    if (buffer->size() != x_.size()) *buffer = AlignedBuffer<Real>(x_.size());
    std::copy_n(x_.data(), x_.size(), buffer->data());
  }
}

template <class Real>
double EngineState<Real>::spring_energy_at(const Real* px, std::size_t i,
                                           const Vec3& position) const {
  const ClothModel& springs = *model_;
  const std::size_t s = stride_;
  double energy = 0.0;
  for (uint32_t k = springs.adjacency_offsets[i]; k < springs.adjacency_offsets[i + 1]; ++k) {
    const uint32_t spring = springs.adjacent_springs[k];
    const uint32_t j = springs.first[spring] == i ? springs.second[spring] : springs.first[spring];
    // No hypot: its scaling against overflow costs more than the rest of the spring, and a
    // cloth whose lengths overflow when squared (past 1e154 m) has long been called diverged.
    const double dx = px[j] - position[0], dy = px[s + j] - position[1],
                 dz = px[2 * s + j] - position[2];
    const double stretch = std::sqrt(dx * dx + dy * dy + dz * dz) - springs.rest_length[spring];
    energy += 0.5 * springs.ks[spring] * stretch * stretch;
  }
  return energy;
}

template <class Real>
clothlab_status EngineState<Real>::resolve_contacts(double t, void* x, void* v) {
  if (colliders_.empty()) return CLOTHLAB_OK;
  if (x == nullptr || v == nullptr) return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  Real* const px = static_cast<Real*>(x);
  Real* const pv = static_cast<Real*>(v);
  const std::size_t s = stride_;
  const std::vector<double>& masses = model_->masses;  // a mesh's differ per particle
  // Each collider where its motion has carried it by t; the paths start where the last
  // resolution (or the step's start) left the particles and the colliders.
  for (std::size_t k = 0; k < colliders_.size(); ++k)
    moved_colliders_[k] = step_colliders_[k].advanced(t - step_start_time_);
  const std::span<const Collider> met_before = colliders_, met_now = moved_colliders_;
  // Serial: a handful of colliders against the particles costs a fraction of a force pass.
  for (const clothlab_range& range : active_)
    for (std::size_t i = range.begin; i < range.end; ++i) {
      Vec3 position{px[i], px[s + i], px[2 * s + i]};
      Vec3 velocity{pv[i], pv[s + i], pv[2 * s + i]};
      for (int k = 0; k < 3; ++k)
        if (!std::isfinite(position[k]) || !std::isfinite(velocity[k]))
          return CLOTHLAB_ERROR_NUMERICAL;
      Real* const start = path_start_.data();
      const Vec3 from{start[i], start[s + i], start[2 * s + i]};
      const Vec3 before = position, velocity_before = velocity;
      if (resolve_swept_contact(met_before, met_now, from, position, velocity)) {
        // What the move did to the cloth's energy, signed (StabilityMonitor balances it): the
        // springs are read on the positions already moved, so the sum over particles is exact.
        double work = spring_energy_at(px, i, position) - spring_energy_at(px, i, before);
        for (int k = 0; k < 3; ++k)
          work += masses[i] *
                  (0.5 * (velocity[k] * velocity[k] - velocity_before[k] * velocity_before[k]) -
                   scene_.gravity[k] * (position[k] - before[k]));
        contact_work_ += work;
        for (int k = 0; k < 3; ++k) {
          px[k * s + i] = static_cast<Real>(position[k]);
          pv[k * s + i] = static_cast<Real>(velocity[k]);
        }
      }
      // The next substep's path starts where this one's ends.
      for (int k = 0; k < 3; ++k) start[k * s + i] = px[k * s + i];
    }
  colliders_.swap(moved_colliders_);
  return CLOTHLAB_OK;
}

template <class Real>
Cloth::Contacts EngineState<Real>::contacts() const {
  Cloth::Contacts out;
  if (colliders_.empty()) return out;
  out.particles_crossed = particles_crossed_;
  const Real* const px = x_.data();
  const std::size_t s = stride_;
  for (const clothlab_range& range : active_)
    for (std::size_t i = range.begin; i < range.end; ++i) {
      const ContactDepths depths = contact_depths(colliders_, {px[i], px[s + i], px[2 * s + i]});
      out.max_penetration = std::max(out.max_penetration, depths.penetration);
      out.max_depth_past_thickness = std::max(out.max_depth_past_thickness, depths.past_thickness);
      if (depths.penetration > 0) ++out.particles_inside;
    }
  return out;
}

template class EngineState<float>;
template class EngineState<double>;

}  // namespace clothlab::detail
