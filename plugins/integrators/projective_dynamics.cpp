// Projective dynamics / fast mass-spring (Liu et al. 2013; Bouaziz et al. 2014): backward
// Euler on the springs as the minimisation of
//   1/(2 h^2) |x - y|_M^2 + sum_s ks_s/2 |x_i - x_j - d_s|^2,   y = x0 + h v0 + h^2 a_ext(x0),
// over positions x and spring vectors d_s of rest length. Alternating, for `iterations`:
//   local:  d_s = rest_s (x_i - x_j) / |x_i - x_j|    (each spring projected to its rest length)
//   global: (M + h D + h^2 K) x = M y + h D x0 + h^2 sum_s ks_s A_s^T d_s + h c(x)
// with K (and D) the spring graph's Laplacian weighted by ks (and kd), the same matrix for x,
// y and z. Converged, this is backward Euler on the same springs and the same damping as
// eval_acceleration (below), the step implicit_euler converges to with more Newton steps;
// each iteration lowers the energy, so few iterations give a damped but stable step.
// On stiff cloth the iteration contracts slowly (a spectral radius near 1); `chebyshev_rho`
// > 0 accelerates it (Wang 2015, chebyshev_weights.hpp): after `chebyshev_delay` plain
// iterations each new iterate is extrapolated from the two before it. lab/real-cloth.md
// ("Chebyshev acceleration") has the counts and how to estimate rho.
//
// Damping: eval_acceleration damps each spring along its direction n only,
// -kd n n^T (v_i - v_j). In the matrix it enters isotropically, as h D (-kd (v_i - v_j)),
// which keeps the matrix constant; the local step hands back what the isotropic term damps
// across the spring, c = sum_s kd_s A_s^T (I - n n^T) A_s (x - x0), with n and x from the
// current iterate. The matrix dominates that correction (D >= the transverse part), so the
// iteration still converges, to damping along n alone. External forces (gravity, wind)
// come from clothlab.external-forces/1 at x0, explicitly.
//
// Pinned particles are eliminated: the unknowns are the active particles, numbered in the
// fill-reducing (AMD) order computed once in `prepare`, so the factorisation works in natural
// order with no permuted copy, and its factors solve all three coordinates in one sweep. The
// parameter `factorization` picks the global solve: 0, Eigen's SimplicialLDLT
// (simplicial_ldlt_factorization.hpp), 1, SuiteSparse CHOLMOD's supernodal LL^T
// (cholmod_factorization.hpp), 2, no factorisation but geometric multigrid on the cloth's grid
// (clothlab.grid/1; multigrid_global_solve.hpp): V-cycles from the previous iterate to
// `multigrid_tolerance` relative to the residual of the step's start positions, with storage and
// setup linear in the particles (unknowns then in the particles' order); lab/performance.md
// compares the three. A multigrid solve that stops at `multigrid_max_cycles` first is reported
// through clothlab.solver-statistics/1 (converged 0). The matrix is factored (or the hierarchy
// built) on the first step and again only when h changes (stiffness and pins are fixed while a
// system lives; `prepare` starts over). A matrix that is not positive definite (a negative
// stiffness) is a numerical error naming the pivot. `step` solves into preallocated vectors and
// does not allocate, except in a factorisation with CHOLMOD (its update workspace) or with Eigen
// above 16384 active particles (see SimplicialLdltFactorization). The factorisation is double in
// both precisions: states are converted at the boundary.
#include <clothlab/ext/integrator_traits.h>
#include <clothlab/ext/solver_statistics.h>

#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <clothlab/sdk.hpp>
#include <clothlab/sdk/threads.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "chebyshev_weights.hpp"
#include "cholmod_factorization.hpp"
#include "multigrid_global_solve.hpp"
#include "multigrid_grid.hpp"
#include "projective_dynamics_matrix.hpp"
#include "scratch_vectors.hpp"
#include "simplicial_ldlt_factorization.hpp"

