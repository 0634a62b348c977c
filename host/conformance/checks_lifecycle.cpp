// lifecycle.*: instances survive every order of calls a host may make, on every grid shape and
// on an irregular mesh.
#include <string>

#include "check.hpp"
#include "fixtures.hpp"

namespace clothlab::conformance {
namespace {

constexpr int repeat_rounds = 10;
constexpr int grid_steps = 20;
constexpr double step_size = 1e-3;

Values defaults_of(const clothlab_integrator& integrator) { return default_values(integrator); }

Verdict repeated_lifecycle(const clothlab_integrator& integrator, SheetShape shape) {
  State first;
  for (int round = 0; round < repeat_rounds; ++round) {
    const State state = simulate(integrator, sheet_scene(3, 3), preferred_precision(integrator), 1,
                                 grid_steps, step_size, shape);
    if (round == 0) first = state;
    require(state == first, "round " + std::to_string(round + 1) +
                                " of create/prepare/step/destroy differs from round 1");
  }
  return {true, std::to_string(repeat_rounds) + " rounds, identical results"};
}

Verdict zero_steps(const clothlab_integrator& integrator, SheetShape shape) {
  { IntegratorInstance unprepared(integrator, defaults_of(integrator)); }
  Cloth cloth = sheet_cloth(sheet_scene(3, 3), shape, preferred_precision(integrator),
                            pipeline_for(integrator));
  const State before = state_of(cloth);
  {
    IntegratorInstance instance(integrator, defaults_of(integrator));
    instance.prepare(cloth);
    instance.prepare(cloth);  // rebinding is allowed
  }
  require(state_of(cloth) == before, "create/prepare/destroy without a step changed the state");
  return {true, ""};
}

Verdict zero_dt(const clothlab_integrator& integrator, SheetShape shape) {
  Cloth cloth = sheet_cloth(sheet_scene(4, 5, true), shape, preferred_precision(integrator),
                            pipeline_for(integrator));
  IntegratorInstance instance(integrator, defaults_of(integrator));
  instance.prepare(cloth);
  instance.run(cloth, 5, step_size);  // moving, so a dt = 0 step has forces to ignore
  const State before = state_of(cloth);
  for (int i = 0; i < 3; ++i) instance.step(cloth, 5 * step_size, 0.0);
  require(state_of(cloth) == before, "a step with dt = 0 changed the state");
  return {true, ""};
}

Verdict grid_runs(const clothlab_integrator& integrator, uint32_t rows, uint32_t cols,
                  Precision precision) {
  Cloth cloth(sheet_scene(rows, cols, true), precision, pipeline_for(integrator));
  IntegratorInstance instance(integrator, defaults_of(integrator));
  instance.prepare(cloth);
  instance.run(cloth, grid_steps, step_size);
  return {true, std::to_string(grid_steps) + " steps, finite"};
}

// The header allows rebinding: an instance prepared on one system, then on another, steps the
// second exactly as a fresh instance would.
Verdict prepare_twice(const clothlab_integrator& integrator, SheetShape shape) {
  const Precision precision = preferred_precision(integrator);
  const Scene scene = sheet_scene(4, 5, true);
  const State fresh = simulate(integrator, scene, precision, 1, grid_steps, step_size, shape);
  Cloth first = sheet_cloth(sheet_scene(3, 3), shape, precision, pipeline_for(integrator));
  Cloth second = sheet_cloth(scene, shape, precision, pipeline_for(integrator));
  IntegratorInstance instance(integrator, defaults_of(integrator));
  instance.prepare(first);
  instance.run(first, 3, step_size);
  instance.prepare(second);
  instance.run(second, grid_steps, step_size);
  require(state_of(second) == fresh,
          "after a second prepare the instance steps differently from a fresh one");
  return {true, "a rebound instance matches a fresh one bit for bit"};
}

// evals_per_step is what hosts budget by (work-precision plots count it): it must be exact.
Verdict declared_evaluations(const clothlab_integrator& integrator, SheetShape shape) {
  Cloth cloth = sheet_cloth(sheet_scene(4, 5, true), shape, preferred_precision(integrator),
                            pipeline_for(integrator));
  IntegratorInstance instance(integrator, defaults_of(integrator));
  instance.prepare(cloth);
  cloth.reset_counters();
  constexpr int steps = 10;
  instance.run(cloth, steps, step_size);
  const uint64_t made = cloth.counters().force_evals;
  require(made == uint64_t{steps} * integrator.evals_per_step,
          std::to_string(made) + " force evaluations in " + std::to_string(steps) +
              " steps; declared evals_per_step " + std::to_string(integrator.evals_per_step));
  return {true, std::to_string(made) + " evaluations in " + std::to_string(steps) + " steps"};
}

bool supports(const clothlab_integrator& integrator, uint32_t precision) {
  return (integrator.precisions & (1u << precision)) != 0;
}

}  // namespace

std::vector<Check> lifecycle_checks(const clothlab_integrator& integrator) {
  const clothlab_integrator* c = &integrator;
  std::vector<Check> checks = {
      {c->id, "lifecycle.repeat", [c] { return on_every_shape(*c, repeated_lifecycle); }},
      {c->id, "lifecycle.zero-steps", [c] { return on_every_shape(*c, zero_steps); }},
      {c->id, "lifecycle.dt-zero", [c] { return on_every_shape(*c, zero_dt); }},
      {c->id, "lifecycle.prepare-twice", [c] { return on_every_shape(*c, prepare_twice); }},
      {c->id, "lifecycle.evals-per-step", [c] { return on_every_shape(*c, declared_evaluations); }},
  };
  const std::pair<uint32_t, uint32_t> grids[] = {{1, 1}, {2, 1}, {1, 7}, {3, 3}, {64, 48}};
  for (auto [rows, cols] : grids) {
    const std::string shape = std::to_string(rows) + "x" + std::to_string(cols);
    if (supports(integrator, CLOTHLAB_FLOAT64))
      checks.push_back({c->id, "lifecycle.grid-" + shape + "-f64",
                        [c, rows, cols] { return grid_runs(*c, rows, cols, Precision::Float64); }});
    if (supports(integrator, CLOTHLAB_FLOAT32))
      checks.push_back({c->id, "lifecycle.grid-" + shape + "-f32",
                        [c, rows, cols] { return grid_runs(*c, rows, cols, Precision::Float32); }});
  }
  return checks;
}

}  // namespace clothlab::conformance
