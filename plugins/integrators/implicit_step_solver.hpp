// The nonlinear solve of an implicit step, shared by implicit_euler and bdf2. Both methods reduce
// a step to the same equation for the velocity change dv from a state (x0, v0):
//   v1 = v0 + dv,   x1 = x0 + h v1,   dv = h a(t1, x1, v1),
// with h the step itself (backward Euler) or a multiple of it (BDF2, whose x0 and v0 are
// combinations of the last two states). Newton on that equation, linearised at each iterate
// (x1, v1), is
//   (I - h da/dv - h^2 da/dx) delta = h a(t1, x1, v1) - dv,   dv += delta.
// Its first step starts either at the prediction dv = 0 (x1 = x0 + h v0, v1 = v0), or, as
// Baraff and Witkin, linearised about (x0, v0) itself: a(x1, v1) ~ a(x0, v0) + (da/dx) h v1 +
// (da/dv) dv gives
//   (I - h da/dv - h^2 da/dx) dv = h (a0 + h (da/dx) v0).
// The two differ where the matrix is not the exact Jacobian (the definite one, below): Baraff
// and Witkin's right-hand side carries it in h^2 (da/dx) v0, an O(h^2) change of dv a step that
// only a first-order method can afford; from the prediction the matrix multiplies only the
// correction delta = O(h), so the change is O(h^3) and a second-order method keeps its order.
// `newton_steps` > 1 continues with the Newton steps above.
//
// Each linear system is solved matrix-free by block-Jacobi preconditioned conjugate gradients in
// the mass inner product (preconditioned_cg.hpp): one Jacobian product per iteration; where the
// host offers clothlab.cg-step/1, an iteration is two sweeps (the product with the vector
// updates and dot product around it, and one update sweep). `multigrid` = 1 preconditions CG
// with a geometric multigrid V-cycle on the cloth's grid instead (multigrid_preconditioner.hpp):
// its iteration count stays nearly the same as the mesh is refined, where block-Jacobi's grows
// with the grid's side, at the price of assembling the matrix (from the host's block table of
// the definite Jacobian, clothlab.definite-jacobian/2, else by 75 Jacobian products) and
// Galerkin products per solve, and a V-cycle per iteration (lab/real-cloth.md, "Multigrid"), whose
// finest level smooths with 2 x `multigrid_sweeps` more products; `multigrid_rebuild` = N reuses
// that set-up for N solves, and the step statistics count the builds as factorisations. A solve
// that stops at `max_iterations` (or meets p.Ap <= 0) before the tolerance is reported through
// clothlab.solver-statistics/1, never passed off as converged.
//
// Definiteness (`definite`, on by default). Two terms of the exact da/dx make A indefinite
// or unsymmetric once h is large (a folding flag at dt = 50 ms: CG breaks down, p.Ap <= 0,
// and the step explodes): a spring shorter than its rest length has the transverse
// stiffness -ks (1 - l0/l) (I - n n^T) > 0, and the damping force's x-derivative is not
// symmetric. As Baraff and Witkin (and Choi & Ko 2002 for compression), the matrix then
// keeps the springs' Hooke stiffness without that compressive term plus the damping's
// velocity derivative: the host's clothlab.definite-jacobian/1, one product per CG
// iteration. The Newton matrix changes, not the equation: more Newton steps still converge
// to the implicit method's solution. `definite` = 0 uses the exact Jacobian
// (clothlab.jacobian/1).
//
// Warm start (`warm_start`, on by default): the first solve of a step starts from the
// previous step's dv, scaled by the ratio of the steps (dv ~ h a), instead of 0; the
// tolerance stays relative to the right-hand side, so a good guess saves iterations and
// never loosens the solve. It costs one product for the initial residual.
#pragma once

#include <clothlab/ext/solver_statistics.h>

#include <algorithm>
#include <array>
#include <clothlab/sdk.hpp>
#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

#include "preconditioned_cg.hpp"
#include "scratch_vectors.hpp"