namespace clothlab::builtin {

struct ProjectiveDynamics {
  static constexpr const char* id = "projective_dynamics";
  static constexpr const char* name = "Projective dynamics (fast mass-spring)";
  static constexpr const char* version = "1.1.0";
  static constexpr const char* description =
      "Local/global projective dynamics (Liu et al. 2013) on the springs with a prefactored "
      "(M + h D + h^2 K) or a multigrid global solve; first order when converged, "
      "unconditionally stable";
  static constexpr uint32_t order = 1;
  static constexpr uint32_t evals_per_step = 0;  // springs are its own; external forces only
  static constexpr uint32_t flags = 0;
  static constexpr std::array<clothlab_param_spec, 8> params{
      sdk::int_param("iterations", 10, 1, 1000,
                     "local/global iterations per step (one global solve each)"),
      sdk::int_param("factorization", 0, 0, 2,
                     "the constant matrix's global solve: 0 = Eigen SimplicialLDLT, "
                     "1 = SuiteSparse CHOLMOD supernodal, 2 = no factorisation: multigrid "
                     "V-cycles on the cloth's grid (clothlab.grid/1) to multigrid_tolerance"),
      sdk::real_param("multigrid_tolerance", kDefaultGlobalSolveTolerance, 1e-14, 1e-1, "",
                      "factorization 2: V-cycles from the previous iterate until |b - A x| <= "
                      "this x |b - A x0|, x0 the step's start positions"),
      sdk::int_param("multigrid_max_cycles", kDefaultGlobalSolveMaxCycles, 1, 10000,
                     "factorization 2: V-cycles per global solve at most; a solve that hits it "
                     "is reported"),
      sdk::int_param("multigrid_coarsest", kDefaultCoarsestNodes, 1, kMaxCoarsestNodes,
                     "factorization 2: coarsen the grid while it has more particles than this "
                     "(and both sides at least 3); a dense direct solve there"),
      sdk::int_param("multigrid_sweeps", kDefaultMultigridSweeps, 1, 8,
                     "factorization 2: coloured block Gauss-Seidel sweeps before and after each "
                     "coarse correction"),
      sdk::real_param("chebyshev_rho", 0.0, 0.0, 0.9999, "",
                      "Chebyshev acceleration of the iterations (Wang 2015): the estimated "
                      "spectral radius of one local/global iteration; 0 = off"),
      sdk::int_param("chebyshev_delay", 10, 1, 1000,
                     "plain iterations before Chebyshev acceleration starts"),
  };
  static constexpr clothlab_integrator_traits traits{
      sizeof(clothlab_integrator_traits),
      CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE | CLOTHLAB_TRAIT_ITERATIVE |
          CLOTHLAB_TRAIT_RESOLVES_CONTACTS | CLOTHLAB_TRAIT_MOVES_ATTACHMENTS,
      nullptr, "iterations"};

  explicit ProjectiveDynamics(const sdk::Params& values)
      : iterations_(values.integer("iterations")),
        solve_(static_cast<GlobalSolve>(values.integer("factorization"))),
        multigrid_tolerance_(values.real("multigrid_tolerance")),
        multigrid_max_cycles_(values.integer("multigrid_max_cycles")),
        multigrid_coarsest_(values.integer("multigrid_coarsest")),
        multigrid_sweeps_(values.integer("multigrid_sweeps")),
        chebyshev_(values.real("chebyshev_rho"), values.integer("chebyshev_delay")) {}

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    const sdk::Topology topology = system.topology();
    (void)system.external_forces();  // checked here, so a host without it fails in prepare
    scratch_.allocate(system);
    multigrid_.reset();
    assemble(system, topology);
    factored_h_ = std::numeric_limits<double>::quiet_NaN();
    last_ = {};
  }

  template <class Real>
  void step(sdk::System<Real>& system, double t, double h) {
    const auto [external] = scratch_.bind(system);
    last_ = {sizeof(clothlab_solver_step_statistics), 1, 0, 0, 0.0};
    if (h == 0.0) return;
    if (h != factored_h_) factor(h);

    const size_t stride = system.stride();
    Real* x = system.x();
    Real* v = system.v();
    // Implicit in the positions: the global solves hold the attachments at the step's end.
    system.move_attachments(t + h);
    system.external_forces().acceleration(t, x, external);
    for (uint32_t i = 0; i < matrix_.unknown_of().size(); ++i) {
      const int32_t u = matrix_.unknown_of()[i];
      for (size_t k = 0; k < 3; ++k) {
        const size_t j = k * stride + i;
        if (u < 0) {
          pinned_position_[3 * size_t{i} + k] = x[j];
          continue;
        }
        start_(u, k) = x[j];
        inertial_(u, k) = x[j] + h * v[j] + h * h * external[j];
      }
    }
    // The part of the right-hand side fixed over the step: M y + h D x0 + h^2 K_pinned x_pinned.
    fixed_rhs_.noalias() = damping_ * start_;
    fixed_rhs_ *= h;
    for (Eigen::Index u = 0; u < fixed_rhs_.rows(); ++u)
      fixed_rhs_.row(u) += matrix_.mass()[u] * inertial_.row(u);
    for (const PinnedSpring& spring : pinned_springs_)
      for (size_t k = 0; k < 3; ++k)
        fixed_rhs_(spring.unknown, k) +=
            h * h * spring.ks * pinned_position_[3 * size_t{spring.pinned} + k];

    positions_ = inertial_;
    chebyshev_.restart();
    for (long iteration = 0; iteration < iterations_; ++iteration) {
      rhs_ = fixed_rhs_;
      project_springs(h);
      if (chebyshev_.active()) older_.swap(previous_);  // older_ = the iterate before this one
      if (chebyshev_.active() || iteration + 1 == iterations_) previous_ = positions_;
      solve(rhs_, positions_);
      const double omega = chebyshev_.next();
      if (omega != 1.0) positions_ = omega * (positions_ - older_) + older_;
    }
    const double moved = max_difference(positions_, start_);
    const double change = max_difference(positions_, previous_);
    if (!std::isfinite(change)) throw sdk::Error(CLOTHLAB_ERROR_NUMERICAL, "non-finite positions");
    last_.iterations = static_cast<uint64_t>(iterations_);
    last_.residual = moved > 0.0 ? change / moved : 0.0;

    for (uint32_t i = 0; i < matrix_.unknown_of().size(); ++i) {
      const int32_t u = matrix_.unknown_of()[i];
      if (u < 0) continue;
      for (size_t k = 0; k < 3; ++k) {
        x[k * stride + i] = static_cast<Real>(positions_(u, k));
        v[k * stride + i] = static_cast<Real>((positions_(u, k) - start_(u, k)) / h);
      }
    }
    system.resolve_contacts(t + h);
  }

