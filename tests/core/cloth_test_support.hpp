// Small helpers shared by the core tests: scenes, element access into system vectors, and the
// largest entry and difference of particle-major vectors.
#pragma once

#include <gtest/gtest.h>

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

// A tilted, offset sheet with every force on (all three families damped, gravity, oblique
// wind) and two pins: particle 0 and n / 2.
inline Scene busy_scene(uint32_t rows, uint32_t cols) {
  Scene scene = testing::bare_scene(rows, cols);
  scene.width = 1.3;
  scene.height = 0.9;
  scene.origin = {0.1, 2.0, -0.3};
  scene.col_axis = {0.8, 0.0, 0.6};
  scene.row_axis = {0.0, -1.0, 0.0};
  scene.total_mass = 0.7;
  scene.structural = {500.0, 0.25};
  scene.shear = {120.0, 0.1};
  scene.flexion = {40.0, 0.05};
  scene.gravity = {0.0, -9.81, 0.0};
  scene.wind_direction = {0.48, 0.0, 0.84};
  scene.wind_strength = 7.5;
  const std::size_t n = std::size_t{rows} * cols;
  if (n > 1) scene.pinned.push_back(0);
  if (n > 2) scene.pinned.push_back(static_cast<uint32_t>(n / 2));
  // Scene copies handed to Cloth are expected to be normalised, as scene_from_abi does.
  const double length = std::hypot(scene.wind_direction[0], scene.wind_direction[2]);
  scene.wind_direction = {scene.wind_direction[0] / length, 0.0, scene.wind_direction[2] / length};
  return scene;
}

// Seed eq. 2.2, valid for m, n >= 2 (m rows, n columns).
inline SpringCounts seed_equation_2_2(int64_t m, int64_t n) {
  SpringCounts counts;
  counts.structural = static_cast<uint64_t>(2 * (m - 1) * (n - 1) + (m - 1) + (n - 1));
  counts.shear = static_cast<uint64_t>(2 * (m - 1) * (n - 1));
  counts.flexion = static_cast<uint64_t>(2 * (m - 2) * (n - 2) + 2 * ((m - 2) + (n - 2)));
  return counts;
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

// The largest magnitude among `values`.
inline double max_abs(const std::vector<double>& values) {
  double largest = 0;
  for (double value : values) largest = std::max(largest, std::abs(value));
  return largest;
}

// The largest entrywise difference of two vectors of one size.
inline double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  double largest = 0;
  for (std::size_t e = 0; e < a.size() && e < b.size(); ++e)
    largest = std::max(largest, std::abs(a[e] - b[e]));
  return largest;
}

}  // namespace clothlab::testing
