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
// Definiteness (`definite_springs`, on by default): a spring shorter than its rest length
// has the transverse stiffness -ks (1 - l0/l) (I - n n^T) > 0 in df/dx, which makes A
// indefinite once h^2 ks / m is large (a folding cloth at dt = 50 ms): CG breaks down and the
// step explodes. As in Choi & Ko (2002), that term is dropped from the matrix (and from the
// h^2 (da/dx) v0 of the right-hand side): the plugin subtracts it from the host's exact
// product for the springs it finds compressed at the linearisation state (topology
// extension). The Newton matrix changes, not the equation: still first order, and
// newton_steps > 1 still converges to backward Euler.
#include <clothlab/ext/integrator_traits.h>
#include <clothlab/ext/solver_statistics.h>

#include <algorithm>
#include <array>
#include <clothlab/sdk.hpp>
#include <cmath>
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
  static constexpr std::array<clothlab_param_spec, 4> params{
      sdk::real_param("tolerance", 1e-5, 1e-14, 1e-1, "",
                      "CG stops when the residual's mass norm falls below tolerance x the "
                      "right-hand side's"),
      sdk::int_param("max_iterations", 1000, 1, 100000,
                     "CG iterations per linear solve at most; a solve that hits it is reported"),
      sdk::int_param("newton_steps", 1, 1, 50,
                     "Newton steps per time step: 1 = Baraff-Witkin, more converge to backward "
                     "Euler on the nonlinear springs"),
      sdk::bool_param("definite_springs", true,
                      "drop compressed springs' transverse stiffness from the matrix (keeps it "
                      "positive definite); 0 = the exact Jacobian"),
  };
  static constexpr clothlab_integrator_traits traits{
      sizeof(clothlab_integrator_traits),
      CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE | CLOTHLAB_TRAIT_ITERATIVE, nullptr, "max_iterations"};

  explicit ImplicitEuler(const sdk::Params& values)
      : tolerance_(values.real("tolerance")),
        max_iterations_(values.integer("max_iterations")),
        newton_steps_(values.integer("newton_steps")),
        definite_springs_(values.flag("definite_springs")) {}

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    system.jacobian().reserve();
    (void)system.reductions();  // checked here, so a host without it fails in prepare
    scratch_.allocate(system);
    inverse_blocks_.assign(9 * size_t{system.particle_count()}, 0.0);
    springs_ = {};
    compressed_.clear();
    if (definite_springs_) {
      springs_ = system.topology().raw();
      compressed_.reserve(springs_.spring_count);  // filled per solve, never beyond
    }
    inverse_mass_.resize(system.particle_count());
    for (uint32_t i = 0; i < system.particle_count(); ++i)
      inverse_mass_[i] = system.inverse_mass()[i];
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
    const Solver<Real> solver{system, vectors};
    Real* x = system.x();
    Real* v = system.v();

    // Baraff-Witkin: b = h a0 + h^2 (da/dx) v0, A linearised at (x0, v0).
    system.acceleration(t, x, v, acceleration);
    find_compressed_springs(system, x);
    solver.jacobian.apply(t, x, v, h * h, 0.0, v, rhs);
    subtract_compressed_stiffness(system, h * h, v, rhs);
    system.template lincomb<1>(rhs, rhs, {h}, {acceleration});
    solve(solver, t, h, x, v, rhs, dv);

    for (long newton = 1; newton < newton_steps_; ++newton) {
      // Whole copies first: the pinned particles' entries of the iterate are theirs.
      system.copy(v1, v);
      system.axpy(v1, 1.0, dv);
      system.copy(x1, x);
      system.axpy(x1, h, v1);
      system.acceleration(t + h, x1, v1, acceleration);
      find_compressed_springs(system, x1);
      system.template lincomb<2>(rhs, zero, {h, -1.0}, {acceleration, dv});
      solve(solver, t + h, h, x1, v1, rhs, delta);
      system.axpy(dv, 1.0, delta);
    }
    system.axpy(v, 1.0, dv);
    system.axpy(x, h, v);
  }

  void last_step_statistics(clothlab_solver_step_statistics& out) const { out = last_; }

 private:
  // Scratch: acceleration, dv, rhs, delta, x1, v1, zero (never written), then CG's r, z, p, q.
  static constexpr size_t step_vectors = 7;
  static constexpr size_t cg_vectors = 4;

  template <class Real>
  struct Solver {
    Solver(const sdk::System<Real>& system,
           const std::array<Real*, step_vectors + cg_vectors>& vectors)
        : system(system),
          jacobian(system.jacobian()),
          reductions(system.reductions()),
          zero(vectors[6]),
          r(vectors[step_vectors]),
          z(vectors[step_vectors + 1]),
          p(vectors[step_vectors + 2]),
          q(vectors[step_vectors + 3]) {}
    const sdk::System<Real>& system;
    sdk::Jacobian<Real> jacobian;
    sdk::Reductions<Real> reductions;
    const Real* zero;
    Real *r, *z, *p, *q;
  };

  // Solves (I - h da/dv - h^2 da/dx) at (x, v) times solution = rhs by block-Jacobi PCG in
  // the mass inner product, from solution = 0, with compressed_ found at x; adds to last_.
  template <class Real>
  void solve(const Solver<Real>& s, double t, double h, const Real* x, const Real* v,
             const Real* rhs, Real* solution) {
    const sdk::System<Real>& system = s.system;
    const double c_x = -h * h, c_v = -h;  // A u = u + J u with these weights
    invert_diagonal_blocks(s, t, x, v, c_x, c_v);

    system.copy(solution, s.zero);
    system.copy(s.r, rhs);
    const double rhs_norm = std::sqrt(s.reductions.mass_dot(rhs, rhs));
    double residual_norm = rhs_norm;
    bool converged = rhs_norm == 0.0;
    long iterations = 0;
    if (!converged) {
      precondition(system, s.r, s.z);
      system.copy(s.p, s.z);
      double rz = s.reductions.mass_dot(s.r, s.z);
      while (iterations < max_iterations_) {
        s.jacobian.apply(t, x, v, c_x, c_v, s.p, s.q);
        subtract_compressed_stiffness(system, c_x, s.p, s.q);
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
    s.jacobian.diagonal_blocks(t, x, v, c_x, c_v, inverse_blocks_.data());
    for (const CompressedSpring& spring : compressed_)
      for (const uint32_t end : {spring.first, spring.second}) {
        const double scale = c_x * spring.stiffness * inverse_mass_[end];
        double* b = &inverse_blocks_[9 * size_t{end}];
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c)
            b[3 * r + c] -=
                scale * ((r == c ? 1.0 : 0.0) - spring.direction[r] * spring.direction[c]);
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

  // compressed_ = the springs shorter than their rest length at x, with
  // ks (l0/l - 1) and their direction n; none when definite_springs is off.
  template <class Real>
  void find_compressed_springs(const sdk::System<Real>& system, const Real* x) {
    compressed_.clear();
    if (!definite_springs_) return;
    const size_t stride = system.stride();
    for (uint32_t k = 0; k < springs_.spring_count; ++k) {
      const uint32_t i = springs_.first[k], j = springs_.second[k];
      if (inverse_mass_[i] == 0.0 && inverse_mass_[j] == 0.0) continue;
      std::array<double, 3> d{};
      for (size_t c = 0; c < 3; ++c) d[c] = double{x[c * stride + i]} - double{x[c * stride + j]};
      const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      const double rest = springs_.rest_length[k];
      if (!(length < rest) || length == 0.0) continue;
      compressed_.push_back({i,
                             j,
                             springs_.ks[k] * (rest / length - 1.0),
                             {d[0] / length, d[1] / length, d[2] / length}});
    }
  }

  // out -= c_x (the compressed springs' transverse part of da/dx) u: for each, at its
  // active ends, (c_x ks (l0/l - 1) / m) (I - n n^T) (u_end - u_other). Pinned entries of u
  // count as 0, as in the host's product.
  template <class Real>
  void subtract_compressed_stiffness(const sdk::System<Real>& system, double c_x, const Real* u,
                                     Real* out) const {
    const size_t stride = system.stride();
    const auto entry = [&](uint32_t i, size_t c) {
      return inverse_mass_[i] == 0.0 ? 0.0 : double{u[c * stride + i]};
    };
    for (const CompressedSpring& spring : compressed_) {
      std::array<double, 3> du{};
      for (size_t c = 0; c < 3; ++c) du[c] = entry(spring.first, c) - entry(spring.second, c);
      const double along =
          spring.direction[0] * du[0] + spring.direction[1] * du[1] + spring.direction[2] * du[2];
      for (size_t c = 0; c < 3; ++c) {
        const double transverse = c_x * spring.stiffness * (du[c] - along * spring.direction[c]);
        if (inverse_mass_[spring.first] != 0.0)
          out[c * stride + spring.first] -=
              static_cast<Real>(transverse * inverse_mass_[spring.first]);
        if (inverse_mass_[spring.second] != 0.0)
          out[c * stride + spring.second] +=
              static_cast<Real>(transverse * inverse_mass_[spring.second]);
      }
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

  struct CompressedSpring {
    uint32_t first, second;
    double stiffness;                 // ks (l0/l - 1) > 0
    std::array<double, 3> direction;  // unit, first minus second
  };

  double tolerance_;
  long max_iterations_;
  long newton_steps_;
  bool definite_springs_;
  clothlab_topology springs_{};  // the host's arrays, when definite_springs
  std::vector<CompressedSpring> compressed_;
  std::vector<double> inverse_mass_;
  ScratchVectors<step_vectors + cg_vectors> scratch_;
  std::vector<double> inverse_blocks_;  // 9 n, row-major 3x3 per particle
  clothlab_solver_step_statistics last_{};
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-implicit-euler", "1.0.0",
                      clothlab::sdk::integrators<clothlab::builtin::ImplicitEuler>,
                      clothlab::sdk::scenarios<>)
