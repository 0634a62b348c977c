// XPBD: the springs as compliant distance constraints (Macklin, Mueller, Chentanez 2016,
// "XPBD: position-based simulation of compliant constrained dynamics"), one iteration per
// step by default: the host's frame substeps are the small steps of Macklin et al. 2019
// ("Small steps in physics simulation"), so `--substeps` is the one knob of h.
//
// Per substep of length h = dt / inner_substeps (one substep, h = dt, by default):
//   predict    dx = h (v + h a_ext(x))                        (gravity, wind: the host's
//                                                             external-forces extension)
//   project    lambda = 0, then `iterations` Gauss-Seidel sweeps over the springs, colour
//              by colour (the topology extension's independent sets), each colour's springs
//              in parallel: no two share a particle, so every thread count gives the same bits
//              (option: Chebyshev acceleration of the sweeps, xpbd_chebyshev.hpp, on the
//              general path; a grid cloth then takes the general path too)
//   tethers    (option, xpbd_tethers.hpp) each free particle's long-range attachments to
//              pinned particles, |p_i - p_anchor| <= (1 + slack) rest, projected once
//   velocity   v = dx / h,  x += dx
//   contacts   the host's clothlab.contacts/1 on (x, v): the colliders as the substep's last
//              constraint (pushed out to the thickness, normal velocity removed, friction)
// x stays at the substep's start while the projections move only dx, the substep's
// displacement; the springs see the positions x + dx as (x_i - x_j) + (dx_i - dx_j). So v
// never comes from x - x_prev: in float32 a substep's motion (g h^2 is ~1e-8 m at h = 25 us)
// is below the rounding of x itself and would be lost, and the cloth would not start to fall.
//
// Where the parts are:
//   xpbd_constraint.hpp     the constraint law of one spring (eq. 26 with damping)
//   xpbd_general_sweep.hpp  a substep over any topology, colour by colour
//   xpbd_color_blocks.hpp   a colour's springs in blocks of lanes (float32)
//   xpbd_chebyshev.hpp      Chebyshev acceleration of the general sweep's iterations
//   xpbd_grid.hpp           the host's grid (clothlab.grid/1) and its colours as stencils
//   xpbd_grid_path.hpp      the grid path: its plan (xpbd_grid_plan.hpp) and the SIMD
//                           target's sweep
//   xpbd_grid_sweep.hpp     a substep on the grid, row by row, on up to two bands of threads
//   xpbd_wavefront.hpp      the grid substep's phases and their lags
//   xpbd_bands.hpp          how the grid sweep's threads share the rows and phases
//   xpbd_row_kernel.hpp     one colour's springs of one grid row
//   xpbd_uniform_mass.hpp   the grid's common inverse mass, which the row kernels skip
//   xpbd_tethers.hpp        the long-range attachments to the pins
//   xpbd_tether_projection.hpp  their projection
//
// Tethers are a model change, not a solver setting: where the spring dynamics would strain the
// cloth along a tether by more than the slack, the tethered cloth converges (in h) to another
// solution, so they are off by default (`tethers` 0) and the accuracy below holds without them.
//
// Chebyshev acceleration (`chebyshev_rho` > 0) runs on the general path only: the grid sweep
// pipelines a substep's iterations as phases of one wavefront over the rows
// (xpbd_wavefront.hpp), so no moment holds a complete iterate to extrapolate from. With it on,
// a grid cloth is swept by the general path (same Gauss-Seidel order, without the grid's
// row kernels); with it off (the default) nothing changes.
//
// Accuracy: one converged projection per substep is backward Euler on the elastic dynamics
// (same equation as its Newton step for a single spring), so XPBD converges at first order
// in h to the spring dynamics with the scene's ks and kd; one iteration per substep adds an
// O(h^2) per-step Gauss-Seidel error, which keeps the method first order.

#include <algorithm>
#include <array>
#include <clothlab/sdk.hpp>
#include <clothlab/sdk/threads.hpp>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>

#include "scratch_vectors.hpp"
#include "xpbd_general_sweep.hpp"
#include "xpbd_grid.hpp"
#include "xpbd_grid_path.hpp"
#include "xpbd_substep.hpp"
#include "xpbd_tethers.hpp"

