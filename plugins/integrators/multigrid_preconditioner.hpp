// implicit_euler's multigrid preconditioner: the V-cycle (multigrid_cycle.hpp) for the mass-
// weighted matrix S = M A of a solve A dv = b, A = I + J, on a cloth laid out as a grid
// (clothlab.grid/1, particle r * cols + c). CG runs in the mass inner product, so its
// preconditioner is z = B M r with B ~ S^-1 symmetric: self-adjoint in that product.
//
// S's blocks come from J's products, not from a host block table: the definite Jacobian has
// none, and probing gives whichever form CG solves with. Every spring joins particles at most
// two grid spacings apart (checked, multigrid_grid.hpp), so particles whose rows and columns are
// equal mod 5 share no neighbour: one product with e_d on all particles of such a class gives
// column d of every block coupling to them, 75 products in all. A single-precision system's blocks
// carry its rounding, so S is symmetrised ((S + S^T) / 2) and the V-cycle stays exactly symmetric;
// its V-cycle also smooths in single precision (multigrid_lanes.hpp), all its CG resolves.
// Pinned particles are the fine level's Dirichlet nodes.
//
// The fine level smooths matrix-free: Chebyshev iteration on block-Jacobi (D^-1 A, D the
// diagonal blocks of A), `sweeps` host products before the coarse correction and as many
// after, in the system's precision and layout. Its polynomial targets D^-1 A's eigenvalues in
// [lambda_max / kChebyshevRatio, lambda_max] (lambda_max a block Gershgorin bound from the
// fine blocks): the coarse levels take the rest. A product costs about an explicit step,
// where a Gauss-Seidel sweep over the stored fine blocks costs several; pre- and post-smoothing
// apply the same polynomial, so the V-cycle stays symmetric. On the cotton flag 2 + 2 such
// steps take as many CG iterations as 2 + 2 Gauss-Seidel sweeps. Coarser levels keep their
// Gauss-Seidel smoother (multigrid_smoother.hpp).
//
// Reuse: the set-up (probing, Galerkin products, factors) costs several CG iterations, so
// `prepare_solve` can keep the last hierarchy for up to `rebuild_interval` solves. CG's products
// still use the current matrix, so the answer is converged as before; a V-cycle of an older
// symmetric positive definite matrix is still a symmetric positive definite preconditioner, and
// only the iteration count changes (on cotton it grows by more than the set-up saves:
// lab/real-cloth.md, "Reusing the hierarchy over steps").
#pragma once

#include <algorithm>
#include <array>
#include <clothlab/sdk.hpp>
#include <clothlab/sdk/threads.hpp>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "multigrid_cycle.hpp"
#include "multigrid_grid.hpp"
#include "multigrid_hierarchy.hpp"

namespace clothlab::builtin {

class MultigridPreconditioner {
 public:
  // From `prepare`: one-line sdk::Error where the cloth is no grid, a spring reaches further
  // than two spacings, or the grid does not coarsen far enough (plan_levels).
  template <class Real>
  MultigridPreconditioner(const sdk::System<Real>& system, long coarsest_particles, long sweeps,
                          long rebuild_interval = 1)
      : rebuild_interval_(rebuild_interval),
        hierarchy_(plan_grid_levels(system, coarsest_particles, "multigrid = 1"),
                   fixed_particles(system), GridLevel::Blocks::single,
                   std::is_same_v<Real, float> ? LanePrecision::float32 : LanePrecision::float64),
        cycle_(hierarchy_, sweeps, sdk::plugin_threads(system, 0, true)),
        mass_(system.particle_count(), 0.0),
        sweeps_(sweeps),
        jacobi_(9 * std::size_t{system.particle_count()}, 0.0),
        fine_residual_(3 * std::size_t{system.particle_count()}, 0.0),
        fine_correction_(3 * std::size_t{system.particle_count()}, 0.0),
        probe_(system.alloc_vector()),
        probe_products_{system.alloc_vector(), system.alloc_vector(), system.alloc_vector()} {
    check_spring_reach(system, hierarchy_.level(0).cols(), "multigrid = 1");
    const Real* inverse_mass = system.inverse_mass();
    for (const clothlab_range& range : system.active())
      for (uint32_t i = range.begin; i < range.end; ++i) mass_[i] = 1.0 / inverse_mass[i];
    std::fill_n(static_cast<Real*>(probe_), 3 * std::size_t{system.stride()}, Real{0});
  }
  MultigridPreconditioner(const MultigridPreconditioner&) = delete;
  MultigridPreconditioner& operator=(const MultigridPreconditioner&) = delete;

