// Linearised backward Euler (Baraff & Witkin 1998). Backward Euler on (x, v),
//   v1 = v0 + h a(x1, v1),   x1 = x0 + h v1,
// is the equation g(dv) = h a(x0 + h (v0 + dv), v0 + dv) - dv = 0 for dv = v1 - v0. Baraff and
// Witkin take one Newton step from dv = 0 with a linearised about (x0, v0):
//   (I - h da/dv - h^2 da/dx) dv = h (a0 + h (da/dx) v0)
// (their (M - h df/dv - h^2 df/dx) dv = h (f0 + h (df/dx) v0) divided by M). `newton_steps`
// > 1 continues with Newton on g itself, linearised at each iterate (x1, v1):
//   (I - h da/dv - h^2 da/dx) delta = h a(x1, v1) - dv,   dv += delta,
// which converges to backward Euler proper. First order; stable at any dt on a damped cloth.
//
// Each linear system is solved matrix-free by preconditioned conjugate gradients: one
// Jacobian product (clothlab.jacobian/1) per iteration. A = I - h da/dv - h^2 da/dx is
// self-adjoint in the mass inner product (M A = M - h df/dv - h^2 df/dx is symmetric), so
// every inner product is the M-weighted one (clothlab.reductions/1 mass_dot) and the
// tolerance is on |r|_M / |b|_M. The preconditioner is block-Jacobi: the inverted 3x3
// diagonal blocks of A. Pinned particles drop out inside CG, since every host vector
// operation and Jacobian product acts on the active particles only and their entries of
// dv stay 0. A solve that stops at `max_iterations` (or meets p.Ap <= 0) before the
// tolerance is reported through clothlab.solver-statistics/1, never passed off as converged.
//
// Definiteness (`definite`, on by default). Two terms of the exact da/dx make A indefinite
// or unsymmetric once h is large (a folding flag at dt = 50 ms: CG breaks down, p.Ap <= 0,
// and the step explodes): a spring shorter than its rest length has the transverse
// stiffness -ks (1 - l0/l) (I - n n^T) > 0, and the damping force's x-derivative is not
// symmetric. As Baraff and Witkin (and Choi & Ko 2002 for compression), the matrix then
// keeps the springs' Hooke stiffness without that compressive term plus the damping's
// velocity derivative: the host's clothlab.definite-jacobian/1, one product per CG
// iteration. The Newton matrix changes, not the equation: still first order, and
// newton_steps > 1 still converges to backward Euler. `definite` = 0 uses the exact
// Jacobian (clothlab.jacobian/1).
//
// Warm start (`warm_start`, on by default): the first solve of a step starts from the
// previous step's dv, scaled by the ratio of the steps (dv ~ h a), instead of 0; the
// tolerance stays relative to the right-hand side, so a good guess saves iterations and
// never loosens the solve. It costs one product for the initial residual.
#include <clothlab/ext/integrator_traits.h>
#include <clothlab/ext/solver_statistics.h>

#include <algorithm>
#include <array>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>

#include "scratch_vectors.hpp"

namespace clothlab::builtin {

struct ImplicitEuler {
  static constexpr const char* id = "implicit_euler";
  static constexpr const char* name = "Implicit (backward) Euler, Baraff-Witkin";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Linearised backward Euler (Baraff & Witkin 1998), Newton steps solved by block-Jacobi "
      "preconditioned CG on Jacobian products; first order, unconditionally stable";
  static constexpr uint32_t order = 1;
  static constexpr uint32_t evals_per_step = 1;  // one more per Newton step beyond the first
  static constexpr uint32_t flags = CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
  static constexpr std::array<clothlab_param_spec, 5> params{
      sdk::real_param("tolerance", 1e-5, 1e-14, 1e-1, "",
                      "CG stops when the residual's mass norm falls below tolerance x the "
                      "right-hand side's"),
      sdk::int_param("max_iterations", 1000, 1, 100000,
                     "CG iterations per linear solve at most; a solve that hits it is reported"),
      sdk::int_param("newton_steps", 1, 1, 50,
                     "Newton steps per time step: 1 = Baraff-Witkin, more converge to backward "
                     "Euler on the nonlinear springs"),
      sdk::bool_param("definite", true,
                      "Baraff-Witkin's definite matrix: no compressive transverse stiffness, no "
                      "damping x-derivative; 0 = the exact Jacobian"),
      sdk::bool_param("warm_start", true,
                      "CG starts from the previous step's dv (scaled by the step ratio); 0 = "
                      "from 0"),
  };
  static constexpr clothlab_integrator_traits traits{
      sizeof(clothlab_integrator_traits),
      CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE | CLOTHLAB_TRAIT_ITERATIVE, nullptr, "max_iterations"};