namespace clothlab::builtin {
namespace {

// Smaller clothes run on the calling thread: a colour of fewer than ~5000 springs is not
// worth the barrier that ends it (12 barriers per sweep).
constexpr uint32_t parallel_from_springs = 65536;

// One precision's solver state: the tethers and the sweep the topology takes.
template <class Real>
struct Solver {
  Tethers<Real> tethers;
  GeneralSweep<Real> general;
  GridPath<Real> grid;
  bool on_grid = false;
};

}  // namespace

// Built twice from this file (plugins/integrators/CMakeLists.txt): `xpbd`, tethers off, and
// `xpbd_tethers`, the same code with tethers on by default, so that a search over the plugin
// path (clothlab --choose) weighs the tethered model beside the plain one.
#ifdef CLOTHLAB_XPBD_TETHERED
inline constexpr bool tethered_build = true;
#else
inline constexpr bool tethered_build = false;
#endif

struct Xpbd {
  static constexpr const char* id = tethered_build ? "xpbd_tethers" : "xpbd";
  static constexpr const char* name = tethered_build
                                          ? "XPBD with long-range attachments (tethers) to the pins"
                                          : "XPBD distance constraints with substeps";
  static constexpr const char* version = "1.2.0";
  static constexpr const char* description =
      tethered_build
          ? "xpbd with tethers 3 by default: Kim et al. 2012 long-range attachments, each free "
            "particle at most (1 + tether_slack) x its initial distance from its pins"
          : "Macklin et al. 2016/2019: springs as compliant constraints (alpha = 1/ks, damping "
            "eq. 26), Gauss-Seidel by spring colour, substeps; first order, unconditionally "
            "stable";
  static constexpr uint32_t order = 1;
  // No eval_acceleration calls: its cost is inner_substeps x iterations passes over the springs.
  static constexpr uint32_t evals_per_step = 0;
  // The damping (kd) is part of the constraint projection; the flag makes the host and the
  // conformance runner treat the scene's damping as present.
  static constexpr uint32_t flags = CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
  static constexpr std::array<clothlab_param_spec, 7> params{
      sdk::int_param("inner_substeps", 1, 1, 1000,
                     "substeps inside each host step (h = dt / inner_substeps); they multiply the "
                     "frame substeps, which are the knob to turn"),
      sdk::int_param("iterations", 1, 1, 100, "Gauss-Seidel sweeps over the springs per substep"),
      sdk::threads_param(),
      sdk::int_param("tethers", tethered_build ? 3 : 0, 0, 16,
                     "long-range attachments per free particle to pinned particles (the nearest "
                     "pin of each pinned island, then pins spread along it); 0 = off"),
      sdk::real_param("tether_slack", 0.0, 0.0, 1.0, "",
                      "a tether's max length is (1 + tether_slack) x the particle's straight-line "
                      "distance to its pin at prepare"),
      sdk::real_param("chebyshev_rho", 0.0, 0.0, 0.9999, "",
                      "Chebyshev acceleration of a substep's sweeps (Wang 2015): the estimated "
                      "spectral radius of one sweep; 0 = off. On (with chebyshev_delay below "
                      "iterations): the general (not the grid) path"),
      sdk::int_param("chebyshev_delay", 10, 1, 1000,
                     "plain sweeps of a substep before Chebyshev acceleration starts; at "
                     "iterations or more, none is accelerated"),
  };
  static constexpr clothlab_integrator_traits traits{
      sizeof(clothlab_integrator_traits),
      CLOTHLAB_TRAIT_ITERATIVE | CLOTHLAB_TRAIT_RESOLVES_CONTACTS |
          CLOTHLAB_TRAIT_MOVES_ATTACHMENTS | CLOTHLAB_TRAIT_LOCAL_SOLVES,
      "inner_substeps", "iterations"};

  explicit Xpbd(const sdk::Params& values)
      : substeps_(static_cast<int>(values.integer("inner_substeps"))),
        iterations_(static_cast<int>(values.integer("iterations"))),
        requested_threads_(values.integer("threads")),
        tethers_per_particle_(static_cast<uint32_t>(values.integer("tethers"))),
        tether_slack_(values.real("tether_slack")),
        chebyshev_rho_(values.real("chebyshev_rho")),
        chebyshev_delay_(values.integer("chebyshev_delay")) {}

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    const sdk::Topology topology = system.topology();
    (void)system.external_forces();  // fails here, not in step, when the host lacks it
    scratch_.allocate(system);
    Solver<Real>& solver = solver_for<Real>();
    solver.tethers.build(topology, system.x(), system.stride(), system.inverse_mass(),
                         tethers_per_particle_, tether_slack_);
    threads_ = sdk::plugin_threads(system, requested_threads_,
                                   topology.spring_count() >= parallel_from_springs);
    std::optional<GridLayout> grid = grid_layout(system.grid(), topology);
    // Every sweep before the delay has weight 1: a delay of `iterations` or more accelerates
    // nothing, and such a setting keeps the grid path and no divergence check.
    const bool accelerated = chebyshev_rho_ > 0.0 && chebyshev_delay_ < iterations_;
    solver.on_grid = grid.has_value() && !accelerated;
    if (solver.on_grid)
      solver.grid.prepare(std::move(*grid), iterations_, solver.tethers.slots(),
                          system.inverse_mass(), system.particle_count(), threads_);
    else
      solver.general.build(system, topology, iterations_, accelerated ? chebyshev_rho_ : 0.0,
                           chebyshev_delay_, threads_);
    sdk::start_thread_team(threads_);
  }

