// Helpers for the host-extension tests: looking an extension up, moving a cloth off rest,
// system vectors to and from particle-major doubles, and the spring accelerations summed
// by a plain loop over the topology's spring list.
#pragma once

#include <clothlab/ext/external_forces.h>
#include <clothlab/ext/grid.h>
#include <clothlab/ext/jacobian.h>
#include <clothlab/ext/reductions.h>
#include <clothlab/ext/topology.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "cloth_test_support.hpp"

namespace clothlab::testing {

template <class Table>
const Table& host_extension(const clothlab_system& system, const char* id) {
  const void* table = system.get_extension(system.context, id);
  if (table == nullptr) throw std::runtime_error(std::string("the engine lacks ") + id);
  return *static_cast<const Table*>(table);
}

inline clothlab_topology topology_of(const clothlab_system& system) {
  clothlab_topology out{};
  out.struct_size = sizeof out;
  const auto& table = host_extension<clothlab_topology_extension>(system, CLOTHLAB_EXT_TOPOLOGY);
  if (table.get(system.context, &out) != CLOTHLAB_OK) throw std::runtime_error("topology failed");
  return out;
}

inline clothlab_grid grid_of(const clothlab_system& system) {
  clothlab_grid out{};
  out.struct_size = sizeof out;
  const auto& table = host_extension<clothlab_grid_extension>(system, CLOTHLAB_EXT_GRID);
  if (table.get(system.context, &out) != CLOTHLAB_OK) throw std::runtime_error("grid failed");
  return out;
}

// Jitters positions by up to `jitter` and gives every particle a velocity of up to
// 20 jitter; returns the state as stored (rounded to the cloth's precision).
inline void move_off_rest(Cloth& cloth, unsigned seed, double jitter, std::vector<double>& x,
                          std::vector<double>& v) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-jitter, jitter);
  cloth.positions(x);
  v.assign(x.size(), 0.0);
  for (double& component : x) component += uniform(random);
  for (double& component : v) component = 20 * uniform(random);
  cloth.set_state(x, v);
  cloth.positions(x);
  cloth.velocities(v);
}

// A fresh system vector holding `values` (particle-major doubles).
template <class Real>
void* vector_from(const clothlab_system& system, const std::vector<double>& values) {
  void* out = system.alloc_vector(system.context);
  for (std::size_t i = 0; i < system.particle_count; ++i)
    for (std::size_t k = 0; k < 3; ++k)
      element<Real>(out, system, i, k) = static_cast<Real>(values[3 * i + k]);
  return out;
}

template <class Real>
std::vector<double> values_of(const clothlab_system& system, const void* vector) {
  std::vector<double> out(3 * std::size_t{system.particle_count});
  for (std::size_t i = 0; i < system.particle_count; ++i)
    for (std::size_t k = 0; k < 3; ++k)
      out[3 * i + k] = element<Real>(const_cast<void*>(vector), system, i, k);
  return out;
}

// M^-1 times the spring forces, F_i = [ks (l - l0) + kd (u . dv)] u, from the topology's
// list (v empty: no damping); 0 on pinned particles.
inline std::vector<double> spring_acceleration(const clothlab_topology& topology,
                                               const std::vector<double>& inverse_mass,
                                               const std::vector<double>& x,
                                               const std::vector<double>& v) {
  std::vector<double> a(x.size(), 0.0);
  for (uint32_t s = 0; s < topology.spring_count; ++s) {
    const std::size_t i = topology.first[s], j = topology.second[s];
    double d[3], dv[3] = {0, 0, 0}, squared = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      d[k] = x[3 * j + k] - x[3 * i + k];
      if (!v.empty()) dv[k] = v[3 * j + k] - v[3 * i + k];
      squared += d[k] * d[k];
    }
    const double length = std::sqrt(squared);
    const double along = (d[0] * dv[0] + d[1] * dv[1] + d[2] * dv[2]) / length;
    const double magnitude = topology.ks[s] * (length - topology.rest_length[s]) +
                             (v.empty() ? 0.0 : topology.kd[s] * along);
    for (std::size_t k = 0; k < 3; ++k) {
      const double force = magnitude * d[k] / length;
      a[3 * i + k] += force * inverse_mass[i];
      a[3 * j + k] -= force * inverse_mass[j];
    }
  }
  return a;
}

template <class Real>
std::vector<double> inverse_masses(const clothlab_system& system) {
  const Real* inverse_mass = static_cast<const Real*>(system.inverse_mass);
  return std::vector<double>(inverse_mass, inverse_mass + system.particle_count);
}

}  // namespace clothlab::testing
