// Vertex block descent (Chen, Macklin, et al. 2024, "Vertex Block Descent"): backward Euler on
// the springs as the minimisation of the incremental potential
//   E(x) = 1/(2 h^2) |x - y|_M^2 + elastic and damping potentials of the springs,
//   y = x0 + h v0 + h^2 a_ext(x0),
// by block coordinate descent with one particle per block: `iterations` sweeps over the
// particle colours (the topology extension's), each free particle taking one Newton step on
// its own 3x3 block with the others held (vbd_vertex_step.hpp), a colour's particles in
// parallel (vbd_blocks.hpp: the same bits for every thread count). Then v = (x - x0) / h.
//
// The unknown is the displacement d = x - x0, not x: v = d / h then keeps the step's motion
// exactly where, in float32, x0 + d would round it away (as XPBD keeps dx, xpbd.cpp).
//
// Initial guess (`adaptive_guess`, on by default): the paper's adaptive guess
// d = h v0 + h^2 a~, a~ the external acceleration's direction times the part of the last
// step's acceleration (v0 - v_prev) / h_prev along it, clamped to [0, |a_ext|]: a resting
// cloth starts where it rests, a falling one where it falls. Off, or on the first step after
// prepare, d = y - x0 (inertia). Only the start of the iteration changes: converged, both give
// the same step.
//
// Converged (iterations -> inf) this is backward Euler on the springs and their damping along
// each spring, with the external forces (gravity, wind: clothlab.external-forces/1) at x0, the
// step implicit_euler converges to with more Newton steps; first order in h. Each block step
// descends on E with a positive definite block, so few iterations give a stiff-looking but
// stable, dissipative step (the cloth is softer than its springs until the sweeps converge).
#include <clothlab/ext/integrator_traits.h>
#include <clothlab/ext/solver_statistics.h>

#include <algorithm>
#include <array>
#include <clothlab/sdk.hpp>
#include <clothlab/sdk/threads.hpp>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "scratch_vectors.hpp"
#include "vbd_blocks.hpp"
#include "vbd_vertex_step.hpp"

namespace clothlab::builtin {
namespace {

// Smaller clothes run on the calling thread: a colour of fewer than ~800 blocks is not worth
// the barrier that ends it (one per colour per sweep). The engine's own threshold.
constexpr std::size_t parallel_from_blocks = 4096;

// One precision's solver state, sized in prepare.
template <class Real>
struct Solver {
  VertexBlocks<Real> blocks;
  // Particle-major, 3 n: x0, the inertial target, d, the velocity the last step started from.
  std::vector<Real> start, inertial, displacement, previous_velocity;
  bool has_previous = false;  // previous_velocity and previous_h hold a step of this system
  double previous_h = 0;
};

// What a step needs, for every thread.
template <class Real>
struct StepArrays {
  Solver<Real>* solver;
  Real* x;
  Real* v;
  const Real* inverse_mass;
  const Real* external_acceleration;
  std::size_t particle_count;
  std::size_t stride;
  Real h;
  bool adaptive;  // adaptive initial guess, with a previous step to take it from
  Real previous_h;
};

// One thread's share of a step's outcome; combined by && and max, so in any order.
struct Outcome {
  bool finite;
  double correction;  // largest block correction of the last sweep
  double motion;      // largest displacement component
};

}  // namespace

struct Vbd {
  static constexpr const char* id = "vbd";
  static constexpr const char* name = "Vertex block descent";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Chen et al. 2024: backward Euler as per-particle 3x3 Newton steps on the incremental "
      "potential, Gauss-Seidel over the particle colours; first order when converged";
  static constexpr uint32_t order = 1;
  static constexpr uint32_t evals_per_step = 0;  // springs are its own; external forces only
  // The springs' damping (kd) is part of the incremental potential.
  static constexpr uint32_t flags = CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
  static constexpr std::array<clothlab_param_spec, 3> params{
      sdk::int_param("iterations", 10, 1, 500,
                     "sweeps over the particle colours per step (one 3x3 Newton step per free "
                     "particle each)"),
      sdk::bool_param("adaptive_guess", true,
                      "start from the paper's adaptive initial guess; 0 = from inertia "
                      "(x0 + h v + h^2 a_ext)"),
      sdk::threads_param(),
  };
  static constexpr clothlab_integrator_traits traits{
      sizeof(clothlab_integrator_traits),
      CLOTHLAB_TRAIT_ITERATIVE | CLOTHLAB_TRAIT_MOVES_ATTACHMENTS | CLOTHLAB_TRAIT_LOCAL_SOLVES,
      nullptr, "iterations"};