  void last_step_statistics(clothlab_solver_step_statistics& out) const { out = last_; }

 private:
  using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  // One row per unknown: a particle's x, y, z side by side for the 3-wide solves.
  using Positions = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

  // A spring with one end pinned: its pull toward the pinned end is constant over a step.
  struct PinnedSpring {
    int32_t unknown;
    uint32_t pinned;
    double ks;
  };
  // A spring with at least one active end, ends as unknowns (-1 for a pinned end).
  struct Spring {
    int32_t first, second;
    uint32_t first_particle, second_particle;
    double rest_length, ks, kd;
  };

  // The constant matrix (projective_dynamics_matrix.hpp), the spring lists and every step
  // buffer.
  template <class Real>
  void assemble(const sdk::System<Real>& system, const sdk::Topology& topology) {
    const bool multigrid = solve_ == GlobalSolve::kMultigrid;
    // Checked before the matrix is built, so a scene without a grid fails fast.
    const std::vector<GridSize> levels =
        multigrid ? plan_grid_levels(system, multigrid_coarsest_, "factorization = 2")
                  : std::vector<GridSize>{};
    if (multigrid)
      check_spring_reach(system, static_cast<long>(levels[0].cols), "factorization = 2");
    matrix_.build(system, topology,
                  multigrid ? ProjectiveDynamicsMatrix::Order::kParticles
                            : ProjectiveDynamicsMatrix::Order::kFillReducing);
    const std::vector<int32_t>& unknown_of = matrix_.unknown_of();
    springs_.clear();
    pinned_springs_.clear();
    for (uint32_t s = 0; s < topology.spring_count(); ++s) {
      const uint32_t i = topology.first()[s], j = topology.second()[s];
      const int32_t a = unknown_of[i], b = unknown_of[j];
      if (a < 0 && b < 0) continue;
      const double ks = topology.ks()[s], kd = topology.kd()[s];
      springs_.push_back({a, b, i, j, topology.rest_length()[s], ks, kd});
      if (a < 0 || b < 0) pinned_springs_.push_back({a >= 0 ? a : b, a >= 0 ? j : i, ks});
    }
    damping_ = matrix_.damping_upper().selfadjointView<Eigen::Upper>();
    system_matrix_ = matrix_.pattern();
    if (solve_ == GlobalSolve::kCholmod) cholmod_.analyze(system_matrix_);
    if (solve_ == GlobalSolve::kLdlt) ldlt_.analyze(system_matrix_);
    if (multigrid) {
      multigrid_.emplace(levels, fixed_particles(system), matrix_.node_of(), multigrid_sweeps_,
                         multigrid_tolerance_, multigrid_max_cycles_,
                         sdk::plugin_threads(system, 0, true));
    }

    pinned_position_.assign(3 * unknown_of.size(), 0.0);
    for (Positions* buffer :
         {&start_, &inertial_, &fixed_rhs_, &rhs_, &positions_, &previous_, &older_})
      buffer->setZero(matrix_.unknowns(), 3);
  }

  // System matrix M + h D + h^2 K, entry by entry in the shared pattern, then factored (or
  // the multigrid hierarchy built on it).
  void factor(double h) {
    matrix_.combine(h, system_matrix_);
    std::string failure;
    switch (solve_) {
      case GlobalSolve::kLdlt:
        failure = ldlt_.factorize(system_matrix_);
        break;
      case GlobalSolve::kCholmod:
        failure = cholmod_.factorize(system_matrix_);
        break;
      case GlobalSolve::kMultigrid:
        failure = multigrid_->factorize(system_matrix_);
        break;
    }
    if (!failure.empty())
      throw sdk::Error(CLOTHLAB_ERROR_NUMERICAL, "factorising M + h D + h^2 K (h = " +
                                                     std::to_string(h) + ") failed: " + failure);
    factored_h_ = h;
    ++last_.factorizations;
  }

