#include "scene_attachments.hpp"

#include <algorithm>
#include <clothlab/core/attachment_path.hpp>
#include <clothlab/host/errors.hpp>
#include <clothlab/host/param_text.hpp>
#include <cmath>
#include <stdexcept>

namespace clothlab::cli {

namespace {

void check_call(clothlab_status status, const clothlab_message& message, const std::string& what) {
  if (status != CLOTHLAB_OK)
    throw host::PluginError(status, what + ": " + host::one_line(message.text));
}

}  // namespace

SceneAttachments::SceneAttachments(const host::ScenarioPlugin& scenario,
                                   const host::ScenarioInstance& instance, uint32_t particles,
                                   double dt, uint64_t steps, uint32_t samples_per_step)
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
  // Every target the run will ask for at a step start or substep, so a scripted path that leaves
  // the finite or jumps stops the run before its first step.
  const auto read = [&](double t, std::vector<double>& positions, std::vector<double>& velocities) {
    check_call(table_->targets(instance_, t, positions.data(), velocities.data(), &message),
               message,
               "scenario " + scenario_id_ +
                   ": attachments: targets at t = " + host::format_number(t) + " s");
  };
  try {
    check_attached_particles(particles_, particles);
    check_attachment_path(particles_, read, dt, steps, samples_per_step);
  } catch (const std::invalid_argument& error) {
    throw host::InputError("scenario " + scenario_id_ + ": " + error.what());
  }
}

void SceneAttachments::check_start(const Cloth& cloth) {
  std::vector<double> start, positions(3 * particles_.size()), velocities(3 * particles_.size());
  cloth.positions(start);
  clothlab_message message{};
  check_call(table_->targets(instance_, 0.0, positions.data(), velocities.data(), &message),
             message, "scenario " + scenario_id_ + ": attachments: targets at t = 0 s");
  try {
    check_attachment_start(particles_, positions, start, *cloth.model());
  } catch (const std::invalid_argument& error) {
    throw host::InputError("scenario " + scenario_id_ + ": " + error.what());
  }
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

}  // namespace clothlab::cli