  explicit Vbd(const sdk::Params& values)
      : iterations_(static_cast<int>(values.integer("iterations"))),
        adaptive_guess_(values.flag("adaptive_guess")),
        requested_threads_(values.integer("threads")) {}

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    const sdk::Topology topology = system.topology();
    (void)system.external_forces();  // fails here, not in step, when the host lacks it
    scratch_.allocate(system);
    Solver<Real>& solver = solver_for<Real>();
    solver.blocks.build(topology, system.inverse_mass());
    const std::size_t entries = 3 * std::size_t{system.particle_count()};
    for (std::vector<Real>* buffer :
         {&solver.start, &solver.inertial, &solver.displacement, &solver.previous_velocity})
      buffer->assign(entries, 0);
    solver.has_previous = false;
    threads_ = sdk::plugin_threads(system, requested_threads_,
                                   solver.blocks.block_count() >= parallel_from_blocks);
    sdk::start_thread_team(threads_);
    last_ = {};
  }

  template <class Real>
  void step(sdk::System<Real>& system, double t, double h) {
    const auto [external_acceleration] = scratch_.bind(system);
    last_ = {sizeof(clothlab_solver_step_statistics), 1, 0, 0, 0.0};
    if (h == 0.0) return;
    Solver<Real>& solver = solver_for<Real>();
    // Implicit in the positions: the sweeps hold the attachments at the step's end.
    system.move_attachments(t + h);
    system.external_forces().acceleration(t, system.x(), external_acceleration);
    const StepArrays<Real> arrays{&solver,
                                  system.x(),
                                  system.v(),
                                  system.inverse_mass(),
                                  external_acceleration,
                                  system.particle_count(),
                                  system.stride(),
                                  static_cast<Real>(h),
                                  adaptive_guess_ && solver.has_previous,
                                  static_cast<Real>(solver.previous_h)};
    Outcome outcome{};
    if (threads_ == 1) {
      outcome = sweep(arrays);
    } else {
      bool finite = true;
      double correction = 0, motion = 0;
#pragma omp parallel num_threads(threads_) reduction(&& : finite) reduction(max : correction, motion)
      {
        const Outcome mine = sweep(arrays);
        finite = mine.finite, correction = mine.correction, motion = mine.motion;
      }
      outcome = {finite, correction, motion};
    }
    if (!outcome.finite)
      throw sdk::Error(CLOTHLAB_ERROR_NUMERICAL,
                       "non-finite velocity in the step at t = " + std::to_string(t));
    solver.has_previous = true;
    solver.previous_h = h;
    last_.iterations = static_cast<uint64_t>(iterations_);
    last_.residual = outcome.motion > 0 ? outcome.correction / outcome.motion : 0.0;
  }

  void last_step_statistics(clothlab_solver_step_statistics& out) const { out = last_; }

