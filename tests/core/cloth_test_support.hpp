// Small helpers shared by the core tests: scenes and element access into system vectors.
#pragma once

#include <algorithm>
#include <clothlab/core/cloth.hpp>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace clothlab::testing {

// A unit-mass-per-particle grid in the xy plane (columns along +x, rows along -y),
// without springs, gravity or wind: tests switch on what they check.
inline Scene bare_scene(uint32_t rows, uint32_t cols) {
  Scene scene;
  scene.rows = rows;
  scene.cols = cols;
  scene.width = cols > 1 ? cols - 1.0 : 1.0;
  scene.height = rows > 1 ? rows - 1.0 : 1.0;
  scene.total_mass = static_cast<double>(rows) * cols;
  scene.gravity = {0, 0, 0};
  return scene;
}

// Pins the first column and/or particles n/2 and n - 1, kept sorted and unique as a Scene's
// pins must be.
inline void add_pins(Scene& scene, bool first_column, bool two_singles) {
  const uint32_t n = scene.rows * scene.cols;
  if (first_column) {
    for (uint32_t r = 0; r < scene.rows; ++r) scene.pinned.push_back(r * scene.cols);
  }
  if (two_singles) {
    scene.pinned.push_back(n / 2);
    scene.pinned.push_back(n - 1);
  }
  std::sort(scene.pinned.begin(), scene.pinned.end());
  scene.pinned.erase(std::unique(scene.pinned.begin(), scene.pinned.end()), scene.pinned.end());
}

// Component k of particle i on the unit-spaced layout (x = column, y = -row) moved by a
// smooth pattern of the given amplitude: a state off rest, springs stretched and sheared.
inline double perturbed_layout(std::size_t i, std::size_t k, uint32_t cols, double amplitude) {
  const double layout[3] = {static_cast<double>(i % cols), -static_cast<double>(i / cols), 0.0};
  return layout[k] + amplitude * std::sin(1.7 * static_cast<double>(i) + 2.1 * k + 0.3);
}

// Component k of particle i in a system vector of precision Real.
template <class Real>
Real& element(void* vector, const clothlab_system& system, std::size_t i, std::size_t k) {
  return static_cast<Real*>(vector)[k * system.stride + i];
}

// Evaluates the acceleration of the cloth's current state into a fresh vector and returns
// it particle-major as doubles.
template <class Real>
std::vector<double> acceleration(Cloth& cloth, bool with_velocity = true) {
  const clothlab_system& system = cloth.system();
  void* a = system.alloc_vector(system.context);
  const clothlab_status status = system.eval_acceleration(system.context, 0.0, system.x,
                                                          with_velocity ? system.v : nullptr, a);
  std::vector<double> out(3 * system.particle_count);
  for (std::size_t i = 0; i < system.particle_count; ++i) {
    for (std::size_t k = 0; k < 3; ++k) out[3 * i + k] = element<Real>(a, system, i, k);
  }
  if (status != CLOTHLAB_OK) out.assign(out.size(), -1e300);
  return out;
}

}  // namespace clothlab::testing