  const MultigridHierarchy& hierarchy() const { return hierarchy_; }
  // The fine smoother's upper bound on D^-1 A's eigenvalues, from the last build (0 before, and
  // where the fine level is the coarsest).
  double lambda_max() const { return lambda_max_; }

  // Hierarchies built so far (each ends in a factorisation of the coarsest level).
  uint64_t rebuild_count() const { return rebuild_count_; }

  // Readies the V-cycle for a solve whose matrix has J's position weight c_x = -h^2: linearises
  // (see `linearise`) where there is no valid hierarchy, c_x changed since the last build (the
  // old matrix may then be far from the new one), or `rebuild_interval` solves used the last.
  template <class Real, class Product>
  void prepare_solve(const sdk::System<Real>& system, double c_x, Product&& product) {
    if (!valid_ || c_x != built_c_x_ || solves_since_rebuild_ >= rebuild_interval_) {
      valid_ = false;  // until linearise succeeds: a throw leaves no hierarchy to reuse
      linearise(system, product);
      valid_ = true, built_c_x_ = c_x, solves_since_rebuild_ = 0;
    }
    ++solves_since_rebuild_;
  }

  // Assembles S = M (I + J), J applied by product(u, out): out = J u, and rebuilds the levels.
  // A class's three products (one per component) come first, so that each block is written
  // whole, once: the fine level's blocks far exceed the caches.
  template <class Real, class Product>
  void linearise(const sdk::System<Real>& system, Product&& product) {
    GridLevel& fine = hierarchy_.level(0);
    fine.clear();
    Real* probe = static_cast<Real*>(probe_);
    const std::size_t stride = system.stride();
    std::array<const Real*, 3> out{};
    for (int color = 0; color < kProbePeriod * kProbePeriod; ++color) {
      for (int d = 0; d < 3; ++d) {
        set_probe(fine, color, probe + d * stride, Real{1});
        product(probe, static_cast<Real*>(probe_products_[d]));
        set_probe(fine, color, probe + d * stride, Real{0});
        out[d] = static_cast<const Real*>(probe_products_[d]);
      }
      for (int r = 0; r < fine.rows(); ++r) {
        const int r2 = r + offset_to(color / kProbePeriod, r);
        if (r2 < 0 || r2 >= fine.rows()) continue;
        for (int c = 0; c < fine.cols(); ++c) {
          const std::size_t i = fine.node(r, c);
          const int c2 = c + offset_to(color % kProbePeriod, c);
          if (fine.fixed(i) || c2 < 0 || c2 >= fine.cols() || fine.fixed(fine.node(r2, c2)))
            continue;
          double* block = fine.block(r, c, r2, c2);
          for (int k = 0; k < 3; ++k)
            for (int d = 0; d < 3; ++d) block[3 * k + d] = mass_[i] * out[d][k * stride + i];
        }
      }
    }
    for (int r = 0; r < fine.rows(); ++r)
      for (int c = 0; c < fine.cols(); ++c) {
        if (fine.fixed(fine.node(r, c))) continue;
        double* diagonal = fine.block(r, c, r, c);
        for (int k = 0; k < 3; ++k) diagonal[4 * k] += mass_[fine.node(r, c)];
      }
    symmetrise(fine);
    ++rebuild_count_;
    if (!hierarchy_.rebuild())
      throw sdk::Error(CLOTHLAB_ERROR_NUMERICAL,
                       "multigrid: the linearised matrix is not positive definite (definite = 0 "
                       "with compressed springs?)");
    if (hierarchy_.level_count() > 1) prepare_chebyshev(system);
  }

