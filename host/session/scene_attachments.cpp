#include "scene_attachments.hpp"

#include <algorithm>
#include <clothlab/host/errors.hpp>
#include <clothlab/host/param_text.hpp>
#include <cmath>

namespace clothlab::cli {

namespace {

void check_call(clothlab_status status, const clothlab_message& message, const std::string& what) {
  if (status != CLOTHLAB_OK)
    throw host::PluginError(status, what + ": " + host::one_line(message.text));
}

double norm_at(const std::vector<double>& values, std::size_t index) {
  return std::hypot(values[3 * index], values[3 * index + 1], values[3 * index + 2]);
}

// Slack for rounding in a path that stands still or barely moves (m).
constexpr double jump_tolerance = 1e-9;

}  // namespace

SceneAttachments::SceneAttachments(const host::ScenarioPlugin& scenario,
                                   const host::ScenarioInstance& instance, uint32_t particles,
                                   double dt, uint64_t steps)
    : table_(static_cast<const clothlab_attachments_extension*>(
          scenario.extension(CLOTHLAB_EXT_ATTACHMENTS))),
      instance_(instance.get()),
      scenario_id_(scenario.info().id) {
  if (table_ == nullptr) return;
  particles_.resize(table_->count(instance_));
  if (particles_.empty()) return;
  clothlab_message message{};
  check_call(table_->particles(instance_, particles_.data(), &message), message,
             "scenario " + scenario_id_ + ": attachments: particles");
  for (std::size_t k = 0; k < particles_.size(); ++k)
    if (particles_[k] >= particles)
      throw host::InputError("scenario " + scenario_id_ + ": attachment " + std::to_string(k) +
                             ": particle = " + std::to_string(particles_[k]) + ", allowed 0 .. " +
                             std::to_string(particles - 1) +
                             " (the cloth's rows x cols particles)");
  // Every target the run will ask for at a step start, so a scripted path that leaves the
  // finite or jumps stops the run before its first step.
  std::vector<double> x0, v0, x1, v1;
  read(0.0, x0, v0);
  for (uint64_t step = 1; step <= steps; ++step) {
    const double t = static_cast<double>(step) * dt;
    read(t, x1, v1);
    for (std::size_t k = 0; k < particles_.size(); ++k) {
      const double moved = std::hypot(x1[3 * k] - x0[3 * k], x1[3 * k + 1] - x0[3 * k + 1],
                                      x1[3 * k + 2] - x0[3 * k + 2]);
      const double allowed = 2.0 * dt * std::max(norm_at(v0, k), norm_at(v1, k)) + jump_tolerance;
      if (!(moved <= allowed))
        throw host::InputError(owner(k) + ": target jumps " + host::format_number(moved) +
                               " m between t = " + host::format_number(t - dt) + " and " +
                               host::format_number(t) + " s, allowed a continuous path (at most " +
                               host::format_number(allowed) +
                               " m: twice the step times its velocity there)");
    }
    std::swap(x0, x1);
    std::swap(v0, v1);
  }
}

void SceneAttachments::read(double t, std::vector<double>& positions,
                            std::vector<double>& velocities) const {
  positions.assign(3 * particles_.size(), 0.0);
  velocities.assign(3 * particles_.size(), 0.0);
  clothlab_message message{};
  check_call(table_->targets(instance_, t, positions.data(), velocities.data(), &message), message,
             "scenario " + scenario_id_ +
                 ": attachments: targets at t = " + host::format_number(t) + " s");
  static constexpr const char* axes[] = {"x", "y", "z"};
  for (std::size_t i = 0; i < positions.size(); ++i)
    for (const auto& [name, values] :
         {std::pair{"position", &positions}, std::pair{"velocity", &velocities}})
      if (!std::isfinite((*values)[i]))
        throw host::InputError(owner(i / 3) + ": target at t = " + host::format_number(t) +
                               " s: " + name + "." + axes[i % 3] + " = " +
                               host::format_number((*values)[i]) + ", allowed finite");
}

bool SceneAttachments::targets(double t, std::span<double> positions,
                               std::span<double> velocities) noexcept {
  clothlab_message message{};
  if (table_->targets(instance_, t, positions.data(), velocities.data(), &message) != CLOTHLAB_OK)
    return false;
  return std::all_of(positions.begin(), positions.end(),
                     [](double value) { return std::isfinite(value); }) &&
         std::all_of(velocities.begin(), velocities.end(),
                     [](double value) { return std::isfinite(value); });
}

std::string SceneAttachments::owner(std::size_t index) const {
  std::string text = "scenario " + scenario_id_ + ": attachment " + std::to_string(index);
  if (index < particles_.size()) text += " (particle " + std::to_string(particles_[index]) + ")";
  return text;
}

}  // namespace clothlab::cli