namespace clothlab::builtin {

// What every method on this solver declares: stable at any step, iterative (CG), contacts and
// attachments after each step.
inline constexpr clothlab_integrator_traits implicit_step_solver_traits{
    sizeof(clothlab_integrator_traits),
    CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE | CLOTHLAB_TRAIT_ITERATIVE |
        CLOTHLAB_TRAIT_RESOLVES_CONTACTS | CLOTHLAB_TRAIT_MOVES_ATTACHMENTS,
    nullptr, "max_iterations"};

// The solver's settings, in the schema order of both plugins; `newton_steps_help` says what
// more Newton steps converge to.
constexpr std::array<clothlab_param_spec, 10> implicit_step_solver_params(
    const char* newton_steps_help) {
  return {
      sdk::real_param("tolerance", 1e-5, 1e-14, 1e-1, "",
                      "CG stops when the residual's mass norm falls below tolerance x the "
                      "right-hand side's"),
      sdk::int_param("max_iterations", 1000, 1, 100000,
                     "CG iterations per linear solve at most; a solve that hits it is reported"),
      sdk::int_param("newton_steps", 1, 1, 50, newton_steps_help),
      sdk::bool_param("definite", true,
                      "Baraff-Witkin's definite matrix: no compressive transverse stiffness, no "
                      "damping x-derivative; 0 = the exact Jacobian"),
      sdk::bool_param("warm_start", true,
                      "CG starts from the previous step's dv (scaled by the step ratio); 0 = "
                      "from 0"),
      sdk::bool_param("multigrid", false,
                      "CG preconditioned by a geometric multigrid V-cycle on the cloth's grid "
                      "(clothlab.grid/1); 0 = block-Jacobi"),
      sdk::int_param("multigrid_coarsest", kDefaultCoarsestNodes, 1, kMaxCoarsestNodes,
                     "multigrid: coarsen the grid while it has more particles than this (and "
                     "both sides at least 3); a dense direct solve there"),
      sdk::int_param("multigrid_sweeps", kDefaultMultigridSweeps, 1, 8,
                     "multigrid: smoothing steps before and after each coarse correction "
                     "(Chebyshev steps of one Jacobian product each on the cloth's own grid, "
                     "Chebyshev steps over the stored blocks on the coarser ones)"),
      sdk::int_param("multigrid_coarsening", kPreconditionerCoarsening, kMinCoarsening,
                     kMaxCoarsening,
                     "multigrid: each coarser level keeps every Nth node along both axes; 3: "
                     "smaller coarse levels, cheaper V-cycles, more CG iterations; 2: the "
                     "reverse"),
      sdk::int_param("multigrid_rebuild", 1, 1, 1024,
                     "multigrid: build the hierarchy for every Nth linear solve and reuse it in "
                     "between (CG still converges on the current matrix); always after prepare "
                     "and when the step size changes"),
  };
}

// Where the first Newton step of a solve is linearised (see the top).
enum class FirstNewtonStep { kAtStart, kAtPrediction };

class ImplicitStepSolver {
 public:
  explicit ImplicitStepSolver(const sdk::Params& values)
      : tolerance_(values.real("tolerance")),
        max_iterations_(values.integer("max_iterations")),
        newton_steps_(values.integer("newton_steps")),
        definite_(values.flag("definite")),
        warm_start_(values.flag("warm_start")),
        multigrid_(values.flag("multigrid")),
        multigrid_coarsest_(values.integer("multigrid_coarsest")),
        multigrid_sweeps_(values.integer("multigrid_sweeps")),
        multigrid_coarsening_(values.integer("multigrid_coarsening")),
        multigrid_rebuild_(values.integer("multigrid_rebuild")) {}

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    system.jacobian().reserve();
    // Checked here, so a host without them fails in prepare.
    if (definite_) (void)system.definite_jacobian();
    (void)system.reductions();
    scratch_.allocate(system);
    inverse_blocks_.assign(9 * size_t{system.particle_count()}, 0.0);
    multigrid_preconditioner_.reset();
    if (multigrid_)
      multigrid_preconditioner_.emplace(system, multigrid_coarsest_, multigrid_sweeps_,
                                        multigrid_rebuild_,
                                        definite_ && system.definite_jacobian().has_blocks()
                                            ? std::optional(system.jacobian().pattern())
                                            : std::nullopt,
                                        static_cast<int>(multigrid_coarsening_));
    previous_h_ = 0.0;
    last_ = {};
  }

  // Starts a step's statistics: a step without a solve (h = 0) reports a converged one.
  void begin_step() { last_ = {sizeof(clothlab_solver_step_statistics), 1, 0, 0, 0.0}; }