  // z = B M r on the active particles, J applied by product(u, out): out = J u.
  template <class Real, class Product>
  void apply(const sdk::System<Real>& system, const Real* r, Real* z, Product&& product) {
    if (hierarchy_.level_count() == 1) return solve_directly(system, r, z);
    const std::size_t stride = system.stride();
    Real* residual = static_cast<Real*>(probe_products_[0]);
    for (const clothlab_range& range : system.active())
      for (uint32_t i = range.begin; i < range.end; ++i)
        for (std::size_t k = 0; k < 3; ++k) {
          residual[k * stride + i] = r[k * stride + i];
          z[k * stride + i] = Real{0};
        }
    smooth(system, product, r, z, true);
    std::fill(fine_residual_.begin(), fine_residual_.end(), 0.0);
    std::fill(fine_correction_.begin(), fine_correction_.end(), 0.0);
    for (const clothlab_range& range : system.active())
      for (uint32_t i = range.begin; i < range.end; ++i)
        for (std::size_t k = 0; k < 3; ++k)
          fine_residual_[3 * i + k] = mass_[i] * residual[k * stride + i];
    cycle_.correct(fine_residual_.data(), fine_correction_.data());
    for (const clothlab_range& range : system.active())
      for (uint32_t i = range.begin; i < range.end; ++i)
        for (std::size_t k = 0; k < 3; ++k)
          z[k * stride + i] += static_cast<Real>(fine_correction_[3 * i + k]);
    smooth(system, product, r, z, false);
  }

 private:
  static constexpr int kProbePeriod = 2 * GridLevel::reach + 1;
  // The Chebyshev polynomial's target: D^-1 A's eigenvalues down to lambda_max / this ratio
  // (the smooth rest is the coarse levels').
  static constexpr double kChebyshevRatio = 30.0;

  // The fine level alone (it is the coarsest): z = S^-1 M r by the direct solve.
  template <class Real>
  void solve_directly(const sdk::System<Real>& system, const Real* r, Real* z) {
    const std::size_t stride = system.stride();
    double* rhs = cycle_.fine_rhs();
    std::fill_n(rhs, 3 * hierarchy_.level(0).node_count(), 0.0);
    for (const clothlab_range& range : system.active())
      for (uint32_t i = range.begin; i < range.end; ++i)
        for (std::size_t k = 0; k < 3; ++k) rhs[3 * i + k] = mass_[i] * r[k * stride + i];
    const double* solution = cycle_.apply();
    for (const clothlab_range& range : system.active())
      for (uint32_t i = range.begin; i < range.end; ++i)
        for (std::size_t k = 0; k < 3; ++k)
          z[k * stride + i] = static_cast<Real>(solution[3 * i + k]);
  }

  // out = D^-1 u on the active particles (D: A's diagonal blocks).
  template <class Real>
  void apply_jacobi(const sdk::System<Real>& system, const Real* u, Real* out) const {
    const std::size_t stride = system.stride();
    for (const clothlab_range& range : system.active())
      for (uint32_t i = range.begin; i < range.end; ++i) {
        const double* d = &jacobi_[9 * std::size_t{i}];
        const double u0 = u[i], u1 = u[stride + i], u2 = u[2 * stride + i];
        for (std::size_t k = 0; k < 3; ++k)
          out[k * stride + i] =
              static_cast<Real>(d[3 * k] * u0 + d[3 * k + 1] * u1 + d[3 * k + 2] * u2);
      }
  }

