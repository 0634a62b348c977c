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
    : moving_(static_cast<const clothlab_colliders_extension_2*>(
          scenario.extension(CLOTHLAB_EXT_COLLIDERS_2))),
      posed_(moving_ != nullptr ? nullptr
                                : static_cast<const clothlab_colliders_extension*>(
                                      scenario.extension(CLOTHLAB_EXT_COLLIDERS))),
      instance_(instance.get()),
      scenario_id_(scenario.info().id),
      dt_(dt),
      end_(static_cast<double>(steps) * dt) {
  if (moving_ == nullptr && posed_ == nullptr) return;
  const uint32_t count = moving_ != nullptr ? moving_->count(instance_) : posed_->count(instance_);
  colliders_.reserve(count);
  for (uint32_t index = 0; index < count; ++index) {
    clothlab_collider raw{};
    raw.struct_size = sizeof raw;
    clothlab_message message{};
    check_call(moving_ != nullptr ? moving_->describe(instance_, index, &raw, &message)
                                  : posed_->describe(instance_, index, &raw, &message),
               message, owner(index) + ": describe");
    try {
      colliders_.push_back(collider_from_abi(raw));
    } catch (const std::invalid_argument& error) {
      throw host::InputError(owner(index) + ": " + error.what());
    }
  }
  // Every pose the run will ask for, so a scripted path that leaves the finite (or the unit
  // quaternions), jumps between two steps or reports a velocity its poses do not follow, stops
  // the run before its first step.
  std::vector<Pose> previous(count);
  std::vector<Motion> previous_motion(count);
  for (uint64_t step = 0; step <= steps; ++step) {
    const double t = static_cast<double>(step) * dt;
    for (uint32_t index = 0; index < count; ++index) {
      Motion given;
      const Pose now = pose(index, t, moving_ != nullptr ? &given : nullptr);
      if (step > 0) {
        try {
          check_pose_continuity(previous[index], now, dt);
        } catch (const std::invalid_argument& error) {
          throw host::InputError(owner(index) + ": pose from t = " + host::format_number(t - dt) +
                                 " s to " + host::format_number(t) + " s: " + error.what());
        }
        if (moving_ != nullptr) try {
            check_motion_agrees(previous_motion[index], motion_between(previous[index], now, dt));
          } catch (const std::invalid_argument& error) {
            throw host::InputError(owner(index) + ": at t = " + host::format_number(t - dt) +
                                   " s: " + error.what() + " up to t = " + host::format_number(t) +
                                   " s");
          }
      }
      previous[index] = now;
      previous_motion[index] = given;
    }
  }
}

std::span<const Collider> SceneColliders::at(double t) {
  for (uint32_t index = 0; index < colliders_.size(); ++index) {
    Collider& collider = colliders_[index];
    if (moving_ != nullptr) {
      collider.pose = pose(index, t, &collider.motion);
    } else {
      collider.pose = pose(index, t, nullptr);
      // Over the step from t; at the run's end, where there is none, the last step's.
      if (t + dt_ <= end_ * (1 + 1e-12))
        collider.motion = motion_between(collider.pose, pose(index, t + dt_, nullptr), dt_);
      else if (t >= dt_)
        collider.motion = motion_between(pose(index, t - dt_, nullptr), collider.pose, dt_);
      else
        collider.motion = {};
    }
  }
  return colliders_;
}

Pose SceneColliders::pose(uint32_t index, double t, Motion* motion) const {
  clothlab_collider_motion raw{};
  clothlab_message message{};
  if (moving_ != nullptr)
    check_call(moving_->motion(instance_, index, t, &raw, &message), message,
               owner(index) + ": motion");
  else
    check_call(posed_->pose(instance_, index, t, &raw.pose, &message), message,
               owner(index) + ": pose");
  try {
    if (motion != nullptr) *motion = motion_from_abi(raw);
    return pose_from_abi(raw.pose);
  } catch (const std::invalid_argument& error) {
    throw host::InputError(owner(index) + ": " + (moving_ != nullptr ? "motion" : "pose") +
                           " at t = " + host::format_number(t) + " s: " + error.what());
  }
}

std::string SceneColliders::owner(uint32_t index) const {
  std::string text = "scenario " + scenario_id_ + ": collider " + std::to_string(index);
  if (index < colliders_.size())
    text += " (" + std::string(to_string(colliders_[index].shape)) + ")";
  return text;
}

}  // namespace clothlab::cli