  // dv of the step from (x0, v0) of size h (see the top): the acceleration and Jacobian of a
  // first step at the start at time t0, every other one's at t1. Returns the solver's own
  // vector, valid until the next solve.
  template <class Real>
  const Real* solve(sdk::System<Real>& system, double t0, double t1, double h, const Real* x0,
                    const Real* v0, FirstNewtonStep first) {
    const auto vectors = scratch_.bind(system);
    Real *const acceleration = vectors[0], *const dv = vectors[1], *const rhs = vectors[2],
                *const delta = vectors[3], *const x1 = vectors[4], *const v1 = vectors[5],
                *const zero = vectors[6];
    std::array<Real*, PreconditionedCg<Real>::vector_count> cg_vectors{};
    std::copy(vectors.begin() + step_vectors, vectors.end(), cg_vectors.begin());
    PreconditionedCg<Real> solver(
        system, cg_vectors, inverse_blocks_, definite_, true,
        multigrid_preconditioner_ ? &*multigrid_preconditioner_ : nullptr);
    const uint64_t rebuilds_before = rebuild_count();

    // Cleared until the solve completes: a solve that throws leaves no dv to start from.
    const double previous_h = std::exchange(previous_h_, 0.0);
    const bool warm = warm_start_ && previous_h > 0.0;
    long newton = 0;
    if (first == FirstNewtonStep::kAtStart) {
      // Baraff-Witkin: b = h a0 + h^2 (da/dx) v0, A linearised at (x0, v0).
      system.acceleration(t0, x0, v0, acceleration);
      if (definite_) {
        system.definite_jacobian().apply(t0, x0, v0, h * h, 0.0, v0, rhs);
      } else {
        system.jacobian().apply(t0, x0, v0, h * h, 0.0, v0, rhs);
      }
      system.template lincomb<1>(rhs, rhs, {h}, {acceleration});
      if (warm) {
        system.template lincomb<1>(dv, zero, {h / previous_h}, {dv});
      } else {
        system.copy(dv, zero);
      }
      solve_linear(solver, t0, h, x0, v0, rhs, dv, warm);
      newton = 1;
    } else {
      // The first correction starts from the last step's dv; the iterate itself from dv = 0.
      if (warm) system.template lincomb<1>(delta, zero, {h / previous_h}, {dv});
      system.copy(dv, zero);
    }

    for (; newton < newton_steps_; ++newton) {
      // Whole copies first: the pinned particles' entries of the iterate are theirs.
      system.copy(v1, v0);
      system.axpy(v1, 1.0, dv);
      system.copy(x1, x0);
      system.axpy(x1, h, v1);
      system.acceleration(t1, x1, v1, acceleration);
      system.template lincomb<2>(rhs, zero, {h, -1.0}, {acceleration, dv});
      const bool guess = newton == 0 && warm;
      if (!guess) system.copy(delta, zero);
      solve_linear(solver, t1, h, x1, v1, rhs, delta, guess);
      system.axpy(dv, 1.0, delta);
    }
    // Each multigrid build ends in a factorisation of its coarsest level.
    last_.factorizations += rebuild_count() - rebuilds_before;
    previous_h_ = h;
    return dv;
  }

  void last_step_statistics(clothlab_solver_step_statistics& out) const { out = last_; }

 private:
  // Scratch: acceleration, dv (kept from solve to solve for the warm start), rhs, delta, x1,
  // v1, zero (never written), then CG's.
  static constexpr size_t step_vectors = 7;
  static constexpr size_t cg_vectors = PreconditionedCg<double>::vector_count;

  uint64_t rebuild_count() const {
    return multigrid_preconditioner_ ? multigrid_preconditioner_->rebuild_count() : 0;
  }

  // Solves (I - h da/dv - h^2 da/dx) at (x, v) times solution = rhs from the solution's entries
  // (guess) or 0 (solution zeroed by the caller); adds to last_.
  template <class Real>
  void solve_linear(PreconditionedCg<Real>& solver, double t, double h, const Real* x,
                    const Real* v, const Real* rhs, Real* solution, bool guess) {
    solver.start(t, h, x, v, rhs, solution, guess, tolerance_);
    long iterations = 0;
    bool converged = solver.converged();
    while (!converged && iterations < max_iterations_) {
      const auto outcome = solver.iterate();
      if (outcome == PreconditionedCg<Real>::Outcome::kBreakdown) break;  // reported as missed
      ++iterations;
      converged = outcome == PreconditionedCg<Real>::Outcome::kConverged;
    }
    solver.finish();
    const double rhs_norm = solver.rhs_norm();
    last_.iterations += static_cast<uint64_t>(iterations);
    last_.converged = last_.converged && converged ? 1u : 0u;
    last_.residual =
        std::max(last_.residual, rhs_norm == 0.0 ? 0.0 : solver.residual_norm() / rhs_norm);
  }

  double tolerance_;
  long max_iterations_;
  long newton_steps_;
  bool definite_;
  bool warm_start_;
  bool multigrid_;
  long multigrid_coarsest_;
  long multigrid_sweeps_;
  long multigrid_coarsening_;
  long multigrid_rebuild_;
  std::optional<MultigridPreconditioner> multigrid_preconditioner_;  // where multigrid_
  double previous_h_ = 0.0;  // the last solve's h; 0: no dv to start from
  ScratchVectors<step_vectors + cg_vectors> scratch_;
  std::vector<double> inverse_blocks_;  // 9 n, row-major 3x3 per particle
  clothlab_solver_step_statistics last_{};
};

}  // namespace clothlab::builtin