  // out = A u = u + J u.
  template <class Real, class Product>
  static void apply_a(const sdk::System<Real>& system, Product& product, const Real* u, Real* out) {
    product(u, out);
    const std::size_t stride = system.stride();
    for (const clothlab_range& range : system.active())
      for (uint32_t i = range.begin; i < range.end; ++i)
        for (std::size_t k = 0; k < 3; ++k) out[k * stride + i] += u[k * stride + i];
  }

  // D^-1 from the fine level's exact diagonal blocks (D = S_ii / m_i), and an upper bound on
  // D^-1 A's eigenvalues (those of D_S^-1 S): block Gershgorin, the largest row sum of
  // |D_S,i^-1 S_ij| over a row's blocks. An estimate from below (power iteration) would let
  // the polynomial amplify the stiffest modes.
  template <class Real>
  void prepare_chebyshev(const sdk::System<Real>& system) {
    const GridLevel& fine = hierarchy_.level(0);
    const std::vector<double>& inverse = hierarchy_.smoother(0).inverse_diagonal();
    for (const clothlab_range& range : system.active())
      for (uint32_t i = range.begin; i < range.end; ++i)
        for (std::size_t k = 0; k < 9; ++k)
          jacobi_[9 * std::size_t{i} + k] = mass_[i] * inverse[9 * std::size_t{i} + k];
    double bound = 0.0;
    for (int r = 0; r < fine.rows(); ++r)
      for (int c = 0; c < fine.cols(); ++c) {
        const std::size_t i = fine.node(r, c);
        if (fine.fixed(i)) continue;
        const double* d = &inverse[9 * i];
        const GridLevel::Window w = fine.window(r, c);
        std::array<double, 3> row_sums{};
        for (const GridLevel::Offset& offset : fine.couplings()) {
          const int r2 = r + offset.rows, c2 = c + offset.cols;
          if (r2 < w.row_begin || r2 >= w.row_end || c2 < w.col_begin || c2 >= w.col_end) continue;
          const double* a = fine.block(r, c, r2, c2);
          for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j)
              row_sums[static_cast<std::size_t>(k)] +=
                  std::abs(d[3 * k] * a[j] + d[3 * k + 1] * a[3 + j] + d[3 * k + 2] * a[6 + j]);
        }
        bound = std::max({bound, row_sums[0], row_sums[1], row_sums[2]});
      }
    if (!(bound > 0.0 && std::isfinite(bound)))
      throw sdk::Error(CLOTHLAB_ERROR_NUMERICAL,
                       "multigrid: no spectral bound of the fine level's Jacobi-scaled matrix");
    lambda_max_ = bound;
  }

