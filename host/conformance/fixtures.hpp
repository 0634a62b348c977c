// Building blocks the checks share: parameter values from schemas, owned plugin
// instances that report errors as check failures, and the small scenes the checks run.
#pragma once

#include <clothlab/ext/integrator_traits.h>
#include <clothlab/plugin.h>

#include <clothlab/core/cloth.hpp>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "verdict.hpp"

namespace clothlab::conformance {

// A value that replaces a parameter's default for one component (--param ID.NAME=VALUE).
struct ParameterOverride {
  std::string component;
  std::string name;
  clothlab_param_value value;
};

// Installed once by main before any check runs; every check then starts from these values.
void set_parameter_overrides(std::vector<ParameterOverride> overrides);
const std::vector<ParameterOverride>& parameter_overrides();

// A text that replaces a text parameter's default for one component (--text ID.NAME=TEXT), for
// a plugin that offers clothlab.text-parameters/1.
struct TextOverride {
  std::string component;
  std::string name;
  std::string text;
};
void set_text_overrides(std::vector<TextOverride> overrides);

// The scenario's create with `values`, through its clothlab.text-parameters/1 table when it
// offers one (each text its default or its --text override).
clothlab_status create_scenario(const clothlab_scenario& scenario,
                                const std::vector<clothlab_param_value>& values, void** instance,
                                clothlab_message& message);

// Defaults from the schema, with the overrides for `component` applied.
std::vector<clothlab_param_value> default_values(const std::string& component,
                                                 const clothlab_param_spec* specs, uint32_t count);
std::vector<clothlab_param_value> default_values(const clothlab_integrator& integrator);
std::vector<clothlab_param_value> default_values(const clothlab_scenario& scenario);

// "<status name>: <message>" for a non-OK status, for failure reasons.
std::string describe_status(clothlab_status status, const clothlab_message& message);

// An integrator instance created from `values`; destroyed with the object.
class IntegratorInstance {
 public:
  IntegratorInstance(const clothlab_integrator& integrator,
                     const std::vector<clothlab_param_value>& values);
  ~IntegratorInstance();
  IntegratorInstance(const IntegratorInstance&) = delete;
  IntegratorInstance& operator=(const IntegratorInstance&) = delete;

  void prepare(const Cloth& cloth);
  // Fails the check when step returns an error or leaves a non-finite state.
  void step(const Cloth& cloth, double t, double dt);
  void run(const Cloth& cloth, int steps, double dt);
  void* handle() const { return instance_; }

 private:
  const clothlab_integrator& integrator_;
  void* instance_ = nullptr;
};

// A scenario instance created from `values`; destroyed with the object.
class ScenarioInstance {
 public:
  ScenarioInstance(const clothlab_scenario& scenario,
                   const std::vector<clothlab_param_value>& values);
  ~ScenarioInstance();
  ScenarioInstance(const ScenarioInstance&) = delete;
  ScenarioInstance& operator=(const ScenarioInstance&) = delete;

  // Fails the check when describe returns an error.
  clothlab_scene describe() const;
  // The colliders (clothlab.colliders/1) and their poses at t = 0, as raw fields: empty when
  // the scenario offers none. Fails the check when a call returns an error.
  std::vector<double> colliders_at_start() const;
  // Its air's fields (clothlab.air/1), empty without the extension.
  std::vector<double> air() const;
  // The plugin's instance, the first argument of its extensions' functions.
  void* handle() const { return instance_; }
  // What moves over the first 20 s, sampled every 1 ms to 2 s, then every 0.1 s: the attached
  // particles (clothlab.attachments/1) and their targets, and the colliders' poses; empty when
  // nothing does.
  std::vector<double> motion() const;

 private:
  const clothlab_scenario& scenario_;
  void* instance_ = nullptr;
};

// Like the built-in sheet: top corners pinned (none for a single row), gravity, damped
// springs of every family, light wind when `windy`.
Scene sheet_scene(uint32_t rows, uint32_t cols, bool windy = false);

// What a sheet check runs on: the grid, or the same particles jittered into an irregular
// triangle mesh (irregular_grid_mesh) with the scene's pins, mass, springs' ks and kd and loads,
// so the engine's spring-list path and an integrator's general path are exercised too.
enum class SheetShape { Grid, IrregularMesh };
// A cloth of `scene` (a grid of at least 2 x 2 for the mesh) in `shape`.
Cloth sheet_cloth(const Scene& scene, SheetShape shape, Precision precision,
                  PipelineOptions options);

// Runs a sheet check's `body` on the grid, then on the irregular mesh; the verdict is both
// (a failure on the mesh says so). An integrator that refuses the mesh with
// CLOTHLAB_ERROR_UNSUPPORTED in its first prepare or step (it needs a grid-only extension)
// runs on the grid alone, and the verdict's reason says why.
Verdict on_every_shape(const clothlab_integrator& integrator,
                       const std::function<Verdict(SheetShape)>& body);
// The same for a check written as check(integrator, shape, args...).
template <class... Args>
Verdict on_every_shape(const clothlab_integrator& integrator,
                       Verdict (*check)(const clothlab_integrator&, SheetShape, Args...),
                       Args... args) {
  return on_every_shape(integrator,
                        [&](SheetShape shape) { return check(integrator, shape, args...); });
}

PipelineOptions pipeline_for(const clothlab_integrator& integrator, int threads = 1);

bool uses_velocity_forces(const clothlab_integrator& integrator);

// The integrator's "clothlab.integrator-traits/1" extension, or nullptr when it offers none
// (no get_extension, a 1.0/1.1-sized descriptor, or NULL for that id).
const clothlab_integrator_traits* integrator_traits(const clothlab_integrator& integrator);
bool has_trait(const clothlab_integrator& integrator, uint32_t trait);

// Float64 when the integrator offers it, else its other precision.
Precision preferred_precision(const clothlab_integrator& integrator);

struct State {
  std::vector<double> x, v;
  bool operator==(const State&) const = default;
};
State state_of(const Cloth& cloth);

// Runs `steps` steps of a fresh instance (default parameters) on a fresh Cloth of `scene`.
State simulate(const clothlab_integrator& integrator, const Scene& scene, Precision precision,
               int threads, int steps, double dt, SheetShape shape = SheetShape::Grid);

}  // namespace clothlab::conformance
