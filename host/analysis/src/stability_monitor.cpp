#include "clothlab/analysis/stability_monitor.hpp"

#include <algorithm>
#include <clothlab/core/triangle_mesh.hpp>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace clothlab::analysis {
namespace {

double norm(const Vec3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

void validate(const MonitorOptions& options) {
  auto fail = [](const char* key, double value, const char* allowed) {
    std::ostringstream message;
    message << "stability monitor: " << key << " = " << value << ", allowed " << allowed;
    throw std::invalid_argument(message.str());
  };
  if (options.check_interval < 1) fail("check_interval", 0, ">= 1");
  if (!(options.stretch_limit > 1.0)) fail("stretch_limit", options.stretch_limit, "> 1");
  if (!(options.energy_margin >= 0.0)) fail("energy_margin", options.energy_margin, ">= 0");
  if (!(options.wind_work_safety >= 1.0)) {
    fail("wind_work_safety", options.wind_work_safety, ">= 1");
  }
}

}  // namespace

const char* to_string(StabilityCheck check) {
  switch (check) {
    case StabilityCheck::None:
      return "none";
    case StabilityCheck::NonFinite:
      return "non-finite";
    case StabilityCheck::Stretch:
      return "stretch";
    case StabilityCheck::Energy:
      return "energy";
  }
  return "unknown";
}

StabilityMonitor::StabilityMonitor(const Cloth& cloth, double t0, const MonitorOptions& options)
    : options_(options), last_time_(t0), attachment_time_(t0) {
  validate(options);
  const Scene& scene = cloth.scene();
  const Cloth::Energy energy = cloth.energy();
  initial_energy_ = energy.total();
  const ClothModel& model = *cloth.model();
  const double diagonal = rest_diagonal(scene, model);
  energy_scale_ = scene.total_mass * norm(scene.gravity) * diagonal + std::abs(energy.kinetic) +
                  std::abs(energy.spring) + std::abs(energy.gravity);
  rest_area_ = surface_area(model.rest_positions, model.triangles);
  // Nothing here changes during a run: decided once, so the momentum's pass over every particle
  // is made only where it is used.
  measures_momentum_ = options.momentum_measures_pins && !scene.has_wind() && !scene.has_air() &&
                       cloth.colliders().empty();
  if (cloth.state_is_finite()) {
    last_power_ = wind_power_bound(cloth, cloth.max_stretch());
    cloth.pin_loads(pins_before_);
    if (measures_momentum_) momentum_before_ = cloth.free_momentum();
  }
}

void StabilityMonitor::add_attachment_work(const Cloth& cloth, double t) {
  if (!(t > attachment_time_)) return;
  cloth.pin_loads(pins_now_);
  const Cloth::PinLoads& before = pins_before_;
  const Cloth::PinLoads& now = pins_now_;
  const std::size_t values = now.positions.size();
  const Cloth::Momentum momentum_now =
      measures_momentum_ && values != 0 ? cloth.free_momentum() : Cloth::Momentum{};
  if (values != 0 && before.positions.size() == values) {
    const double dt = t - attachment_time_;
    // The pins' mean displacement over the interval.
    Vec3 mean{0, 0, 0};
    for (std::size_t k = 0; k < values; ++k) mean[k % 3] += now.positions[k] - before.positions[k];
    for (double& component : mean) component /= static_cast<double>(values / 3);
    // The impulse the pins gave the free cloth. Where gravity is the only other force on it, the
    // free particles' momentum measures it whatever the method did inside the step (springs,
    // constraints, tethers); otherwise it is sampled from the pins' springs.
    const Vec3& gravity = cloth.scene().gravity;
    Vec3 impulse{0, 0, 0};
    if (measures_momentum_)
      for (std::size_t axis = 0; axis < 3; ++axis)
        impulse[axis] = momentum_now.momentum[axis] - momentum_before_.momentum[axis] -
                        momentum_now.mass * gravity[axis] * dt;
    else
      for (std::size_t k = 0; k < values; ++k)
        impulse[k % 3] -= 0.5 * (now.spring_forces[k] + before.spring_forces[k]) * dt;
    // Work = sum over pins of impulse . displacement / dt: the whole impulse moves with the mean
    // displacement (exact where measured), each pin's sampled share with its own difference.
    double work = 0.0;
    for (std::size_t axis = 0; axis < 3; ++axis) work += impulse[axis] * mean[axis] / dt;
    for (std::size_t k = 0; k < values; ++k)
      work -= 0.5 * (now.spring_forces[k] + before.spring_forces[k]) *
              (now.positions[k] - before.positions[k] - mean[k % 3]);
    attachment_work_ += work;
  }
  std::swap(pins_before_, pins_now_);
  momentum_before_ = momentum_now;
  attachment_time_ = t;
}

double StabilityMonitor::wind_power_bound(const Cloth& cloth, double stretch) {
  const Scene& scene = cloth.scene();
  if (!(scene.has_wind() || scene.has_air()) || rest_area_ == 0.0) return 0.0;
  cloth.velocities(velocities_);
  double fastest_squared = 0.0;
  for (std::size_t i = 0; i + 2 < velocities_.size(); i += 3) {
    fastest_squared = std::max(fastest_squared, velocities_[i] * velocities_[i] +
                                                    velocities_[i + 1] * velocities_[i + 1] +
                                                    velocities_[i + 2] * velocities_[i + 2]);
  }
  const double area = rest_area_ * std::max(1.0, stretch) * std::max(1.0, stretch);
  const double fastest = std::sqrt(fastest_squared);
  // The air's drag and lift on a triangle are at most density (C_d + C_l / 2) A |u|^2 / 2, with
  // |u| <= |wind| + the fastest particle's speed.
  const Air& air = scene.air;
  const double relative = norm(air.wind_velocity) + fastest;
  const double air_force =
      scene.has_air() ? 0.5 * air.density * (air.drag_coefficient + 0.5 * air.lift_coefficient) *
                            relative * relative
                      : 0.0;
  return (std::abs(scene.wind_strength) + air_force) * area * fastest;
}

void StabilityMonitor::fail(StabilityCheck check, uint64_t step, double t, double value,
                            double limit, std::string reason) {
  verdict_ = {false, check, step, t, value, limit, std::move(reason)};
}

const Verdict& StabilityMonitor::observe(const Cloth& cloth, uint64_t step, double t) {
  // Every step: the attachments' power changes as fast as the cloth moves.
  if (verdict_.stable) add_attachment_work(cloth, t);
  if (step % options_.check_interval != 0) return verdict_;
  return check(cloth, step, t);
}

const Verdict& StabilityMonitor::check(const Cloth& cloth, uint64_t step, double t) {
  if (!verdict_.stable) return verdict_;
  ++checks_;
  std::ostringstream reason;
  if (!cloth.state_is_finite()) {
    reason << "non-finite position or velocity at step " << step << " (t = " << t << " s)";
    fail(StabilityCheck::NonFinite, step, t, 0.0, 0.0, reason.str());
    return verdict_;
  }
  const double stretch = cloth.max_stretch();
  if (!(stretch <= options_.stretch_limit)) {
    reason << "spring stretched to " << stretch << " x rest (limit " << options_.stretch_limit
           << ") at step " << step << " (t = " << t << " s)";
    fail(StabilityCheck::Stretch, step, t, stretch, options_.stretch_limit, reason.str());
    return verdict_;
  }
  const double power = wind_power_bound(cloth, stretch);
  wind_work_ +=
      std::max(0.0, t - last_time_) * std::max(power, last_power_) * options_.wind_work_safety;
  last_time_ = t;
  last_power_ = power;
  add_attachment_work(cloth, t);
  const double contact_work = cloth.contact_work();
  const double energy = cloth.energy().total();
  const double limit = initial_energy_ + wind_work_ + attachment_work_ + contact_work +
                       options_.energy_margin * energy_scale_;
  if (!(energy <= limit)) {
    reason << "energy " << energy << " J above initial " << initial_energy_
           << " J + wind work bound " << wind_work_ << " J";
    if (attachment_work_ != 0.0) reason << " + attachment work " << attachment_work_ << " J";
    if (contact_work != 0.0) reason << " + contact work " << contact_work << " J";
    reason << " + margin " << options_.energy_margin * energy_scale_ << " J at step " << step
           << " (t = " << t << " s)";
    fail(StabilityCheck::Energy, step, t, energy, limit, reason.str());
  }
  return verdict_;
}

}  // namespace clothlab::analysis
