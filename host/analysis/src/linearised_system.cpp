#include "clothlab/analysis/linearised_system.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "aligned_vector.hpp"

namespace clothlab::analysis {

using detail::AlignedVector;

struct LinearisedSystem::Impl {
  const clothlab_system& system;
  double t;
  std::size_t stride;
  std::vector<clothlab_range> active;
  AlignedVector base_x, base_v, probe_x, probe_v, plus, minus;
  double position_scale;  // a length typical of the state, for the finite-difference step
  uint64_t evaluations = 0;

  Impl(const clothlab_system& s, double time)
      : system(s),
        t(time),
        stride(s.stride),
        active(s.active, s.active + s.active_count),
        base_x(3 * stride),
        base_v(3 * stride),
        probe_x(3 * stride),
        probe_v(3 * stride),
        plus(3 * stride),
        minus(3 * stride),
        position_scale(0.0) {
    std::copy_n(static_cast<const double*>(s.x), 3 * stride, base_x.data());
    std::copy_n(static_cast<const double*>(s.v), 3 * stride, base_v.data());
    for (int k = 0; k < 3; ++k) {
      const double* component = base_x.data() + k * stride;
      const auto [low, high] = std::minmax_element(component, component + s.particle_count);
      position_scale = std::max(position_scale, *high - *low);
    }
    if (!(position_scale > 0.0)) position_scale = 1.0;
  }

  template <class Visit>
  void for_each_active(Visit visit) const {
    for (int k = 0; k < 3; ++k) {
      for (const clothlab_range& range : active) {
        for (uint32_t i = range.begin; i < range.end; ++i) visit(k * stride + i);
      }
    }
  }

  double max_abs(std::span<const double> u) const {
    double largest = 0.0;
    for_each_active([&](std::size_t i) { largest = std::max(largest, std::abs(u[i])); });
    return largest;
  }

  void evaluate(const AlignedVector& x, const AlignedVector& v, AlignedVector& a) {
    clothlab_status status =
        system.eval_acceleration(system.context, t, x.data(), v.data(), a.data());
    ++evaluations;
    if (status != CLOTHLAB_OK) {
      throw std::runtime_error("linearisation: eval_acceleration returned status " +
                               std::to_string(status) + " about the base state");
    }
  }

  // out = (a(base + eps d) - a(base - eps d)) / (2 eps), d applied to x or to v.
  void central_difference(std::span<const double> direction, std::span<double> out,
                          bool along_velocity, double eps) {
    std::copy_n(base_x.data(), base_x.size(), probe_x.data());
    std::copy_n(base_v.data(), base_v.size(), probe_v.data());
    AlignedVector& probe = along_velocity ? probe_v : probe_x;
    const AlignedVector& base = along_velocity ? base_v : base_x;
    for_each_active([&](std::size_t i) { probe[i] = base[i] + eps * direction[i]; });
    evaluate(probe_x, probe_v, plus);
    for_each_active([&](std::size_t i) { probe[i] = base[i] - eps * direction[i]; });
    evaluate(probe_x, probe_v, minus);
    std::fill(out.begin(), out.end(), 0.0);
    for_each_active([&](std::size_t i) { out[i] = (plus[i] - minus[i]) / (2.0 * eps); });
  }

  void apply(std::span<const double> direction, std::span<double> out, bool along_velocity) {
    if (direction.size() != 3 * stride || out.size() != 3 * stride) {
      throw std::invalid_argument("linearisation: vectors must hold 3 * stride = " +
                                  std::to_string(3 * stride) + " doubles");
    }
    const double largest = max_abs(direction);
    if (largest == 0.0) {
      std::fill(out.begin(), out.end(), 0.0);
      return;
    }
    // Positions: a step of ~1e-6 of the cloth's extent balances truncation against round-off.
    // Damping is linear in v, so any step is exact; a unit-scale one keeps round-off low.
    const double eps = (along_velocity ? 1.0 : 1e-6 * position_scale) / largest;
    central_difference(direction, out, along_velocity, eps);
  }
};

LinearisedSystem::LinearisedSystem(const clothlab_system& system, double t) {
  if (system.precision != CLOTHLAB_FLOAT64) {
    throw std::invalid_argument(
        "linearisation: system precision " + std::to_string(system.precision) +
        " not supported, needs float64 (" + std::to_string(CLOTHLAB_FLOAT64) + ")");
  }
  if (system.x == nullptr || system.v == nullptr || system.eval_acceleration == nullptr) {
    throw std::invalid_argument("linearisation: system lacks state arrays or eval_acceleration");
  }
  impl_ = std::make_unique<Impl>(system, t);
}

LinearisedSystem::~LinearisedSystem() = default;

std::size_t LinearisedSystem::vector_size() const { return 3 * impl_->stride; }

std::size_t LinearisedSystem::active_dof() const {
  std::size_t count = 0;
  for (const clothlab_range& range : impl_->active) count += range.end - range.begin;
  return 3 * count;
}

void LinearisedSystem::position_jacobian(std::span<const double> u, std::span<double> out) {
  impl_->apply(u, out, false);
}

void LinearisedSystem::velocity_jacobian(std::span<const double> w, std::span<double> out) {
  impl_->apply(w, out, true);
}

double LinearisedSystem::dot(std::span<const double> a, std::span<const double> b) const {
  double sum = 0.0;
  impl_->for_each_active([&](std::size_t i) { sum += a[i] * b[i]; });
  return sum;
}

void LinearisedSystem::keep_active(std::span<double> u) const {
  std::vector<double> kept(u.size(), 0.0);
  impl_->for_each_active([&](std::size_t i) { kept[i] = u[i]; });
  std::copy(kept.begin(), kept.end(), u.begin());
}

uint64_t LinearisedSystem::acceleration_evaluations() const { return impl_->evaluations; }

}  // namespace clothlab::analysis
