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
// fill-reducing (AMD) order computed once in `prepare`, so Eigen's SimplicialLDLT factors
// the matrix in natural order with no permuted copy (and its factors solve all three
// coordinates in one sweep). The matrix is factored on the first step and again only when h
// changes (stiffness and pins are fixed while a system lives;
// `prepare` starts over); `step` solves into preallocated vectors and does not allocate
// (except a refactorisation above 16384 active particles: see PreorderedLDLT).
// The factorisation is double in both precisions: states are converted at the boundary.
#include <clothlab/ext/integrator_traits.h>
#include <clothlab/ext/solver_statistics.h>

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "scratch_vectors.hpp"

namespace clothlab::builtin {

struct ProjectiveDynamics {
  static constexpr const char* id = "projective_dynamics";
  static constexpr const char* name = "Projective dynamics (fast mass-spring)";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Local/global projective dynamics (Liu et al. 2013) on the springs with a prefactored "
      "(M + h D + h^2 K); first order when converged, unconditionally stable";
  static constexpr uint32_t order = 1;
  static constexpr uint32_t evals_per_step = 0;  // springs are its own; external forces only
  static constexpr uint32_t flags = 0;
  static constexpr std::array<clothlab_param_spec, 1> params{
      sdk::int_param("iterations", 10, 1, 1000,
                     "local/global iterations per step (one back-substitution each)"),
  };
  static constexpr clothlab_integrator_traits traits{
      sizeof(clothlab_integrator_traits),
      CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE | CLOTHLAB_TRAIT_ITERATIVE |
          CLOTHLAB_TRAIT_RESOLVES_CONTACTS | CLOTHLAB_TRAIT_MOVES_ATTACHMENTS,
      nullptr, "iterations"};

