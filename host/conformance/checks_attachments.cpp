// attachments.*: an integrator declaring CLOTHLAB_TRAIT_MOVES_ATTACHMENTS leaves every attached
// particle exactly on its target (clothlab.attachment-targets/1) after every step, in position
// and velocity, while the cloth hangs from it.
#include <clothlab/ext/integrator_traits.h>

#include <cmath>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "check.hpp"
#include "fixtures.hpp"

namespace clothlab::conformance {
namespace {

constexpr double circle_radius = 0.1;  // m
constexpr double circle_rate = 4.0;    // rad/s
constexpr double step_dt = 1e-3;
constexpr int steps = 30;

// Each attached particle goes round a circle in the x-y plane through where it starts.
class CirclingTargets final : public AttachmentSource {
 public:
  explicit CirclingTargets(std::vector<double> starts) : starts_(std::move(starts)) {}

  bool targets(double t, std::span<double> positions,
               std::span<double> velocities) noexcept override {
    const double c = std::cos(circle_rate * t), s = std::sin(circle_rate * t);
    for (std::size_t k = 0; 3 * k < starts_.size(); ++k) {
      positions[3 * k] = starts_[3 * k] + circle_radius * (c - 1.0);
      positions[3 * k + 1] = starts_[3 * k + 1] + circle_radius * s;
      positions[3 * k + 2] = starts_[3 * k + 2];
      velocities[3 * k] = -circle_radius * circle_rate * s;
      velocities[3 * k + 1] = circle_radius * circle_rate * c;
      velocities[3 * k + 2] = 0.0;
    }
    return true;
  }

 private:
  std::vector<double> starts_;
};

Verdict attachments_follow_their_targets(const clothlab_integrator& integrator, SheetShape shape,
                                         Precision precision) {
  Cloth cloth = sheet_cloth(sheet_scene(6, 5), shape, precision, pipeline_for(integrator));
  const std::vector<uint32_t> attached = cloth.scene().pinned;
  const State start = state_of(cloth);
  std::vector<double> starts;
  for (const uint32_t particle : attached)
    for (int axis = 0; axis < 3; ++axis) starts.push_back(start.x[3 * particle + axis]);
  CirclingTargets source(starts);
  cloth.set_attachments(attached, source);
  require(cloth.move_attachments(0.0), "the targets at t = 0 are not finite");
  IntegratorInstance instance(integrator, default_values(integrator));
  instance.prepare(cloth);
  std::vector<double> x(starts.size()), v(starts.size());
  // Float32 stores the target rounded: a few units in the last place of a coordinate ~1 m.
  const double tolerance = precision == Precision::Float32 ? 1e-6 : 1e-12;
  for (int step = 1; step <= steps; ++step) {
    instance.step(cloth, (step - 1) * step_dt, step_dt);
    const double t = step * step_dt;
    source.targets(t, x, v);
    const State now = state_of(cloth);
    for (std::size_t k = 0; k < attached.size(); ++k)
      for (int axis = 0; axis < 3; ++axis) {
        const std::size_t i = 3 * std::size_t{attached[k]} + axis;
        if (std::abs(now.x[i] - x[3 * k + axis]) <= tolerance &&
            std::abs(now.v[i] - v[3 * k + axis]) <= tolerance)
          continue;
        std::ostringstream reason;
        reason.precision(9);
        reason << "attached particle " << attached[k] << " off its target after step " << step
               << " (t = " << t << " s): coordinate " << axis << " at x " << now.x[i] << ", v "
               << now.v[i] << "; target x " << x[3 * k + axis] << ", v " << v[3 * k + axis];
        require(false, reason.str());
      }
  }
  return {true, std::to_string(attached.size()) + " attached particles on their circles after " +
                    "each of " + std::to_string(steps) + " steps"};
}

}  // namespace

std::vector<Check> attachment_checks(const clothlab_integrator& integrator) {
  const clothlab_integrator_traits* traits = integrator_traits(integrator);
  if (traits == nullptr || (traits->flags & CLOTHLAB_TRAIT_MOVES_ATTACHMENTS) == 0) return {};
  const clothlab_integrator* c = &integrator;
  std::vector<Check> checks;
  if (c->precisions & (1u << CLOTHLAB_FLOAT64))
    checks.push_back(
        {c->id, "attachments.follow-f64",
         [c] { return on_every_shape(*c, attachments_follow_their_targets, Precision::Float64); }});
  if (c->precisions & (1u << CLOTHLAB_FLOAT32))
    checks.push_back(
        {c->id, "attachments.follow-f32",
         [c] { return on_every_shape(*c, attachments_follow_their_targets, Precision::Float32); }});
  return checks;
}

}  // namespace clothlab::conformance
