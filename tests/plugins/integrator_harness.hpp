// Drives one integrator plugin through the C ABI against a MockSystem.
#pragma once

#include <clothlab/ext/solver_statistics.h>
#include <gtest/gtest.h>

#include <clothlab/host/plugin_library.hpp>
#include <memory>
#include <string>
#include <vector>

#include "mock_system.hpp"
#include "param_values.hpp"

namespace clothlab::test {

// Standard gravity (m/s²), under which the integrator tests' scenes fall.
inline constexpr double g = 9.81;

// The test name suffix of a test parameterised by integrator id: "/rk4", stable across builds.
template <class Id>
std::string integrator_id_name(const ::testing::TestParamInfo<Id>& info) {
  return std::string(info.param);
}

// Paths of the built plugins, passed in by CMake.
inline std::string integrator_path(const std::string& id) {
  if (id == "euler") return CLOTHLAB_TEST_EULER_PLUGIN;
  if (id == "midpoint") return CLOTHLAB_TEST_MIDPOINT_PLUGIN;
  if (id == "rk4") return CLOTHLAB_TEST_RK4_PLUGIN;
  if (id == "verlet") return CLOTHLAB_TEST_VERLET_PLUGIN;
  if (id == "implicit_euler") return CLOTHLAB_TEST_IMPLICIT_EULER_PLUGIN;
  if (id == "bdf2") return CLOTHLAB_TEST_BDF2_PLUGIN;
  if (id == "projective_dynamics") return CLOTHLAB_TEST_PROJECTIVE_DYNAMICS_PLUGIN;
  if (id == "xpbd") return CLOTHLAB_TEST_XPBD_PLUGIN;
  if (id == "vbd") return CLOTHLAB_TEST_VBD_PLUGIN;
  throw std::runtime_error("no integrator plugin " + id);
}

inline const std::vector<std::string>& all_integrators() {
  static const std::vector<std::string> ids{"euler", "midpoint", "rk4", "verlet"};
  return ids;
}

class Integrator {
 public:
  explicit Integrator(const std::string& id)
      : library_(host::PluginLibrary::load(integrator_path(id))) {
    values_ = default_values(descriptor().params, descriptor().param_count);
  }
  ~Integrator() {
    if (instance_ != nullptr) descriptor().destroy(instance_);
  }

  const clothlab_integrator& descriptor() const { return library_.integrator().descriptor(); }

  // Must come before create().
  Integrator& with(const std::string& name, double value) {
    set_value(values_, descriptor().params, name, {{value, 0, 0}});
    return *this;
  }

  clothlab_status create() {
    return descriptor().create(values_.data(), static_cast<uint32_t>(values_.size()), &instance_,
                               &message_);
  }

  template <class Real>
  clothlab_status prepare(MockSystem<Real>& system) {
    system.allocation_allowed = true;
    const clothlab_status status = descriptor().prepare(instance_, &system.raw(), &message_);
    system.allocation_allowed = false;
    return status;
  }

  template <class Real>
  clothlab_status step(MockSystem<Real>& system, double t, double dt) {
    return descriptor().step(instance_, &system.raw(), t, dt, &message_);
  }

  // create + prepare, failing the test on error.
  template <class Real>
  void start(MockSystem<Real>& system) {
    ASSERT_EQ(create(), CLOTHLAB_OK) << message();
    ASSERT_EQ(prepare(system), CLOTHLAB_OK) << message();
  }

  // n steps of dt from t = 0, failing the test on error.
  template <class Real>
  void run(MockSystem<Real>& system, int steps, double dt) {
    for (int n = 0; n < steps; ++n) ASSERT_EQ(step(system, n * dt, dt), CLOTHLAB_OK) << message();
  }

  std::string message() const { return message_.text; }
  void* instance() const { return instance_; }

 private:
  host::PluginLibrary library_;
  std::vector<clothlab_param_value> values_;
  void* instance_ = nullptr;
  clothlab_message message_{};
};

// The solver statistics of the integrator's last step; zeros if it offers none.
inline clothlab_solver_step_statistics solver_statistics_of(const Integrator& integrator) {
  const auto* extension = static_cast<const clothlab_solver_statistics_extension*>(
      integrator.descriptor().get_extension(CLOTHLAB_EXT_SOLVER_STATISTICS));
  clothlab_solver_step_statistics out{};
  out.struct_size = sizeof out;
  if (extension != nullptr) {
    EXPECT_EQ(extension->last_step(integrator.instance(), &out), CLOTHLAB_OK);
  }
  return out;
}

}  // namespace clothlab::test
