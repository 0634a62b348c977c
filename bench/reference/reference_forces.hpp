// The straightforward, seed-style force evaluation: an array of spring structs with
// particle indices, one loop that scatters each spring's force into both particles, one
// thread, particle-major (AoS) arrays. It is the in-run performance baseline and the
// correctness oracle for the core's stencil kernels.
#pragma once

#include <clothlab/core/cloth.hpp>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace clothlab::reference {

template <class Real>
struct Spring {
  uint32_t i;
  uint32_t j;
  Real rest;
  Real ks;
  Real kd;
  uint8_t family;  // CLOTHLAB_SPRING_* (clothlab/ext/topology.h)
};

template <class Real>
class ReferenceCloth {
 public:
  explicit ReferenceCloth(const Scene& scene);

  std::size_t particle_count() const { return inverse_mass_.size(); }
  const std::vector<Spring<Real>>& springs() const { return springs_; }
  // The initial layout, particle-major: x[3 * i + k].
  const std::vector<Real>& initial_positions() const { return initial_positions_; }

  // a = M^-1 F(x, v) on unpinned particles, 0 on pinned ones; all arrays particle-major
  // with 3 * particle_count() elements. v == nullptr leaves out damping. No allocation.
  void acceleration(const Real* x, const Real* v, Real* a);
  // The same for gravity, wind and air alone (no springs); the air at velocities v
  // (nullptr: at rest).
  void external_acceleration(const Real* x, const Real* v, Real* a);
  const std::vector<Real>& inverse_masses() const { return inverse_mass_; }

 private:
  void add_springs(const Real* x, const Real* v);
  void to_acceleration(Real* a) const;
  void add_wind(const Real* x);
  void add_air(const Real* x, const Real* v);

  Scene scene_;
  std::vector<Spring<Real>> springs_;
  std::vector<Real> initial_positions_;
  std::vector<Real> inverse_mass_;
  std::vector<Real> forces_;
  Real mass_;
};

extern template class ReferenceCloth<float>;
extern template class ReferenceCloth<double>;

}  // namespace clothlab::reference
