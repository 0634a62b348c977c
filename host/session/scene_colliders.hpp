// The colliders a scenario offers (clothlab.colliders/2, or /1), read and checked before the
// run, and their poses and velocities step by step.
#pragma once

#include <clothlab/ext/colliders.h>

#include <clothlab/core/collider.hpp>
#include <clothlab/host/components.hpp>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace clothlab::cli {

class SceneColliders {
 public:
  // None: a scenario without the extension.
  SceneColliders() = default;
  // Reads every collider and its pose at each step start t = k dt, k = 0 .. steps, before the
  // run: a malformed shape, friction or thickness, a non-finite or non-unit pose, a pose that
  // jumps between two steps (check_pose_continuity), or (/2) a velocity that is not finite or
  // that the poses do not follow (check_motion_agrees), is an InputError naming the scenario,
  // the collider, the time, the field, its value and what is allowed;
  // a failing call is the plugin's PluginError. `instance` must outlive this object.
  SceneColliders(const host::ScenarioPlugin& scenario, const host::ScenarioInstance& instance,
                 double dt, uint64_t steps);

  bool empty() const { return colliders_.empty(); }
  std::size_t size() const { return colliders_.size(); }
  // The colliders at their poses at time t, each with its motion over the step from t: the
  // scenario's velocity (/2), or the one that takes its pose at t to its pose at t + dt (/1; at
  // the run's end, the one from t - dt to t); valid until the next call.
  std::span<const Collider> at(double t);

 private:
  // Collider `index`'s pose at t, and its velocity there into *motion when asked (/2 only).
  Pose pose(uint32_t index, double t, Motion* motion) const;
  std::string owner(uint32_t index) const;

  const clothlab_colliders_extension_2* moving_ = nullptr;
  const clothlab_colliders_extension* posed_ = nullptr;
  void* instance_ = nullptr;
  std::string scenario_id_;
  double dt_ = 0;
  double end_ = 0;  // the run's duration: no pose is asked for later
  std::vector<Collider> colliders_;
};

}  // namespace clothlab::cli