  explicit ImplicitEuler(const sdk::Params& values)
      : tolerance_(values.real("tolerance")),
        max_iterations_(values.integer("max_iterations")),
        newton_steps_(values.integer("newton_steps")),
        definite_(values.flag("definite")),
        warm_start_(values.flag("warm_start")) {}

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    system.jacobian().reserve();
    // Checked here, so a host without them fails in prepare.
    if (definite_) (void)system.definite_jacobian();
    (void)system.reductions();
    scratch_.allocate(system);
    inverse_blocks_.assign(9 * size_t{system.particle_count()}, 0.0);
    previous_h_ = 0.0;
    last_ = {};
  }

  template <class Real>
  void step(sdk::System<Real>& system, double t, double h) {
    const auto vectors = scratch_.bind(system);
    last_ = {sizeof(clothlab_solver_step_statistics), 1, 0, 0, 0.0};
    if (h == 0.0) return;
    Real *const acceleration = vectors[0], *const dv = vectors[1], *const rhs = vectors[2],
                *const delta = vectors[3], *const x1 = vectors[4], *const v1 = vectors[5],
                *const zero = vectors[6];
    const Solver<Real> solver{system, vectors, definite_};
    Real* x = system.x();
    Real* v = system.v();

    // Baraff-Witkin: b = h a0 + h^2 (da/dx) v0, A linearised at (x0, v0).
    system.acceleration(t, x, v, acceleration);
    apply_jacobian(solver, t, x, v, h * h, 0.0, v, rhs);
    system.template lincomb<1>(rhs, rhs, {h}, {acceleration});
    // Cleared until the step completes: a step that throws leaves no dv to start from.
    const double previous_h = std::exchange(previous_h_, 0.0);
    const bool warm = warm_start_ && previous_h > 0.0;
    if (warm) {
      system.template lincomb<1>(dv, zero, {h / previous_h}, {dv});
    } else {
      system.copy(dv, zero);
    }
    solve(solver, t, h, x, v, rhs, dv, warm);

    for (long newton = 1; newton < newton_steps_; ++newton) {
      // Whole copies first: the pinned particles' entries of the iterate are theirs.
      system.copy(v1, v);
      system.axpy(v1, 1.0, dv);
      system.copy(x1, x);
      system.axpy(x1, h, v1);
      system.acceleration(t + h, x1, v1, acceleration);
      system.template lincomb<2>(rhs, zero, {h, -1.0}, {acceleration, dv});
      system.copy(delta, zero);
      solve(solver, t + h, h, x1, v1, rhs, delta, false);
      system.axpy(dv, 1.0, delta);
    }
    system.axpy(v, 1.0, dv);
    system.axpy(x, h, v);
    previous_h_ = h;
  }

  void last_step_statistics(clothlab_solver_step_statistics& out) const { out = last_; }

 private:
  // Scratch: acceleration, dv (kept from step to step for the warm start), rhs, delta, x1, v1,
  // zero (never written), then CG's r, z, p, q.
  static constexpr size_t step_vectors = 7;
  static constexpr size_t cg_vectors = 4;

  template <class Real>
  struct Solver {
    Solver(const sdk::System<Real>& system,
           const std::array<Real*, step_vectors + cg_vectors>& vectors, bool definite_form)
        : system(system),
          jacobian(system.jacobian()),
          definite(definite_form ? std::optional{system.definite_jacobian()} : std::nullopt),
          reductions(system.reductions()),
          zero(vectors[6]),
          r(vectors[step_vectors]),
          z(vectors[step_vectors + 1]),
          p(vectors[step_vectors + 2]),
          q(vectors[step_vectors + 3]) {}
    const sdk::System<Real>& system;
    sdk::Jacobian<Real> jacobian;
    std::optional<sdk::DefiniteJacobian<Real>> definite;  // with `definite` only
    sdk::Reductions<Real> reductions;
    const Real* zero;
    Real *r, *z, *p, *q;
  };

  // q = J u, J the exact Jacobian or (definite) the Baraff-Witkin matrix.
  template <class Real>
  void apply_jacobian(const Solver<Real>& s, double t, const Real* x, const Real* v, double c_x,
                      double c_v, const Real* u, Real* q) const {
    if (!definite_) return s.jacobian.apply(t, x, v, c_x, c_v, u, q);
    s.definite->apply(t, x, v, c_x, c_v, u, q);
  }

