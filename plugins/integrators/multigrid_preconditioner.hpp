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
// Reuse: the set-up (probing, Galerkin products, factors) costs several CG iterations, so
// `prepare_solve` can keep the last hierarchy for up to `rebuild_interval` solves. CG's products
// still use the current matrix, so the answer is converged as before; a V-cycle of an older
// symmetric positive definite matrix is still a symmetric positive definite preconditioner, and
// only the iteration count changes (on cotton it grows by more than the set-up saves:
// lab/real-cloth.md, "Reusing the hierarchy over steps").
#pragma once

#include <algorithm>
#include <clothlab/sdk.hpp>
#include <clothlab/sdk/threads.hpp>
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
        probe_(system.alloc_vector()),
        probe_product_(system.alloc_vector()) {
    check_spring_reach(system, hierarchy_.level(0).cols(), "multigrid = 1");
    const Real* inverse_mass = system.inverse_mass();
    for (const clothlab_range& range : system.active())
      for (uint32_t i = range.begin; i < range.end; ++i) mass_[i] = 1.0 / inverse_mass[i];
    std::fill_n(static_cast<Real*>(probe_), 3 * std::size_t{system.stride()}, Real{0});
  }
  MultigridPreconditioner(const MultigridPreconditioner&) = delete;
  MultigridPreconditioner& operator=(const MultigridPreconditioner&) = delete;

  const MultigridHierarchy& hierarchy() const { return hierarchy_; }

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
  template <class Real, class Product>
  void linearise(const sdk::System<Real>& system, Product&& product) {
    GridLevel& fine = hierarchy_.level(0);
    fine.clear();
    Real* probe = static_cast<Real*>(probe_);
    const Real* out = static_cast<const Real*>(probe_product_);
    const std::size_t stride = system.stride();
    for (int color = 0; color < kProbePeriod * kProbePeriod; ++color)
      for (int d = 0; d < 3; ++d) {
        set_probe(fine, color, probe + d * stride, Real{1});
        product(probe, static_cast<Real*>(probe_product_));
        set_probe(fine, color, probe + d * stride, Real{0});
        for (int r = 0; r < fine.rows(); ++r)
          for (int c = 0; c < fine.cols(); ++c) {
            const std::size_t i = fine.node(r, c);
            const int r2 = r + offset_to(color / kProbePeriod, r),
                      c2 = c + offset_to(color % kProbePeriod, c);
            if (fine.fixed(i) || r2 < 0 || r2 >= fine.rows() || c2 < 0 || c2 >= fine.cols() ||
                fine.fixed(fine.node(r2, c2)))
              continue;
            double* block = fine.block(r, c, r2, c2);
            for (int k = 0; k < 3; ++k) block[3 * k + d] = mass_[i] * out[k * stride + i];
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
  }

  // z = B M r on the active particles.
  template <class Real>
  void apply(const sdk::System<Real>& system, const Real* r, Real* z) {
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

 private:
  static constexpr int kProbePeriod = 2 * GridLevel::reach + 1;

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
  std::vector<double> mass_;  // per particle, 0 where pinned
  void* probe_;               // system vectors in its precision: the probe and J times it
  void* probe_product_;
};

}  // namespace clothlab::builtin
