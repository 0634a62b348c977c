// A small, valid test plugin: one integrator (forward Euler on x only, enough to see it
// step) and one scenario, with a parameter of every type and one scenario extension.
#include <clothlab/sdk.hpp>
#include <string_view>

#include "test_point_echo.h"

namespace {

struct TestDrift {
  static constexpr const char* id = "test-drift";
  static constexpr const char* name = "Test drift";
  static constexpr const char* version = "0.1.0";
  static constexpr const char* description = "moves x by dt * v; for host tests";
  static constexpr uint32_t order = 1, evals_per_step = 0, flags = 0;
  static constexpr std::array params{
      clothlab::sdk::real_param("gain", 1.0, 0.0, 10.0, "1/s", "a real parameter"),
      clothlab::sdk::int_param("count", 3, 1, 5, "an integer parameter"),
      clothlab::sdk::bool_param("enabled", true, "a boolean parameter"),
      clothlab::sdk::vec3_param("offset", {1.0, 2.0, 3.0}, -5.0, 5.0, "m", "a vector parameter"),
  };
  explicit TestDrift(const clothlab::sdk::Params&) {}
  template <class Real>
  void prepare(clothlab::sdk::System<Real>&) {}
  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double, double dt) {
    system.axpy(system.x(), dt, system.v());
  }
};

struct TestPoint {
  static constexpr const char* id = "test-point";
  static constexpr const char* name = "Test point";
  static constexpr const char* version = "0.1.0";
  static constexpr const char* description = "a small free grid; for host tests";
  static constexpr std::array params{
      clothlab::sdk::int_param("rows", 2, 1, 8, "particle rows"),
  };
  explicit TestPoint(const clothlab::sdk::Params& values)
      : rows_(static_cast<uint32_t>(values.integer("rows"))) {}
  void describe(clothlab_scene& scene) const {
    scene.rows = rows_;
    scene.cols = 1;
    scene.width = 1.0;
    scene.height = 1.0;
    scene.col_axis[0] = 1.0;
    scene.row_axis[1] = -1.0;
    scene.total_mass = 1.0;
    scene.structural = {1.0, 0.0};
  }
  static const void* extension(std::string_view id) noexcept {
    static constexpr clothlab_test_point_echo echo{
        [](void* instance) { return static_cast<const TestPoint*>(instance)->rows_; }};
    return id == CLOTHLAB_TEST_POINT_ECHO ? &echo : nullptr;
  }

 private:
  uint32_t rows_;
};

}  // namespace

CLOTHLAB_PLUGIN_ENTRY("clothlab-test-good", "0.1.0", clothlab::sdk::integrators<TestDrift>,
                      clothlab::sdk::scenarios<TestPoint>)