 private:
  // A whole step on the calling thread's share of each loop. The worksharing loops run on the
  // team of a parallel region, or, on one thread, orphaned (no team, no barrier, no allocation).
  template <class Real>
  Outcome sweep(const StepArrays<Real>& s) const {
    Solver<Real>& solver = *s.solver;
    const VertexBlocks<Real>& blocks = solver.blocks;
    const auto n = static_cast<long>(s.particle_count);
#pragma omp for schedule(static)
    for (long i = 0; i < n; ++i) start_particle(s, static_cast<std::size_t>(i));

    const BlockArrays<Real> block_arrays{solver.start.data(), solver.inertial.data(),
                                         solver.displacement.data(), 1 / s.h, 1 / (s.h * s.h)};
    Real correction = 0;
    for (int iteration = 0; iteration < iterations_; ++iteration) {
      const bool last = iteration + 1 == iterations_;
      for (std::size_t color = 0; color < blocks.color_count(); ++color) {
        const long begin = blocks.color_begin(color), end = blocks.color_begin(color + 1);
#pragma omp for schedule(static)
        for (long b = begin; b < end; ++b) {
          const Real moved =
              descend_block(blocks.particle(b), blocks.mass(b), blocks.springs(b), block_arrays);
          if (last) correction = std::max(correction, moved);
        }
      }
    }

    bool finite = true;
    Real motion = 0;
    const auto block_count = static_cast<long>(blocks.block_count());
#pragma omp for schedule(static)
    for (long b = 0; b < block_count; ++b) {
      const std::size_t i = blocks.particle(b);
      for (std::size_t k = 0; k < 3; ++k) {
        const Real d = solver.displacement[3 * i + k];
        const std::size_t e = k * s.stride + i;
        s.x[e] += d;
        s.v[e] = d / s.h;
        finite = finite && std::isfinite(s.v[e]);
        motion = std::max(motion, std::abs(d));
      }
    }
    return {finite, correction, motion};
  }

  // x0 of particle i, and for a free one the inertial target, the initial guess and the
  // velocity the step starts from (the next step's adaptive guess reads it).
  template <class Real>
  void start_particle(const StepArrays<Real>& s, std::size_t i) const {
    Solver<Real>& solver = *s.solver;
    std::array<Real, 3> v, a;
    for (std::size_t k = 0; k < 3; ++k) {
      solver.start[3 * i + k] = s.x[k * s.stride + i];
      solver.displacement[3 * i + k] = 0;  // pinned: stays 0
      v[k] = s.v[k * s.stride + i];
      a[k] = s.external_acceleration[k * s.stride + i];
    }
    if (s.inverse_mass[i] == 0) return;
    std::array<Real, 3> guess = a;
    if (s.adaptive)
      guess = adaptive_acceleration(v, &solver.previous_velocity[3 * i], a, s.previous_h);
    for (std::size_t k = 0; k < 3; ++k) {
      solver.inertial[3 * i + k] = s.h * (v[k] + s.h * a[k]);
      solver.displacement[3 * i + k] = s.h * (v[k] + s.h * guess[k]);
      solver.previous_velocity[3 * i + k] = v[k];
    }
  }

  // a~ = a_ext / |a_ext| clamp(a_last . a_ext / |a_ext|, 0, |a_ext|), a_last = (v - v_prev) /
  // h_prev.
  template <class Real>
  static std::array<Real, 3> adaptive_acceleration(const std::array<Real, 3>& v,
                                                   const Real* previous_v,
                                                   const std::array<Real, 3>& a, Real previous_h) {
    const Real size = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    if (!(size > 0)) return {0, 0, 0};
    Real along = 0;
    for (std::size_t k = 0; k < 3; ++k) along += (v[k] - previous_v[k]) * a[k];
    along /= previous_h * size;
    const Real scale = std::clamp(along, Real(0), size) / size;
    return {a[0] * scale, a[1] * scale, a[2] * scale};
  }

  template <class Real>
  Solver<Real>& solver_for() {
    if constexpr (sizeof(Real) == 4)
      return solver_f32_;
    else
      return solver_f64_;
  }

  int iterations_;
  bool adaptive_guess_;
  long requested_threads_;
  int threads_ = 1;
  ScratchVectors<1> scratch_;  // the external acceleration
  Solver<float> solver_f32_;
  Solver<double> solver_f64_;
  clothlab_solver_step_statistics last_{};
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-vbd", "1.0.0",
                      clothlab::sdk::integrators<clothlab::builtin::Vbd>,
                      clothlab::sdk::scenarios<>)