  // positions = (M + h D + h^2 K)^-1 rhs, the three coordinates at once; the multigrid
  // starts from positions' current iterate, measures its tolerance against the step's start
  // and records a solve that misses it.
  void solve(const Positions& rhs, Positions& positions) {
    if (solve_ == GlobalSolve::kMultigrid) {
      const MultigridGlobalSolve::Outcome outcome =
          multigrid_->solve(rhs.data(), start_.data(), positions.data());
      if (!outcome.converged) last_.converged = 0;
      return;
    }
    positions = rhs;
    if (solve_ == GlobalSolve::kCholmod)
      cholmod_.solve_in_place(positions.data());
    else
      ldlt_.solve_in_place(positions.data());
  }

  // rhs_ += h^2 sum_s ks_s A_s^T d_s, d_s the spring's current vector at its rest length,
  // and h c: the isotropic damping's part across each spring, handed back (see the top).
  void project_springs(double h) {
    for (const Spring& s : springs_) {
      std::array<double, 3> d{}, moved{};
      for (size_t k = 0; k < 3; ++k) {
        d[k] = end_position(s.first, s.first_particle, k) -
               end_position(s.second, s.second_particle, k);
        moved[k] = end_motion(s.first, k) - end_motion(s.second, k);
      }
      const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      // A spring of zero length has no direction: it keeps its (zero) vector and is damped
      // isotropically.
      const double scale = length > 0.0 ? h * h * s.ks * s.rest_length / length : 0.0;
      const double along =
          length > 0.0 ? (d[0] * moved[0] + d[1] * moved[1] + d[2] * moved[2]) / (length * length)
                       : 0.0;
      for (size_t k = 0; k < 3; ++k) {
        const double change = scale * d[k] + h * s.kd * (moved[k] - along * d[k]);
        if (s.first >= 0) rhs_(s.first, k) += change;
        if (s.second >= 0) rhs_(s.second, k) -= change;
      }
    }
  }

  // max |a - b| over all entries, NaN if any is NaN; a plain loop because GCC 12 warns
  // (falsely) inside Eigen's AVX-512 maxCoeff.
  static double max_difference(const Positions& a, const Positions& b) {
    double largest = 0.0;
    for (Eigen::Index k = 0; k < a.size(); ++k) {
      const double difference = std::abs(a.data()[k] - b.data()[k]);
      if (std::isnan(difference)) return difference;
      largest = std::max(largest, difference);
    }
    return largest;
  }

  double end_position(int32_t unknown, uint32_t particle, size_t k) const {
    return unknown >= 0 ? positions_(unknown, k) : pinned_position_[3 * size_t{particle} + k];
  }
  // x - x0 of a spring's end over the step so far (a pinned end does not move).
  double end_motion(int32_t unknown, size_t k) const {
    return unknown >= 0 ? positions_(unknown, k) - start_(unknown, k) : 0.0;
  }

  // The global solve, as the parameter `factorization` numbers it.
  enum class GlobalSolve : long { kLdlt = 0, kCholmod = 1, kMultigrid = 2 };

  long iterations_;
  GlobalSolve solve_;
  double multigrid_tolerance_;
  long multigrid_max_cycles_;
  long multigrid_coarsest_;
  long multigrid_sweeps_;
  ScratchVectors<1> scratch_;  // the external acceleration
  ProjectiveDynamicsMatrix matrix_;
  std::vector<Spring> springs_;
  std::vector<PinnedSpring> pinned_springs_;
  std::vector<double> pinned_position_;  // 3 n, particle-major; pinned entries only
  Matrix system_matrix_;
  Matrix damping_;  // D in full, for D x0
  SimplicialLdltFactorization ldlt_;
  CholmodFactorization cholmod_;
  std::optional<MultigridGlobalSolve> multigrid_;  // where solve_ is kMultigrid
  double factored_h_ = std::numeric_limits<double>::quiet_NaN();
  ChebyshevWeights chebyshev_;
  // previous_: the iterate the last solve started from; older_: the one before it (Chebyshev).
  Positions start_, inertial_, fixed_rhs_, rhs_, positions_, previous_, older_;
  clothlab_solver_step_statistics last_{};
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-projective-dynamics", "1.1.0",
                      clothlab::sdk::integrators<clothlab::builtin::ProjectiveDynamics>,
                      clothlab::sdk::scenarios<>)
