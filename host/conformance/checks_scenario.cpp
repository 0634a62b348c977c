// scenario.*: the scene a scenario describes (its cloth, its colliders, its air) is simulable,
// repeatable and follows its parameters.
#include <clothlab/ext/attachments.h>
#include <clothlab/ext/colliders.h>
#include <clothlab/ext/mesh.h>

#include <clothlab/core/attachment_path.hpp>
#include <clothlab/host/param_text.hpp>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "check.hpp"
#include "fixtures.hpp"
#include "scene_validation.hpp"

namespace clothlab::conformance {
namespace {

// Field-by-field equality (the struct may have padding), pins compared by value.
bool same_scene(const clothlab_scene& a, const clothlab_scene& b) {
  auto same3 = [](const double(&p)[3], const double(&q)[3]) {
    return std::memcmp(p, q, sizeof p) == 0;
  };
  auto same_family = [](const clothlab_spring_family& p, const clothlab_spring_family& q) {
    return p.ks == q.ks && p.kd == q.kd;
  };
  if (a.rows != b.rows || a.cols != b.cols || a.pinned_count != b.pinned_count) return false;
  for (uint32_t i = 0; i < a.pinned_count; ++i)
    if (a.pinned[i] != b.pinned[i]) return false;
  return a.width == b.width && a.height == b.height && same3(a.origin, b.origin) &&
         same3(a.col_axis, b.col_axis) && same3(a.row_axis, b.row_axis) &&
         a.total_mass == b.total_mass && same_family(a.structural, b.structural) &&
         same_family(a.shear, b.shear) && same_family(a.flexion, b.flexion) &&
         same3(a.gravity, b.gravity) && same3(a.wind_direction, b.wind_direction) &&
         a.wind_strength == b.wind_strength;
}

Values defaults_of(const clothlab_scenario& scenario) { return default_values(scenario); }

Verdict scene_valid(const clothlab_scenario& scenario) {
  const ScenarioInstance instance(scenario, defaults_of(scenario));
  const clothlab_scene scene = instance.describe();
  require_valid_scene(scene);
  const Cloth cloth(scene_from_abi(scene), Precision::Float64, PipelineOptions{true, 1});
  require(cloth.state_is_finite(), "the initial state is not finite");
  return {true, std::to_string(scene.rows) + "x" + std::to_string(scene.cols) + ", " +
                    std::to_string(scene.pinned_count) + " pins"};
}

Verdict describe_repeatable(const clothlab_scenario& scenario) {
  const ScenarioInstance first(scenario, defaults_of(scenario));
  const clothlab_scene a = first.describe();
  const clothlab_scene b = first.describe();
  require(same_scene(a, b), "two describe calls on one instance differ");
  const ScenarioInstance second(scenario, defaults_of(scenario));
  require(same_scene(a, second.describe()) &&
              first.colliders_at_start() == second.colliders_at_start() &&
              first.air() == second.air(),
          "two instances with equal parameters differ");
  return {true, ""};
}

// A value inside the range that differs from the default (none when the range is a point).
bool other_value(const clothlab_param_spec& spec, double current, double& out) {
  const bool integral = spec.type == CLOTHLAB_PARAM_INT || spec.type == CLOTHLAB_PARAM_BOOL;
  const double step = integral ? 1.0 : 0.25 * (spec.max_value - spec.min_value);
  if (step <= 0) return false;
  out = current + step <= spec.max_value ? current + step : current - step;
  return out >= spec.min_value && out != current;
}

// The fields a well-known parameter must set; empty for other names.
std::string expected_effect(const clothlab_param_spec& spec, const clothlab_scene& scene,
                            double value) {
  const std::string name = spec.name;
  auto mismatch = [&](const char* field, double actual) {
    return actual == value ? std::string()
                           : std::string(field) + " is " + std::to_string(actual) + ", not " +
                                 std::to_string(value);
  };
  if (name == "rows") return mismatch("scene.rows", scene.rows);
  if (name == "cols" || name == "columns") return mismatch("scene.cols", scene.cols);
  if (name == "mass" || name == "total_mass") return mismatch("scene.total_mass", scene.total_mass);
  if (name == "width") return mismatch("scene.width", scene.width);
  if (name == "height") return mismatch("scene.height", scene.height);
  return {};
}

Verdict parameters_respected(const clothlab_scenario& scenario) {
  const Values defaults = defaults_of(scenario);
  const ScenarioInstance base_instance(scenario, defaults);
  const clothlab_scene base = base_instance.describe();
  const std::vector<double> base_colliders = base_instance.colliders_at_start();
  const std::vector<double> base_air = base_instance.air();
  const std::vector<double> base_motion = base_instance.motion();
  int changed = 0;
  for (uint32_t i = 0; i < scenario.param_count; ++i) {
    const clothlab_param_spec& spec = scenario.params[i];
    Values values = defaults;
    if (!other_value(spec, values[i].v[0], values[i].v[0])) continue;
    const ScenarioInstance instance(scenario, values);
    const clothlab_scene scene = instance.describe();
    const std::string what = std::string(spec.name) + " = " + std::to_string(values[i].v[0]);
    require(!same_scene(scene, base) || instance.colliders_at_start() != base_colliders ||
                instance.air() != base_air || instance.motion() != base_motion,
            "setting " + what +
                " changes neither the scene, nor its colliders, nor its air, nor what moves");
    const std::string wrong = expected_effect(spec, scene, values[i].v[0]);
    require(wrong.empty(), "with " + what + ", " + wrong);
    require_valid_scene(scene);
    ++changed;
  }
  return {true, std::to_string(changed) + " parameters change the scene as declared"};
}

// Every collider and its path over two seconds at 60 Hz pass the core's one collider validation,
// as the host checks them before a run: shapes (collider_from_abi), finite unit poses
// (pose_from_abi), no jump between two frames (check_pose_continuity) and, where the scenario
// gives velocities (clothlab.colliders/2), finite ones (motion_from_abi) that its poses follow
// (check_motion_agrees).
Verdict colliders_valid(const clothlab_scenario& scenario) {
  const auto* table = static_cast<const clothlab_colliders_extension*>(
      clothlab_scenario_extension(&scenario, CLOTHLAB_EXT_COLLIDERS));
  if (table == nullptr) return {true, "no colliders"};
  const auto* moving = static_cast<const clothlab_colliders_extension_2*>(
      clothlab_scenario_extension(&scenario, CLOTHLAB_EXT_COLLIDERS_2));
  const ScenarioInstance instance(scenario, defaults_of(scenario));
  constexpr double dt = 1.0 / 60.0;
  constexpr int frames = 120;
  const uint32_t count = table->count(instance.handle());
  for (uint32_t i = 0; i < count; ++i) {
    const std::string which = "collider " + std::to_string(i) + ": ";
    clothlab_collider raw{};
    raw.struct_size = sizeof raw;
    clothlab_message message{};
    clothlab_status status = table->describe(instance.handle(), i, &raw, &message);
    require(status == CLOTHLAB_OK, which + "describe failed: " + describe_status(status, message));
    try {
      (void)collider_from_abi(raw);
    } catch (const std::invalid_argument& error) {
      throw CheckFailure(which + error.what());
    }
    Pose previous;
    Motion previous_motion;
    for (int frame = 0; frame <= frames; ++frame) {
      const double t = frame * dt;
      clothlab_pose raw_pose{};
      status = table->pose(instance.handle(), i, t, &raw_pose, &message);
      require(status == CLOTHLAB_OK, which + "pose at t = " + host::format_number(t) +
                                         " s failed: " + describe_status(status, message));
      clothlab_collider_motion raw_motion{};
      if (moving != nullptr) {
        status = moving->motion(instance.handle(), i, t, &raw_motion, &message);
        require(status == CLOTHLAB_OK, which + "motion at t = " + host::format_number(t) +
                                           " s failed: " + describe_status(status, message));
      }
      Pose now;
      try {
        now = pose_from_abi(raw_pose);
        if (frame > 0) check_pose_continuity(previous, now, dt);
      } catch (const std::invalid_argument& error) {
        throw CheckFailure(which + "pose at t = " + host::format_number(t) + " s: " + error.what());
      }
      if (moving != nullptr) try {
          const Motion given = motion_from_abi(raw_motion);
          if (frame > 0) check_motion_agrees(previous_motion, motion_between(previous, now, dt));
          previous_motion = given;
        } catch (const std::invalid_argument& error) {
          throw CheckFailure(which + "motion at t = " + host::format_number(t) +
                             " s: " + error.what());
        }
      previous = now;
    }
  }
  return {true, std::to_string(count) + " colliders, valid shapes, continuous poses" +
                    (moving != nullptr ? " and velocities they follow" : "") + " over 2 s"};
}

// The cloth's particle count: the mesh's vertices when the scenario offers one.
uint32_t particle_count(const clothlab_scenario& scenario, const ScenarioInstance& instance) {
  const auto* mesh = static_cast<const clothlab_mesh_extension*>(
      clothlab_scenario_extension(&scenario, CLOTHLAB_EXT_MESH));
  if (mesh == nullptr) {
    const clothlab_scene scene = instance.describe();
    return scene.rows * scene.cols;
  }
  clothlab_mesh out{};
  out.struct_size = sizeof out;
  clothlab_message message{};
  const clothlab_status status = mesh->describe(instance.handle(), &out, &message);
  require(status == CLOTHLAB_OK, "mesh describe failed: " + describe_status(status, message));
  return out.vertex_count;
}

// The attached particles and their targets over two seconds pass the core's one attachment
// validation, as the host checks them before a run, and at substep times too: eight samples per
// step of 1 ms, so a target that jumps inside a step and is back by the next is caught.
Verdict attachments_valid(const clothlab_scenario& scenario) {
  const auto* table = static_cast<const clothlab_attachments_extension*>(
      clothlab_scenario_extension(&scenario, CLOTHLAB_EXT_ATTACHMENTS));
  if (table == nullptr) return {true, "no attachments"};
  constexpr double dt = 1e-3;
  constexpr uint64_t steps = 2000;
  constexpr uint32_t samples_per_step = 8;
  const ScenarioInstance instance(scenario, defaults_of(scenario));
  std::vector<uint32_t> particles(table->count(instance.handle()));
  clothlab_message message{};
  if (!particles.empty()) {
    const clothlab_status status = table->particles(instance.handle(), particles.data(), &message);
    require(status == CLOTHLAB_OK,
            "attachments: particles failed: " + describe_status(status, message));
  }
  const auto read = [&](double t, std::vector<double>& positions, std::vector<double>& velocities) {
    const clothlab_status status =
        table->targets(instance.handle(), t, positions.data(), velocities.data(), &message);
    require(status == CLOTHLAB_OK, "attachments: targets at t = " + host::format_number(t) +
                                       " s failed: " + describe_status(status, message));
  };
  try {
    check_attached_particles(particles, particle_count(scenario, instance));
    check_attachment_path(particles, read, dt, steps, samples_per_step);
  } catch (const std::invalid_argument& error) {
    throw CheckFailure(error.what());
  }
  return {true, std::to_string(particles.size()) +
                    " attached particles, in range, their targets finite and continuous over 2 s "
                    "at 8 samples per 1 ms step"};
}

}  // namespace

std::vector<Check> scenario_checks(const clothlab_scenario& scenario) {
  const clothlab_scenario* c = &scenario;
  return {
      {c->id, "scenario.valid", [c] { return scene_valid(*c); }},
      {c->id, "scenario.deterministic", [c] { return describe_repeatable(*c); }},
      {c->id, "scenario.params", [c] { return parameters_respected(*c); }},
      {c->id, "scenario.colliders", [c] { return colliders_valid(*c); }},
      {c->id, "scenario.attachments", [c] { return attachments_valid(*c); }},
  };
}

}  // namespace clothlab::conformance
