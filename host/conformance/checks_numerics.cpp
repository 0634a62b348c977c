// numerics.*: integrators converge at their declared order on problems with known
// solutions, respect pins, keep rest at rest and are bit-for-bit deterministic.
#include <algorithm>
#include <clothlab/analysis/order_fit.hpp>
#include <clothlab/core/cloth_model.hpp>
#include <cmath>
#include <cstdio>
#include <string>

#include "analytic.hpp"
#include "check.hpp"
#include "fixtures.hpp"

namespace clothlab::conformance {
namespace {

constexpr double order_tolerance = 0.2;
constexpr double roundoff_error = 1e-10;  // errors below this count as exact
// A drag rate, 1/s. Round-off makes 1e-14; the built-ins that solve iteratively leave the
// residual of their solve, whose sum over the particles is momentum no force gave: 3e-5 for
// implicit_euler and bdf2 at CG's default tolerance (1e-5), 1e-11 for projective_dynamics. An
// undeclared drag worth noticing is 1 1/s and more (verlet's damping is typically 1 to 100).
constexpr double momentum_drag_tolerance = 1e-3;

// Single spring hanging from a pin: particle 1 of a 2x1 grid, unit mass, unit rest length.
constexpr double spring_k = 10.0;
constexpr double spring_mass = 1.0;
constexpr double spring_u0 = 0.1;  // initial extension
constexpr double spring_horizon = 2.0;

// Coarsest step count per declared order: errors well above round-off, in the asymptotic range.
int coarsest_steps(uint32_t order) { return order <= 1 ? 400 : order == 2 ? 50 : 20; }

std::string format(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

Scene single_spring_scene(double damping) {
  Scene scene;
  scene.rows = 2;
  scene.cols = 1;
  scene.height = 1.0;
  scene.total_mass = 2.0 * spring_mass;
  scene.structural = {spring_k, damping};
  scene.gravity = {0, 0, 0};
  scene.pinned = {0};
  return scene;
}

// Parameters for the order checks: the defaults, except that an iterative method
// (CLOTHLAB_TRAIT_ITERATIVE) runs with its iteration count at the schema's maximum, so the
// measured order is the time discretisation's and not a truncated solver's.
std::vector<clothlab_param_value> order_values(const clothlab_integrator& integrator) {
  std::vector<clothlab_param_value> values = default_values(integrator);
  const clothlab_integrator_traits* traits = integrator_traits(integrator);
  if (traits == nullptr || (traits->flags & CLOTHLAB_TRAIT_ITERATIVE) == 0 ||
      traits->iterations_param == nullptr)
    return values;
  for (uint32_t i = 0; i < integrator.param_count; ++i)
    if (std::string(integrator.params[i].name) == traits->iterations_param)
      values[i].v[0] = integrator.params[i].max_value;
  return values;
}

// Error of one run, position plus velocity scaled by the natural frequency.
double spring_error(const clothlab_integrator& integrator, double damping, int steps) {
  Cloth cloth(single_spring_scene(damping), Precision::Float64, pipeline_for(integrator));
  State state = state_of(cloth);
  state.x[4] = -(1.0 + spring_u0);  // particle 1, y: rest length below the pin, stretched
  cloth.set_state(state.x, state.v);
  IntegratorInstance instance(integrator, order_values(integrator));
  instance.prepare(cloth);
  instance.run(cloth, steps, spring_horizon / steps);
  const State end = state_of(cloth);
  const Oscillation exact =
      damped_oscillator(spring_k, damping, spring_mass, spring_u0, 0.0, spring_horizon);
  const double omega = std::sqrt(spring_k / spring_mass);
  const double sideways =
      std::abs(end.x[3]) + std::abs(end.x[5]) + std::abs(end.v[3]) + std::abs(end.v[5]);
  return std::abs(-end.x[4] - 1.0 - exact.position) + std::abs(-end.v[4] - exact.velocity) / omega +
         sideways;
}

double free_fall_error(const clothlab_integrator& integrator, int steps) {
  Scene scene;  // 1x1: one free particle under gravity
  scene.gravity = {0.0, -9.81, 0.0};
  Cloth cloth(scene, Precision::Float64, pipeline_for(integrator));
  const std::array<double, 3> x0{0.5, 1.0, -0.25}, v0{1.0, 2.0, -0.5};
  cloth.set_state({x0[0], x0[1], x0[2]}, {v0[0], v0[1], v0[2]});
  IntegratorInstance instance(integrator, order_values(integrator));
  instance.prepare(cloth);
  constexpr double horizon = 1.0;
  instance.run(cloth, steps, horizon / steps);
  const State end = state_of(cloth);
  const Motion exact = free_fall(x0, v0, scene.gravity, horizon);
  double error = 0;
  for (int k = 0; k < 3; ++k)
    error +=
        std::abs(end.x[k] - exact.position[k]) + horizon * std::abs(end.v[k] - exact.velocity[k]);
  return error;
}

template <class ErrorAt>
Verdict converges_at_declared_order(const clothlab_integrator& integrator, ErrorAt error_at) {
  std::vector<double> step_sizes, step_errors;
  std::string errors;
  double largest = 0;
  for (int steps = coarsest_steps(integrator.order), i = 0; i < 4; ++i, steps *= 2) {
    const double error = error_at(steps);
    step_sizes.push_back(1.0 / steps);
    step_errors.push_back(error);
    largest = std::max(largest, error);
    errors += (i ? ", " : "") + format("%.3g", error);
  }
  if (largest < roundoff_error) return {true, "exact to round-off (errors " + errors + ")"};
  // The one order fit (analysis), over every point: four halvings are all asymptotic here.
  const analysis::OrderFit fit = analysis::fit_order_all(step_sizes, step_errors);
  require(fit.valid, "no order fit (" + fit.note + "; errors " + errors + ")");
  const double measured = fit.slope;
  const std::string detail = "measured order " + format("%.2f", measured) + ", declared " +
                             std::to_string(integrator.order) + " (errors " + errors + ")";
  require(std::abs(measured - integrator.order) <= order_tolerance, detail);
  return {true, detail};
}

Verdict pins_untouched(const clothlab_integrator& integrator, SheetShape shape,
                       Precision precision) {
  Cloth cloth = sheet_cloth(sheet_scene(6, 5, true), shape, precision, pipeline_for(integrator));
  const State before = state_of(cloth);
  IntegratorInstance instance(integrator, default_values(integrator));
  instance.prepare(cloth);
  instance.run(cloth, 30, 1e-3);
  const State after = state_of(cloth);
  for (uint32_t pin : cloth.scene().pinned)
    for (int k = 0; k < 3; ++k)
      require(after.x[3 * pin + k] == before.x[3 * pin + k] &&
                  after.v[3 * pin + k] == before.v[3 * pin + k],
              "pinned particle " + std::to_string(pin) + " moved");
  return {true, std::to_string(cloth.scene().pinned.size()) + " pins bit-for-bit unchanged"};
}

Verdict rest_stays_at_rest(const clothlab_integrator& integrator, SheetShape shape) {
  Scene scene = sheet_scene(3, 4);
  scene.pinned.clear();
  scene.gravity = {0, 0, 0};
  Cloth cloth = sheet_cloth(scene, shape, Precision::Float64, pipeline_for(integrator));
  const State before = state_of(cloth);
  IntegratorInstance instance(integrator, default_values(integrator));
  instance.prepare(cloth);
  instance.run(cloth, 50, 1e-3);
  const State after = state_of(cloth);
  double drift = 0, speed = 0;
  for (size_t i = 0; i < after.x.size(); ++i) {
    drift = std::max(drift, std::abs(after.x[i] - before.x[i]));
    speed = std::max(speed, std::abs(after.v[i]));
  }
  require(drift <= 1e-12 && speed <= 1e-10,
          "a cloth at rest without external forces moved: drift " + format("%.3g", drift) +
              " m, speed " + format("%.3g", speed) + " m/s");
  return {true, ""};
}

// A free cloth thrown spinning, its springs stretched and sheared, under gravity alone: its
// momentum changes by gravity's impulse and nothing else, however the method moves it inside.
// The stability monitor credits the attachments' work from the free cloth's momentum for every
// integrator that does not declare CLOTHLAB_TRAIT_DRAGS_TOWARDS_REST, so one that removes or adds
// momentum no force gave would have its pins' work misjudged. The measure is the drag rate that
// would explain the difference: |delta p - M g T| over the integral of sum m |v| dt (not |p|:
// round-off scales with the particles' momenta, which may cancel).
Verdict conserves_momentum(const clothlab_integrator& integrator, SheetShape shape) {
  Scene scene = sheet_scene(6, 5);
  scene.pinned.clear();
  Cloth cloth = sheet_cloth(scene, shape, Precision::Float64, pipeline_for(integrator));
  State state = state_of(cloth);
  const std::size_t n = state.x.size() / 3;
  for (std::size_t i = 0; i < n; ++i) {
    const double phase = 0.7 * static_cast<double>(i);
    const double x = state.x[3 * i], y = state.x[3 * i + 1];
    // Up to 2 cm off rest (springs 16 to 25 cm long), a spin of 3 rad/s about z and a throw
    // of about 1 m/s: every spring family pulls, and the spin keeps them pulling.
    state.x[3 * i] += 0.02 * std::sin(phase);
    state.x[3 * i + 1] += 0.02 * std::cos(1.3 * phase);
    state.x[3 * i + 2] += 0.02 * std::sin(2.1 * phase);
    state.v[3 * i] = -3.0 * y + 0.5;
    state.v[3 * i + 1] = 3.0 * x + 0.8;
    state.v[3 * i + 2] = 0.1 * std::cos(phase);
  }
  cloth.set_state(state.x, state.v);
  IntegratorInstance instance(integrator, default_values(integrator));
  instance.prepare(cloth);
  constexpr int steps = 20;
  constexpr double dt = 1e-3;
  const std::vector<double>& masses = cloth.model()->masses;
  std::vector<double> v;
  auto momentum_sum = [&] {  // sum of m |v|, kg m/s
    cloth.velocities(v);
    double sum = 0;
    for (std::size_t i = 0; i < n; ++i)
      sum += masses[i] * std::hypot(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
    return sum;
  };
  const Cloth::Momentum start = cloth.free_momentum();
  double momentum_time = 0.5 * momentum_sum() * dt;  // trapezoid rule, kg m
  for (int k = 0; k < steps; ++k) {
    instance.step(cloth, k * dt, dt);
    momentum_time += (k + 1 < steps ? 1.0 : 0.5) * momentum_sum() * dt;
  }
  const Cloth::Momentum end = cloth.free_momentum();
  Vec3 unexplained{0, 0, 0};
  for (std::size_t axis = 0; axis < 3; ++axis)
    unexplained[axis] =
        end.momentum[axis] - start.momentum[axis] - start.mass * scene.gravity[axis] * steps * dt;
  const double error = std::hypot(unexplained[0], unexplained[1], unexplained[2]);
  const double drag_rate = error / momentum_time;
  const std::string detail = "momentum not given by gravity " + format("%.3g", error) +
                             " kg m/s over " + std::to_string(steps) +
                             " steps of 1 ms: a drag of " + format("%.3g", drag_rate) + " 1/s";
  require(drag_rate <= momentum_drag_tolerance,
          detail + " (allowed " + format("%.3g", momentum_drag_tolerance) +
              "; a method that drags towards rest declares CLOTHLAB_TRAIT_DRAGS_TOWARDS_REST)");
  return {true, detail};
}

Verdict repeatable(const clothlab_integrator& integrator, SheetShape shape) {
  const Scene scene = sheet_scene(64, 48, true);
  // Half the step on the mesh: masses by area leave a corner a sixth of an inner particle's
  // mass and the jitter shortens some edges, so rk4 diverges there at 1 ms.
  const double dt = shape == SheetShape::Grid ? 1e-3 : 5e-4;
  const State first = simulate(integrator, scene, Precision::Float64, 1, 20, dt, shape);
  const State second = simulate(integrator, scene, Precision::Float64, 1, 20, dt, shape);
  require(first == second, "two identical runs give different bits");
  return {true, ""};
}

Verdict thread_count_independent(const clothlab_integrator& integrator, SheetShape shape,
                                 Precision precision) {
  // Above the engine's threading threshold: below it both runs would be single-threaded.
  constexpr uint32_t cols = 64;
  const Scene scene = sheet_scene(parallel_from_particles / cols + 8, cols, true);
  // Half the usual step: the finer grid is stiffer, and euler must stay finite. Eight steps
  // reach every code path a first step and later steps take; more only cost time, and a Krylov
  // plugin's many small parallel regions are slow wherever the two threads share cores.
  // Three on the mesh, whose spring-list path is many times slower per spring: the first
  // step and the later ones still run.
  const int steps = shape == SheetShape::Grid ? 8 : 3;
  const State one = simulate(integrator, scene, precision, 1, steps, 5e-4, shape);
  const State two = simulate(integrator, scene, precision, 2, steps, 5e-4, shape);
  require(one == two, "1 and 2 threads give different bits");
  return {true, ""};
}

// The same motion in both precisions: an integrator wrong in only one of them (one that does
// nothing in float32, say) fails here though each precision alone passes the other checks.
Verdict precisions_agree(const clothlab_integrator& integrator, SheetShape shape) {
  const Scene scene = sheet_scene(6, 5, true);
  const State start =
      state_of(sheet_cloth(scene, shape, Precision::Float64, pipeline_for(integrator)));
  const State wide = simulate(integrator, scene, Precision::Float64, 1, 30, 1e-3, shape);
  const State narrow = simulate(integrator, scene, Precision::Float32, 1, 30, 1e-3, shape);
  double moved = 0, difference = 0;
  for (size_t i = 0; i < wide.x.size(); ++i) {
    moved = std::max(moved, std::abs(wide.x[i] - start.x[i]));
    difference = std::max(difference, std::abs(narrow.x[i] - wide.x[i]));
  }
  require(moved > 1e-6, "the cloth did not move in float64 (" + format("%.3g", moved) + " m)");
  // float32 rounding over 30 steps stays far below a hundredth of the motion.
  require(difference <= 1e-2 * moved, "float32 and float64 differ by " +
                                          format("%.3g", difference) + " m after 30 steps (" +
                                          format("%.3g", moved) + " m of motion)");
  return {true, "float32 within " + format("%.2g", difference / moved) + " of float64's motion"};
}

}  // namespace

std::vector<Check> numerics_checks(const clothlab_integrator& integrator) {
  const clothlab_integrator* c = &integrator;
  if ((c->precisions & (1u << CLOTHLAB_FLOAT64)) == 0)
    return {{c->id, "numerics.float64", [] {
               return Verdict{false, "numerics are measured in float64, which it lacks"};
             }}};
  std::vector<Check> checks = {
      {c->id, "numerics.order-spring",
       [c] {
         return converges_at_declared_order(*c, [c](int n) { return spring_error(*c, 0.0, n); });
       }},
      {c->id, "numerics.order-free-fall",
       [c] {
         return converges_at_declared_order(*c, [c](int n) { return free_fall_error(*c, n); });
       }},
      {c->id, "numerics.pinned-f64",
       [c] { return on_every_shape(*c, pins_untouched, Precision::Float64); }},
      {c->id, "numerics.rest", [c] { return on_every_shape(*c, rest_stays_at_rest); }},
      {c->id, "numerics.deterministic", [c] { return on_every_shape(*c, repeatable); }},
      {c->id, "numerics.threads-f64",
       [c] { return on_every_shape(*c, thread_count_independent, Precision::Float64); }},
  };
  // A drag towards rest, declared, removes momentum by design: the monitor measures no pin's
  // pull from it.
  if (!has_trait(integrator, CLOTHLAB_TRAIT_DRAGS_TOWARDS_REST))
    checks.push_back(
        {c->id, "numerics.momentum", [c] { return on_every_shape(*c, conserves_momentum); }});
  // Without velocity forces the host builds no damping stage: the damped problem does not apply.
  if (uses_velocity_forces(integrator))
    checks.push_back({c->id, "numerics.order-damped-spring", [c] {
                        return converges_at_declared_order(
                            *c, [c](int n) { return spring_error(*c, 1.0, n); });
                      }});
  if (c->precisions & (1u << CLOTHLAB_FLOAT32)) {
    checks.push_back({c->id, "numerics.pinned-f32",
                      [c] { return on_every_shape(*c, pins_untouched, Precision::Float32); }});
    checks.push_back({c->id, "numerics.threads-f32", [c] {
                        return on_every_shape(*c, thread_count_independent, Precision::Float32);
                      }});
    checks.push_back(
        {c->id, "numerics.precisions-agree", [c] { return on_every_shape(*c, precisions_agree); }});
  }
  return checks;
}

}  // namespace clothlab::conformance
