#include "scene_colliders.hpp"

#include <clothlab/host/errors.hpp>
#include <clothlab/host/param_text.hpp>
#include <stdexcept>

namespace clothlab::cli {

namespace {

void check_call(clothlab_status status, const clothlab_message& message, const std::string& what) {
  if (status != CLOTHLAB_OK)
    throw host::PluginError(status, what + ": " + host::one_line(message.text));
}

}  // namespace

SceneColliders::SceneColliders(const host::ScenarioPlugin& scenario,
                               const host::ScenarioInstance& instance, double dt, uint64_t steps)
    : table_(static_cast<const clothlab_colliders_extension*>(
          scenario.extension(CLOTHLAB_EXT_COLLIDERS))),
      instance_(instance.get()),
      scenario_id_(scenario.info().id) {
  if (table_ == nullptr) return;
  const uint32_t count = table_->count(instance_);
  colliders_.reserve(count);
  for (uint32_t index = 0; index < count; ++index) {
    clothlab_collider raw{};
    raw.struct_size = sizeof raw;
    clothlab_message message{};
    check_call(table_->describe(instance_, index, &raw, &message), message,
               owner(index) + ": describe");
    try {
      colliders_.push_back(collider_from_abi(raw));
    } catch (const std::invalid_argument& error) {
      throw host::InputError(owner(index) + ": " + error.what());
    }
  }
  // Every pose the run will ask for, so a scripted path that leaves the finite (or the unit
  // quaternions), or jumps between two steps, stops the run before its first step.
  std::vector<Pose> previous(count);
  for (uint64_t step = 0; step <= steps; ++step) {
    const double t = static_cast<double>(step) * dt;
    for (uint32_t index = 0; index < count; ++index) {
      const Pose now = pose(index, t);
      if (step > 0) {
        try {
          check_pose_continuity(previous[index], now, dt);
        } catch (const std::invalid_argument& error) {
          throw host::InputError(owner(index) + ": pose from t = " + host::format_number(t - dt) +
                                 " s to " + host::format_number(t) + " s: " + error.what());
        }
      }
      previous[index] = now;
    }
  }
}

std::span<const Collider> SceneColliders::at(double t) {
  for (uint32_t index = 0; index < colliders_.size(); ++index)
    colliders_[index].pose = pose(index, t);
  return colliders_;
}

Pose SceneColliders::pose(uint32_t index, double t) const {
  clothlab_pose raw{};
  clothlab_message message{};
  check_call(table_->pose(instance_, index, t, &raw, &message), message, owner(index) + ": pose");
  try {
    return pose_from_abi(raw);
  } catch (const std::invalid_argument& error) {
    throw host::InputError(owner(index) + ": pose at t = " + host::format_number(t) +
                           " s: " + error.what());
  }
}

std::string SceneColliders::owner(uint32_t index) const {
  std::string text = "scenario " + scenario_id_ + ": collider " + std::to_string(index);
  if (index < colliders_.size())
    text += " (" + std::string(to_string(colliders_[index].shape)) + ")";
  return text;
}

}  // namespace clothlab::cli