  // Solves (I - h da/dv - h^2 da/dx) at (x, v) times solution = rhs by block-Jacobi PCG in
  // the mass inner product, from the solution's entries (guess) or 0 (solution zeroed by the
  // caller); adds to last_.
  template <class Real>
  void solve(const Solver<Real>& s, double t, double h, const Real* x, const Real* v,
             const Real* rhs, Real* solution, bool guess) {
    const sdk::System<Real>& system = s.system;
    const double c_x = -h * h, c_v = -h;  // A u = u + J u with these weights
    invert_diagonal_blocks(s, t, x, v, c_x, c_v);

    if (guess) {  // r = rhs - A solution
      apply_jacobian(s, t, x, v, c_x, c_v, solution, s.q);
      system.template lincomb<2>(s.r, rhs, {-1.0, -1.0}, {solution, s.q});
    } else {
      system.copy(s.r, rhs);
    }
    const double rhs_norm = std::sqrt(s.reductions.mass_dot(rhs, rhs));
    double residual_norm = guess ? std::sqrt(s.reductions.mass_dot(s.r, s.r)) : rhs_norm;
    bool converged = residual_norm <= tolerance_ * rhs_norm;
    long iterations = 0;
    if (!converged) {
      precondition(system, s.r, s.z);
      system.copy(s.p, s.z);
      double rz = s.reductions.mass_dot(s.r, s.z);
      while (iterations < max_iterations_) {
        apply_jacobian(s, t, x, v, c_x, c_v, s.p, s.q);
        system.axpy(s.q, 1.0, s.p);
        const double pq = s.reductions.mass_dot(s.p, s.q);
        if (!std::isfinite(pq))
          throw sdk::Error(CLOTHLAB_ERROR_NUMERICAL, "CG met a non-finite p.Ap");
        if (pq <= 0.0) break;  // A indefinite along p: stop, reported as not converged
        const double alpha = rz / pq;
        system.axpy(solution, alpha, s.p);
        system.axpy(s.r, -alpha, s.q);
        ++iterations;
        residual_norm = std::sqrt(s.reductions.mass_dot(s.r, s.r));
        if (residual_norm <= tolerance_ * rhs_norm) {
          converged = true;
          break;
        }
        precondition(system, s.r, s.z);
        const double rz_next = s.reductions.mass_dot(s.r, s.z);
        system.template lincomb<1>(s.p, s.z, {rz_next / rz}, {s.p});
        rz = rz_next;
      }
    }
    last_.iterations += static_cast<uint64_t>(iterations);
    last_.converged = last_.converged && converged ? 1u : 0u;
    last_.residual = std::max(last_.residual, rhs_norm == 0.0 ? 0.0 : residual_norm / rhs_norm);
  }

  // inverse_blocks_ = inverses of the 3x3 diagonal blocks of A = I + c_x da/dx + c_v da/dv;
  // a block too close to singular (indefinite A) falls back to the identity.
  template <class Real>
  void invert_diagonal_blocks(const Solver<Real>& s, double t, const Real* x, const Real* v,
                              double c_x, double c_v) {
    if (definite_) {
      s.definite->diagonal_blocks(t, x, v, c_x, c_v, inverse_blocks_.data());
    } else {
      s.jacobian.diagonal_blocks(t, x, v, c_x, c_v, inverse_blocks_.data());
    }
    for (const clothlab_range& range : s.system.active())
      for (uint32_t i = range.begin; i < range.end; ++i) {
        double* b = &inverse_blocks_[9 * size_t{i}];
        b[0] += 1.0, b[4] += 1.0, b[8] += 1.0;
        const std::array<double, 9> cofactor{
            b[4] * b[8] - b[5] * b[7], b[2] * b[7] - b[1] * b[8], b[1] * b[5] - b[2] * b[4],
            b[5] * b[6] - b[3] * b[8], b[0] * b[8] - b[2] * b[6], b[2] * b[3] - b[0] * b[5],
            b[3] * b[7] - b[4] * b[6], b[1] * b[6] - b[0] * b[7], b[0] * b[4] - b[1] * b[3]};
        const double determinant = b[0] * cofactor[0] + b[1] * cofactor[3] + b[2] * cofactor[6];
        const double scale = std::max({std::abs(b[0]), std::abs(b[4]), std::abs(b[8])});
        if (!(std::abs(determinant) > 1e-12 * scale * scale * scale)) {
          std::fill(b, b + 9, 0.0);
          b[0] = b[4] = b[8] = 1.0;
          continue;
        }
        for (int k = 0; k < 9; ++k) b[k] = cofactor[k] / determinant;
      }
  }

  // z = blockdiag(A)^-1 r on the active particles.
  template <class Real>
  void precondition(const sdk::System<Real>& system, const Real* r, Real* z) const {
    const size_t stride = system.stride();
    for (const clothlab_range& range : system.active())
      for (uint32_t i = range.begin; i < range.end; ++i) {
        const double* b = &inverse_blocks_[9 * size_t{i}];
        const double r0 = r[i], r1 = r[stride + i], r2 = r[2 * stride + i];
        z[i] = static_cast<Real>(b[0] * r0 + b[1] * r1 + b[2] * r2);
        z[stride + i] = static_cast<Real>(b[3] * r0 + b[4] * r1 + b[5] * r2);
        z[2 * stride + i] = static_cast<Real>(b[6] * r0 + b[7] * r1 + b[8] * r2);
      }
  }

  double tolerance_;
  long max_iterations_;
  long newton_steps_;
  bool definite_;
  bool warm_start_;
  double previous_h_ = 0.0;  // the last step's h; 0: no dv to start from
  ScratchVectors<step_vectors + cg_vectors> scratch_;
  std::vector<double> inverse_blocks_;  // 9 n, row-major 3x3 per particle
  clothlab_solver_step_statistics last_{};
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-implicit-euler", "1.0.0",
                      clothlab::sdk::integrators<clothlab::builtin::ImplicitEuler>,
                      clothlab::sdk::scenarios<>)