  // `sweeps_` Chebyshev steps on A z = r from z, leaving the residual r - A z in
  // probe_products_[0] where `pre` (which starts from z = 0, that residual r already there).
  template <class Real, class Product>
  void smooth(const sdk::System<Real>& system, Product& product, const Real* r, Real* z, bool pre) {
    const std::size_t stride = system.stride();
    Real* residual = static_cast<Real*>(probe_products_[0]);
    Real* direction = static_cast<Real*>(probe_products_[1]);
    Real* image = static_cast<Real*>(probe_products_[2]);
    if (!pre) {
      apply_a(system, product, z, image);
      for (const clothlab_range& range : system.active())
        for (uint32_t i = range.begin; i < range.end; ++i)
          for (std::size_t k = 0; k < 3; ++k)
            residual[k * stride + i] = r[k * stride + i] - image[k * stride + i];
    }
    const double lambda_min = lambda_max_ / kChebyshevRatio;
    const double theta = 0.5 * (lambda_max_ + lambda_min), delta = 0.5 * (lambda_max_ - lambda_min);
    const double sigma = theta / delta;
    double rho = 1.0 / sigma;
    apply_jacobi(system, residual, direction);
    for (const clothlab_range& range : system.active())
      for (uint32_t i = range.begin; i < range.end; ++i)
        for (std::size_t k = 0; k < 3; ++k)
          direction[k * stride + i] = static_cast<Real>(direction[k * stride + i] / theta);
    for (long step = 0; step < sweeps_; ++step) {
      for (const clothlab_range& range : system.active())
        for (uint32_t i = range.begin; i < range.end; ++i)
          for (std::size_t k = 0; k < 3; ++k) z[k * stride + i] += direction[k * stride + i];
      const bool last = step + 1 == sweeps_;
      if (last && !pre) break;
      apply_a(system, product, direction, image);
      for (const clothlab_range& range : system.active())
        for (uint32_t i = range.begin; i < range.end; ++i)
          for (std::size_t k = 0; k < 3; ++k) residual[k * stride + i] -= image[k * stride + i];
      if (last) break;
      const double rho_next = 1.0 / (2.0 * sigma - rho);
      apply_jacobi(system, residual, image);
      for (const clothlab_range& range : system.active())
        for (uint32_t i = range.begin; i < range.end; ++i)
          for (std::size_t k = 0; k < 3; ++k)
            direction[k * stride + i] =
                static_cast<Real>(rho_next * rho * direction[k * stride + i] +
                                  2.0 * rho_next / delta * image[k * stride + i]);
      rho = rho_next;
    }
  }

  // The offset in [-reach, reach] from index n to the nearest index of class `target` mod 5.
  static int offset_to(int target, int n) {
    const int offset = ((target - n) % kProbePeriod + kProbePeriod) % kProbePeriod;
    return offset > GridLevel::reach ? offset - kProbePeriod : offset;
  }

  // component[i] = value for every particle i of the probe class `color`.
  template <class Real>
  static void set_probe(const GridLevel& fine, int color, Real* component, Real value) {
    for (int r = color / kProbePeriod; r < fine.rows(); r += kProbePeriod)
      for (int c = color % kProbePeriod; c < fine.cols(); c += kProbePeriod)
        component[fine.node(r, c)] = value;
  }

  // A = (A + A^T) / 2, block by block.
  static void symmetrise(GridLevel& level) {
    for (int r = 0; r < level.rows(); ++r)
      for (int c = 0; c < level.cols(); ++c) {
        const GridLevel::Window w = level.window(r, c);
        for (int r2 = w.row_begin; r2 < w.row_end; ++r2)
          for (int c2 = w.col_begin; c2 < w.col_end; ++c2) {
            if (level.node(r2, c2) < level.node(r, c)) continue;
            double* upper = level.block(r, c, r2, c2);
            double* lower = level.block(r2, c2, r, c);
            for (int k = 0; k < 9; ++k) {
              const int transposed = 3 * (k % 3) + k / 3;
              if (upper == lower && transposed < k) continue;
              const double mean = 0.5 * (upper[k] + lower[transposed]);
              upper[k] = lower[transposed] = mean;
            }
          }
      }
  }

  long rebuild_interval_;  // solves per hierarchy at most
  bool valid_ = false;     // the hierarchy holds a successfully built matrix
  double built_c_x_ = 0.0;
  long solves_since_rebuild_ = 0;
  uint64_t rebuild_count_ = 0;
  MultigridHierarchy hierarchy_;
  VCycle cycle_;
  std::vector<double> mass_;    // per particle, 0 where pinned
  long sweeps_;                 // Chebyshev steps on the fine level before and after
  std::vector<double> jacobi_;  // per particle: D^-1, A's inverted diagonal block (row-major)
  double lambda_max_ = 0.0;     // bounds D^-1 A's eigenvalues from above
  std::vector<double> fine_residual_, fine_correction_;  // the coarse correction's, 3 per node
  // System vectors in its precision: the probe, and J times it for each of its components.
  void* probe_;
  std::array<void*, 3> probe_products_;
};

}  // namespace clothlab::builtin