  explicit ProjectiveDynamics(const sdk::Params& values)
      : iterations_(values.integer("iterations")) {}

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    const sdk::Topology topology = system.topology();
    (void)system.external_forces();  // checked here, so a host without it fails in prepare
    scratch_.allocate(system);
    number_unknowns(system, topology);
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
    for (uint32_t i = 0; i < unknown_of_.size(); ++i) {
      const int32_t u = unknown_of_[i];
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
      fixed_rhs_.row(u) += mass_[u] * inertial_.row(u);
    for (const PinnedSpring& spring : pinned_springs_)
      for (size_t k = 0; k < 3; ++k)
        fixed_rhs_(spring.unknown, k) +=
            h * h * spring.ks * pinned_position_[3 * size_t{spring.pinned} + k];

    positions_ = inertial_;
    for (long iteration = 0; iteration < iterations_; ++iteration) {
      rhs_ = fixed_rhs_;
      project_springs(h);
      if (iteration + 1 == iterations_) previous_ = positions_;
      positions_ = rhs_;
      solve_in_place(positions_);
    }
    const double moved = max_difference(positions_, start_);
    const double change = max_difference(positions_, previous_);
    if (!std::isfinite(change)) throw sdk::Error(CLOTHLAB_ERROR_NUMERICAL, "non-finite positions");
    last_.iterations = static_cast<uint64_t>(iterations_);
    last_.residual = moved > 0.0 ? change / moved : 0.0;

    for (uint32_t i = 0; i < unknown_of_.size(); ++i) {
      const int32_t u = unknown_of_[i];
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

  // SimplicialLDLT's numeric factorisation of an upper triangle already in elimination
  // order. Its public factorize() first builds a (here identical) reordered copy, which
  // allocates; factorize_preordered, the step it then runs, is protected, hence the
  // subclass. That step's workspace (3 arrays of n) is on the stack up to Eigen's
  // EIGEN_STACK_ALLOCATION_LIMIT (16384 unknowns), on the heap above it.
  class PreorderedLDLT
      : public Eigen::SimplicialLDLT<Matrix, Eigen::Upper, Eigen::NaturalOrdering<int>> {
   public:
    // The symbolic analysis, and the diagonal's storage, which the first factorisation
    // would otherwise allocate.
    void analyze(const Matrix& upper) {
      this->analyzePattern(upper);
      this->m_diag.resize(upper.rows());
    }
    void refactorize(const Matrix& upper) { this->template factorize_preordered<true>(upper); }
    // The factors by reference (matrixL() is a view, but vectorD() returns a copy).
    const Matrix& lower() const { return this->m_matrix; }
    const Eigen::VectorXd& diagonal() const { return this->m_diag; }
  };

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

  // unknown_of_[particle] = its row in the global system in AMD order, -1 when pinned.
  template <class Real>
  void number_unknowns(const sdk::System<Real>& system, const sdk::Topology& topology) {
    const uint32_t n = system.particle_count();
    std::vector<int32_t> natural(n, -1);
    int32_t count = 0;
    for (const clothlab_range& range : system.active())
      for (uint32_t i = range.begin; i < range.end; ++i) natural[i] = count++;
    std::vector<Eigen::Triplet<double, int>> entries;
    for (int32_t u = 0; u < count; ++u) entries.emplace_back(u, u, 1.0);
    for (uint32_t s = 0; s < topology.spring_count(); ++s) {
      const int32_t a = natural[topology.first()[s]], b = natural[topology.second()[s]];
      if (a < 0 || b < 0) continue;
      entries.emplace_back(a, b, 1.0);
      entries.emplace_back(b, a, 1.0);
    }
    Matrix graph(count, count);
    graph.setFromTriplets(entries.begin(), entries.end());
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> elimination_order;
    Eigen::AMDOrdering<int>()(graph, elimination_order);
    // AMD returns the elimination order; row u of the reordered system is the unknown
    // eliminated u-th (as SimplicialLDLT applies it: P = order^-1).
    const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> new_row =
        elimination_order.inverse();
    unknown_of_.assign(n, -1);
    for (uint32_t i = 0; i < n; ++i)
      if (natural[i] >= 0) unknown_of_[i] = new_row.indices()[natural[i]];
  }

  // M, D and K over the unknowns, upper triangle, one sparsity pattern for all three (so
  // M + h D + h^2 K is formed value by value), the spring lists and every step buffer.
  template <class Real>
  void assemble(const sdk::System<Real>& system, const sdk::Topology& topology) {
    const auto count = static_cast<Eigen::Index>(
        std::count_if(unknown_of_.begin(), unknown_of_.end(), [](int32_t u) { return u >= 0; }));
    mass_.assign(static_cast<size_t>(count), 0.0);
    for (uint32_t i = 0; i < unknown_of_.size(); ++i)
      if (unknown_of_[i] >= 0) mass_[unknown_of_[i]] = 1.0 / system.inverse_mass()[i];

    struct Entry {
      int32_t row, col;
      double mass, kd, ks;
    };
    std::vector<Entry> entries;
    for (Eigen::Index u = 0; u < count; ++u)
      entries.push_back({static_cast<int32_t>(u), static_cast<int32_t>(u), mass_[u], 0, 0});
    springs_.clear();
    pinned_springs_.clear();
    for (uint32_t s = 0; s < topology.spring_count(); ++s) {
      const uint32_t i = topology.first()[s], j = topology.second()[s];
      const int32_t a = unknown_of_[i], b = unknown_of_[j];
      if (a < 0 && b < 0) continue;
      const double ks = topology.ks()[s], kd = topology.kd()[s];
      springs_.push_back({a, b, i, j, topology.rest_length()[s], ks, kd});
      if (a >= 0) entries.push_back({a, a, 0, kd, ks});
      if (b >= 0) entries.push_back({b, b, 0, kd, ks});
      if (a >= 0 && b >= 0)
        entries.push_back({std::min(a, b), std::max(a, b), 0, -kd, -ks});
      else
        pinned_springs_.push_back({a >= 0 ? a : b, a >= 0 ? j : i, ks});
    }
    const auto upper = [&](double Entry::*field) {
      std::vector<Eigen::Triplet<double, int>> triplets;
      triplets.reserve(entries.size());
      for (const Entry& e : entries) triplets.emplace_back(e.row, e.col, e.*field);
      Matrix matrix(count, count);
      matrix.setFromTriplets(triplets.begin(), triplets.end());  // keeps explicit zeros
      return matrix;
    };
    mass_matrix_ = upper(&Entry::mass);
    damping_upper_ = upper(&Entry::kd);
    stiffness_ = upper(&Entry::ks);
    damping_ = damping_upper_.selfadjointView<Eigen::Upper>();
    system_matrix_ = mass_matrix_;
    factorization_.analyze(system_matrix_);

    pinned_position_.assign(3 * unknown_of_.size(), 0.0);
    for (Positions* buffer : {&start_, &inertial_, &fixed_rhs_, &rhs_, &positions_, &previous_})
      buffer->setZero(count, 3);
  }

  // System matrix M + h D + h^2 K, entry by entry in the shared pattern, then factored.
  void factor(double h) {
    const Eigen::Index nonzeros = system_matrix_.nonZeros();
    double* values = system_matrix_.valuePtr();
    for (Eigen::Index k = 0; k < nonzeros; ++k)
      values[k] = mass_matrix_.valuePtr()[k] + h * damping_upper_.valuePtr()[k] +
                  h * h * stiffness_.valuePtr()[k];
    factorization_.refactorize(system_matrix_);
    if (factorization_.info() != Eigen::Success)
      throw sdk::Error(CLOTHLAB_ERROR_NUMERICAL, "factorising M + h D + h^2 K failed");
    factored_h_ = h;
    ++last_.factorizations;
  }

  // x = (L D L^T)^-1 x with the factors of SimplicialLDLT, all three columns in one sweep
  // over L each way (Eigen's solve sweeps L once per column, three times the memory traffic).
  void solve_in_place(Positions& positions) const {
    const Matrix& lower = factorization_.lower();
    const Eigen::VectorXd& diagonal = factorization_.diagonal();
    const int* column_start = lower.outerIndexPtr();
    const int* row = lower.innerIndexPtr();
    const double* value = lower.valuePtr();
    double* x = positions.data();
    const auto count = static_cast<int>(lower.cols());
    for (int j = 0; j < count; ++j) {  // L y = b, L unit lower triangular
      const double x0 = x[3 * j], x1 = x[3 * j + 1], x2 = x[3 * j + 2];
      for (int p = column_start[j]; p < column_start[j + 1]; ++p) {
        if (row[p] <= j) continue;  // the unit diagonal
        double* target = &x[3 * row[p]];
        target[0] -= value[p] * x0, target[1] -= value[p] * x1, target[2] -= value[p] * x2;
      }
    }
    for (int j = 0; j < count; ++j)
      for (int k = 0; k < 3; ++k) x[3 * j + k] /= diagonal[j];
    for (int j = count - 1; j >= 0; --j) {  // L^T x = y
      double x0 = x[3 * j], x1 = x[3 * j + 1], x2 = x[3 * j + 2];
      for (int p = column_start[j]; p < column_start[j + 1]; ++p) {
        if (row[p] <= j) continue;
        const double* source = &x[3 * row[p]];
        x0 -= value[p] * source[0], x1 -= value[p] * source[1], x2 -= value[p] * source[2];
      }
      x[3 * j] = x0, x[3 * j + 1] = x1, x[3 * j + 2] = x2;
    }
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

  long iterations_;
  ScratchVectors<1> scratch_;  // the external acceleration
  std::vector<int32_t> unknown_of_;
  std::vector<double> mass_;
  std::vector<Spring> springs_;
  std::vector<PinnedSpring> pinned_springs_;
  std::vector<double> pinned_position_;  // 3 n, particle-major; pinned entries only
  Matrix mass_matrix_, damping_upper_, stiffness_, system_matrix_;
  Matrix damping_;  // D in full, for D x0
  PreorderedLDLT factorization_;
  double factored_h_ = std::numeric_limits<double>::quiet_NaN();
  Positions start_, inertial_, fixed_rhs_, rhs_, positions_, previous_;
  clothlab_solver_step_statistics last_{};
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-projective-dynamics", "1.0.0",
                      clothlab::sdk::integrators<clothlab::builtin::ProjectiveDynamics>,
                      clothlab::sdk::scenarios<>)
