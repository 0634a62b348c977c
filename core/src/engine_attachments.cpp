// The host extension clothlab.attachment-targets/1 of the engine
// (clothlab/ext/attachment_targets.h): the attached particles set to their targets' positions
// and velocities.
#include <clothlab/ext/attachment_targets.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "engine_state.hpp"

namespace clothlab::detail {

template <class Real>
void EngineState<Real>::set_attachments(std::span<const uint32_t> particles,
                                        AttachmentSource& source) {
  for (const uint32_t particle : particles) {
    if (particle >= n_)
      throw std::invalid_argument("attached particle " + std::to_string(particle) +
                                  " out of range (the cloth has " + std::to_string(n_) +
                                  " particles)");
    if (inverse_mass_[particle] != 0)
      throw std::invalid_argument("attached particle " + std::to_string(particle) +
                                  " is not pinned");
  }
  attached_.assign(particles.begin(), particles.end());
  target_x_.assign(3 * attached_.size(), 0.0);
  target_v_.assign(3 * attached_.size(), 0.0);
  attachment_source_ = attached_.empty() ? nullptr : &source;
}

template <class Real>
void EngineState<Real>::pin_loads(Cloth::PinLoads& out) const {
  out.positions.clear();
  out.spring_forces.clear();
  if (attached_.empty()) return;
  const ClothModel& springs = *model_;
  const std::size_t s = stride_;
  for (const uint32_t i : springs.pinned) {
    const Vec3 v_own{v_[i], v_[s + i], v_[2 * s + i]};
    Vec3 force{0, 0, 0};
    for (uint32_t k = springs.adjacency_offsets[i]; k < springs.adjacency_offsets[i + 1]; ++k) {
      const uint32_t spring = springs.adjacent_springs[k];
      const uint32_t j =
          springs.first[spring] == i ? springs.second[spring] : springs.first[spring];
      Vec3 d{}, dv{};
      for (std::size_t axis = 0; axis < 3; ++axis) {
        d[axis] = x_[axis * s + j] - x_[axis * s + i];
        dv[axis] = v_[axis * s + j] - v_own[axis];
      }
      const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      if (length == 0.0) continue;
      // Force on i along d per unit length of d (spring_kernel.hpp's law).
      double magnitude = springs.ks[spring] * (length - springs.rest_length[spring]);
      if (velocity_forces_)
        magnitude += springs.kd[spring] * (dv[0] * d[0] + dv[1] * d[1] + dv[2] * d[2]) / length;
      for (std::size_t axis = 0; axis < 3; ++axis) force[axis] += magnitude / length * d[axis];
    }
    for (std::size_t axis = 0; axis < 3; ++axis) {
      out.positions.push_back(x_[axis * s + i]);
      out.spring_forces.push_back(force[axis]);
    }
  }
}

template <class Real>
Cloth::Momentum EngineState<Real>::free_momentum() const {
  Cloth::Momentum out;
  const std::size_t s = stride_;
  for (std::size_t i = 0; i < n_; ++i) {
    if (inverse_mass_[i] == 0) continue;
    const double mass = model_->masses[i];
    out.mass += mass;
    for (std::size_t axis = 0; axis < 3; ++axis) out.momentum[axis] += mass * v_[axis * s + i];
  }
  return out;
}

template <class Real>
bool EngineState<Real>::move_attachments(double t) {
  return move_attached(t, x_.data(), v_.data()) == CLOTHLAB_OK;
}

template <class Real>
clothlab_status EngineState<Real>::move_attached(double t, void* x, void* v) {
  if (attachment_source_ == nullptr) return CLOTHLAB_OK;
  if (x == nullptr || v == nullptr) return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  if (!attachment_source_->targets(t, target_x_, target_v_)) return CLOTHLAB_ERROR_NUMERICAL;
  Real* const px = static_cast<Real*>(x);
  Real* const pv = static_cast<Real*>(v);
  const std::size_t s = stride_;
  for (std::size_t k = 0; k < attached_.size(); ++k)
    for (std::size_t axis = 0; axis < 3; ++axis) {
      px[axis * s + attached_[k]] = static_cast<Real>(target_x_[3 * k + axis]);
      pv[axis * s + attached_[k]] = static_cast<Real>(target_v_[3 * k + axis]);
    }
  return CLOTHLAB_OK;
}

template class EngineState<float>;
template class EngineState<double>;

}  // namespace clothlab::detail
