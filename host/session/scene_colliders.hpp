// The colliders a scenario offers (clothlab.colliders/1), read and checked before the run, and
// their poses step by step.
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
  // run: a malformed shape, friction or thickness, a non-finite or non-unit pose, or a pose that
  // jumps between two steps (check_pose_continuity), is an InputError naming the scenario, the
  // collider, the field, its value and what is allowed;
  // a failing call is the plugin's PluginError. `instance` must outlive this object.
  SceneColliders(const host::ScenarioPlugin& scenario, const host::ScenarioInstance& instance,
                 double dt, uint64_t steps);

  bool empty() const { return colliders_.empty(); }
  std::size_t size() const { return colliders_.size(); }
  // The colliders at their poses at time t; valid until the next call.
  std::span<const Collider> at(double t);

 private:
  Pose pose(uint32_t index, double t) const;
  std::string owner(uint32_t index) const;

  const clothlab_colliders_extension* table_ = nullptr;
  void* instance_ = nullptr;
  std::string scenario_id_;
  std::vector<Collider> colliders_;
};

}  // namespace clothlab::cli
