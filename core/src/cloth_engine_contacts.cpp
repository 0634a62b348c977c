// The host extension clothlab.contacts/1 of ClothEngine (clothlab/ext/contacts.h), and what the
// host reads of the cloth's contacts: the deepest penetration, the particles inside.
#include <clothlab/ext/contacts.h>

#include <algorithm>
#include <clothlab/core/contact.hpp>
#include <cmath>

#include "cloth_engine.hpp"

namespace clothlab::detail {

// The host sets the colliders at each step's start: the positions then are where each particle's
// path over the step begins.
template <class Real>
void ClothEngine<Real>::set_colliders(std::span<const Collider> colliders) {
  colliders_.assign(colliders.begin(), colliders.end());
  if (colliders_.empty()) return;
  if (path_start_.size() != x_.size()) path_start_ = AlignedBuffer<Real>(x_.size());
  std::copy_n(x_.data(), x_.size(), path_start_.data());
}

template <class Real>
clothlab_status ClothEngine<Real>::contacts_resolve_callback(void* context, double, void* x,
                                                             void* v) {
  ClothEngine& self = *static_cast<ClothEngine*>(context);
  if (self.colliders_.empty()) return CLOTHLAB_OK;
  if (x == nullptr || v == nullptr) return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  Real* const px = static_cast<Real*>(x);
  Real* const pv = static_cast<Real*>(v);
  const std::size_t s = self.stride_;
  // Serial: a handful of colliders against the particles costs a fraction of a force pass.
  for (const clothlab_range& range : self.active_)
    for (std::size_t i = range.begin; i < range.end; ++i) {
      Vec3 position{px[i], px[s + i], px[2 * s + i]};
      Vec3 velocity{pv[i], pv[s + i], pv[2 * s + i]};
      for (int k = 0; k < 3; ++k)
        if (!std::isfinite(position[k]) || !std::isfinite(velocity[k]))
          return CLOTHLAB_ERROR_NUMERICAL;
      Real* const start = self.path_start_.data();
      const Vec3 from{start[i], start[s + i], start[2 * s + i]};
      const bool touched = resolve_swept_contact(self.colliders_, from, position, velocity);
      if (touched) {
        for (int k = 0; k < 3; ++k) {
          px[k * s + i] = static_cast<Real>(position[k]);
          pv[k * s + i] = static_cast<Real>(velocity[k]);
        }
      }
      // The next substep's path starts where this one's ends.
      for (int k = 0; k < 3; ++k) start[k * s + i] = px[k * s + i];
    }
  return CLOTHLAB_OK;
}

template <class Real>
Cloth::Contacts ClothEngine<Real>::contacts() const {
  Cloth::Contacts out;
  if (colliders_.empty()) return out;
  const Real* const px = x_.data();
  const std::size_t s = stride_;
  for (const clothlab_range& range : active_)
    for (std::size_t i = range.begin; i < range.end; ++i) {
      const double depth = penetration_depth(colliders_, {px[i], px[s + i], px[2 * s + i]});
      out.max_penetration = std::max(out.max_penetration, depth);
      if (depth > 0) ++out.particles_inside;
    }
  return out;
}

template class ClothEngine<float>;
template class ClothEngine<double>;

}  // namespace clothlab::detail