  template <class Real>
  void step(sdk::System<Real>& system, double t, double dt) {
    const auto [external_acceleration, displacement] = scratch_.bind(system);
    if (dt == 0.0) return;
    const sdk::ExternalForces<Real> external = system.external_forces();
    const bool wind = external.depends_on_position();
    const double h = dt / substeps_;
    Solver<Real>& solver = solver_for<Real>();
    if (!wind) external.acceleration(t, system.x(), external_acceleration);
    const bool attachments = system.has_attachments();
    // The grid sweep computes the wind's accelerations itself, a few rows ahead of its predict
    // pass, where they read nothing it changes before (no air, which reads v; no attachments,
    // which move x before the sweep) and the host has a scratch slot per sweep thread.
    const bool ahead = wind && solver.on_grid && external.has_rows() &&
                       !external.depends_on_velocity() && !attachments &&
                       solver.grid.computes_external_ahead() &&
                       static_cast<uint32_t>(threads_) <= system.threads().value_or(0);
    if (solver.tethers.active()) solver.tethers.refresh_anchors(system.x(), system.stride());
    const Substep<Real> arrays{system.inverse_mass(),
                               external_acceleration,
                               displacement,
                               system.x(),
                               system.v(),
                               solver.tethers.active() ? &solver.tethers : nullptr,
                               system.particle_count(),
                               system.stride(),
                               static_cast<Real>(h),
                               static_cast<Real>(h * h),
                               static_cast<Real>(1.0 / h)};
    for (int substep = 0; substep < substeps_; ++substep) {
      if (wind && !ahead) external.acceleration(t + substep * h, system.x(), external_acceleration);
      // The substep's constraints hold the attachments (and the tethers' anchors on them) at
      // the substep's end.
      if (attachments) {
        system.move_attachments(t + (substep + 1) * h);
        if (solver.tethers.active()) solver.tethers.refresh_anchors(system.x(), system.stride());
      }
      const bool finite =
          solver.on_grid
              ? solver.grid.run(
                    arrays, threads_,
                    ahead ? ExternalAhead<Real>{&external, external_acceleration, t + substep * h}
                          : ExternalAhead<Real>{})
              : solver.general.run(arrays);
      if (!solver.on_grid && solver.general.diverged())
        throw_divergence(t + substep * h, solver.general.first_change(),
                         solver.general.last_change());
      if (!finite)
        throw sdk::Error(CLOTHLAB_ERROR_NUMERICAL, "non-finite velocity in the substep at t = " +
                                                       std::to_string(t + substep * h));
      // The colliders as one more constraint, projected after the substep's springs.
      system.resolve_contacts(t + (substep + 1) * h);
    }
  }

 private:
  // The accelerated sweeps of the substep at t grew their change (xpbd_chebyshev.hpp).
  [[noreturn]] void throw_divergence(double t, double first_change, double last_change) const {
    char text[320];
    std::snprintf(text, sizeof text,
                  "chebyshev_rho %g diverges: the last of the %d sweeps of the substep at t = %g "
                  "s moved a particle by %.3g m, more than the first (%.3g m); lower "
                  "chebyshev_rho or raise chebyshev_delay",
                  chebyshev_rho_, iterations_, t, last_change, first_change);
    throw sdk::Error(CLOTHLAB_ERROR_NUMERICAL, text);
  }

  template <class Real>
  Solver<Real>& solver_for() {
    if constexpr (sizeof(Real) == 4)
      return solver_f32_;
    else
      return solver_f64_;
  }

  int substeps_;
  int iterations_;
  long requested_threads_;
  uint32_t tethers_per_particle_;
  double tether_slack_;
  double chebyshev_rho_;
  long chebyshev_delay_;
  int threads_ = 1;
  ScratchVectors<2> scratch_;  // external acceleration, the substep's displacement
  Solver<float> solver_f32_;
  Solver<double> solver_f64_;
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY(clothlab::builtin::tethered_build ? "clothlab-builtin-xpbd-tethers"
                                                        : "clothlab-builtin-xpbd",
                      "1.2.0", clothlab::sdk::integrators<clothlab::builtin::Xpbd>,
                      clothlab::sdk::scenarios<>)
