// implicit_euler's multigrid preconditioner: the V-cycle (multigrid_cycle.hpp) for the mass-
// weighted matrix S = M A of a solve A dv = b, A = I + J, on a cloth laid out as a grid
// (clothlab.grid/1, particle r * cols + c). CG runs in the mass inner product, so its
// preconditioner is z = B M r with B ~ S^-1 symmetric: self-adjoint in that product.
//
// S's blocks come from the host's block table of the definite Jacobian where it offers one
// (clothlab.definite-jacobian/2, in clothlab.jacobian/1's pattern: one call, S_ij = m_i D_ij),
// else from A's products (probing: the exact Jacobian, `definite` = 0, and hosts with /1
// alone). Every spring joins particles at most two grid spacings apart (checked,
// multigrid_grid.hpp), so particles whose rows and columns are equal mod 5 share no neighbour:
// one product with e_d on all particles of such a class gives column d of every block coupling
// to them, 75 products in all. Products and tables carry rounding, so S is made symmetric
// (probed: (S + S^T) / 2; from a table: its upper triangle) and the V-cycle stays exactly
// symmetric. From a table the fine level keeps no
// blocks: level 1 (its Galerkin product), D^-1 and the fine smoother's bound are formed from
// the table's rows as they are read, on the V-cycle's threads; a single-precision system's V-cycle
// also smooths in single precision (multigrid_lanes.hpp), all its CG resolves. Pinned
// particles are the fine level's Dirichlet nodes.
//
// The fine level smooths matrix-free: Chebyshev iteration on block-Jacobi (D^-1 A, D the
// diagonal blocks of A), `sweeps` host products before the coarse correction and as many
// after, in the system's precision and layout, with the polynomial and the spectral bound of
// multigrid_chebyshev.hpp. A product costs about an explicit step (less where the host
// offers clothlab.cg-step/1: its product of A linearised once per solve, CG's own product
// too), where a Gauss-Seidel sweep over the stored fine blocks costs several. The coarser levels
// smooth with the same polynomial over their stored blocks in lanes (Smoothing::chebyshev),
// `sweeps` steps each side. On the cotton flag 2 + 2 such steps take about as many CG iterations as
// 2 + 2 Gauss-Seidel sweeps.
//
// Reuse: the set-up (the fine blocks, Galerkin products, factors) costs several CG iterations, so
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
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "multigrid_cycle.hpp"
#include "multigrid_grid.hpp"
#include "multigrid_hierarchy.hpp"

namespace clothlab::builtin {

// The preconditioner's default coarsening (implicit_euler's `multigrid_coarsening`): each
// level keeps every third node of the one above (multigrid_transfer.hpp), so level 1 has 1/9
// of the fine nodes where every other node would keep 1/4, and the coarse levels' passes,
// which stream their stored blocks, cost that much less; on the cotton flag CG takes 1.4 to 1.5
// times the iterations, for a cheaper solve (docs/results.md, "Multigrid").
// projective_dynamics' V-cycles, a solver of their own, keep every other node.
constexpr int kPreconditionerCoarsening = 3;

class MultigridPreconditioner {
 public:
  // From `prepare`: one-line sdk::Error where the cloth is no grid, a spring reaches further
  // than two spacings, the grid does not coarsen far enough (plan_levels), or block_pattern
  // disagrees with the grid. block_pattern: the host's (clothlab.jacobian/1), where the solves'
  // fine blocks come from `prepare_solve`'s blocks (the host's table of the definite Jacobian);
  // nothing: from probing the product. coarsening: every m-th node kept per level.
  template <class Real>
  MultigridPreconditioner(const sdk::System<Real>& system, long coarsest_particles, long sweeps,
                          long rebuild_interval = 1,
                          std::optional<clothlab_block_pattern> block_pattern = std::nullopt,
                          int coarsening = kPreconditionerCoarsening)
      : rebuild_interval_(rebuild_interval),
        hierarchy_(plan_grid_levels(system, coarsest_particles, "multigrid = 1", coarsening),
                   fixed_particles(system),
                   block_pattern ? GridLevel::Blocks::none : GridLevel::Blocks::single,
                   std::is_same_v<Real, float> ? LanePrecision::float32 : LanePrecision::float64,
                   Smoothing::chebyshev, coarsening),
        cycle_(hierarchy_, sweeps, sdk::plugin_threads(system, 0, true)),
        mass_(system.particle_count(), 0.0),
        sweeps_(sweeps),
        jacobi_(std::is_same_v<Real, float> ? 0 : 6 * std::size_t{system.particle_count()}, 0.0),
        jacobi_single_(std::is_same_v<Real, float> ? 6 * std::size_t{system.particle_count()} : 0,
                       0.0f),
        probe_(system.alloc_vector()),
        probe_products_{system.alloc_vector(), system.alloc_vector(), system.alloc_vector()},
        row_bounds_(static_cast<std::size_t>(hierarchy_.level(0).rows()), 0.0) {
    check_spring_reach(system, hierarchy_.level(0).cols(), "multigrid = 1");
    const Real* inverse_mass = system.inverse_mass();
    for (const clothlab_range& range : system.active())
      for (uint32_t i = range.begin; i < range.end; ++i) mass_[i] = 1.0 / inverse_mass[i];
    std::fill_n(static_cast<Real*>(probe_), 3 * std::size_t{system.stride()}, Real{0});
    if (block_pattern) {
      check_block_pattern(*block_pattern, hierarchy_.level(0));
      pattern_ = block_pattern;
      transposed_ = transposed_slots(*block_pattern);
      for (uint32_t i = 0; i < block_pattern->row_count; ++i)
        for (uint32_t k = block_pattern->row_offsets[i]; k < block_pattern->row_offsets[i + 1];
             ++k) {
          const auto cols = static_cast<uint32_t>(hierarchy_.level(0).cols());
          const uint32_t j = block_pattern->columns[k];
          window_places_.push_back(static_cast<uint8_t>(
              (static_cast<int>(j / cols) - static_cast<int>(i / cols) + GridLevel::reach) *
                  kWindowWidth +
              static_cast<int>(j % cols) - static_cast<int>(i % cols) + GridLevel::reach));
        }
      for (uint32_t i = 0; i < block_pattern->row_count; ++i)
        diagonal_slots_.push_back(static_cast<uint32_t>(
            std::lower_bound(block_pattern->columns + block_pattern->row_offsets[i],
                             block_pattern->columns + block_pattern->row_offsets[i + 1], i) -
            block_pattern->columns));
      block_values_.assign(9 * std::size_t{pattern_->block_count}, 0.0);
    }
  }
  MultigridPreconditioner(const MultigridPreconditioner&) = delete;
  MultigridPreconditioner& operator=(const MultigridPreconditioner&) = delete;

  const MultigridHierarchy& hierarchy() const { return hierarchy_; }
  // The fine smoother's upper bound on D^-1 A's eigenvalues, from the last build (0 before, and
  // where the fine level is the coarsest).
  double lambda_max() const { return lambda_max_; }

  // Every level's Galerkin product in bands of `rows` coarse rows from the next build (for
  // comparing band plans: GridTransfer::set_band_rows).
  void set_band_rows(int rows) {
    for (std::size_t l = 0; l + 1 < hierarchy_.level_count(); ++l)
      hierarchy_.transfer(l).set_band_rows(rows);
  }

  // Hierarchies built so far (each ends in a factorisation of the coarsest level).
  uint64_t rebuild_count() const { return rebuild_count_; }

  // Readies the V-cycle for a solve whose matrix has J's position weight c_x = -h^2: assembles
  // (`assemble` from blocks(values), which fills the host's block table, where built with a
  // block pattern, else `linearise` by product(u, out): out = A u) where there is no valid
  // hierarchy, c_x changed since the last build (the old matrix may then be far from the new
  // one), or `rebuild_interval` solves used the last.
  template <class Real, class Product, class Blocks>
  void prepare_solve(const sdk::System<Real>& system, double c_x, Product&& product,
                     Blocks&& blocks) {
    if (!valid_ || c_x != built_c_x_ || solves_since_rebuild_ >= rebuild_interval_) {
      valid_ = false;  // until the build succeeds: a throw leaves no hierarchy to reuse
      if (pattern_) {
        blocks(block_values_.data());
        assemble(block_values_.data());
      } else {
        linearise(system, product);
      }
      valid_ = true, built_c_x_ = c_x, solves_since_rebuild_ = 0;
    }
    ++solves_since_rebuild_;
  }

  // Assembles S = M A, A = I + J applied by product(u, out): out = A u, and rebuilds the levels.
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
    finish_fine_level(system);
  }

  // Assembles S = M (I + J) from J's blocks `values` (9 each) in the order of the block pattern
  // given at construction, and rebuilds the levels. The fine level keeps no blocks where it
  // has a coarser one: level 1, D^-1 and the fine bound come straight from the table, in one
  // pass over it (the Galerkin product's).
  void assemble(const double* values) {
    const int threads = cycle_.threads();
    ++rebuild_count_;
    GridLevel& fine = hierarchy_.level(0);
    if (hierarchy_.level_count() == 1) {  // the fine level is the coarsest: solved directly
      fine.clear();
      for (int r = 0; r < fine.rows(); ++r)
        for (int c = 0; c < fine.cols(); ++c) {
          const auto i = static_cast<uint32_t>(fine.node(r, c));
          if (!fine.fixed(i))
            table_row(block_table(values), fine, i, [&](int r2, int c2, const double* block) {
              std::copy_n(block, 9, fine.block(r, c, r2, c2));
            });
        }
      return require_definite(hierarchy_.rebuild(threads));
    }
    // Row i's read for the Galerkin product also gives D^-1 and the fine smoother's bound
    // (galerkin_from_table).
    std::fill(row_bounds_.begin(), row_bounds_.end(), 0.0);
    hierarchy_.galerkin_products().table(block_table(values), hierarchy_.transfer(0), fine,
                                         hierarchy_.level(1), threads);
    lambda_max_ = 0.0;
    for (const double bound : row_bounds_)
      lambda_max_ = std::isnan(bound) ? bound : std::max(lambda_max_, bound);
    require_definite(lambda_max_ > 0.0 && std::isfinite(lambda_max_) &&
                     hierarchy_.rebuild_below(1, threads));
  }

  // z = B M r on the active particles, A applied by product(u, out): out = A u = u + J u (the
  // host's linearised product, clothlab.cg-step/1, where it offers one). The fine
  // Chebyshev steps (see `chebyshev_steps`) run one pass over the particles after each product:
  // the residual, the direction and z; the residual for the coarse level is restricted straight
  // from the system's vectors after the last pre-smoothing product, and the correction
  // prolonged straight into z.
  template <class Real, class Product>
  void apply(const sdk::System<Real>& system, const Real* r, Real* z, Product&& product) {
    if (hierarchy_.level_count() == 1) return solve_directly(system, r, z);
    const std::size_t stride = system.stride();
    Real* residual = static_cast<Real*>(probe_products_[0]);
    Real* direction = static_cast<Real*>(probe_products_[1]);
    Real* image = static_cast<Real*>(probe_products_[2]);
    // Pre-smoothing from z = 0, where the residual is r.
    ChebyshevSteps pre(lambda_max_);
    const double first_scale = pre.first_scale();
    for_each_active(system, [&](uint32_t begin, uint32_t end) {
      chebyshev_steps<false, true, true, false, Real>(begin, end, stride, r, nullptr,
                                                      ChebyshevSteps::Step{0.0, first_scale},
                                                      residual, direction, z);
    });
    const Real* last_residual = r;
    for (long step = 1; step < sweeps_; ++step) {
      product(direction, image);
      const ChebyshevSteps::Step next = pre.next();
      for_each_active(system, [&](uint32_t begin, uint32_t end) {
        chebyshev_steps<true, false, false>(begin, end, stride, last_residual, image, next,
                                            residual, direction, z);
      });
      last_residual = residual;
    }
    // The coarse correction of the residual r - A z = last residual - A direction.
    product(direction, image);
    const auto cols = static_cast<std::size_t>(hierarchy_.level(0).cols());
    const double* mass = mass_.data();  // 0 on pinned particles
    cycle_.correct(
        [&](int row, int c0, int c1, double weight, GridTransfer::ChunkRow& sum) {
          const std::size_t base = static_cast<std::size_t>(row) * cols;
          for (std::size_t k = 0; k < 3; ++k) {
            const Real* from = last_residual + k * stride + base;
            const Real* to = image + k * stride + base;
            double* out = sum[k] - c0;
#pragma omp simd
            for (int c = c0; c < c1; ++c) {
              const double m = mass[base + static_cast<std::size_t>(c)];
              out[c] += m > 0.0 ? weight * (m * static_cast<double>(Real(from[c] - to[c]))) : 0.0;
            }
          }
        },
        [&](int row, int c0, int c1, const GridTransfer::ChunkRow& correction) {
          const std::size_t base = static_cast<std::size_t>(row) * cols;
          for (std::size_t k = 0; k < 3; ++k) {
            Real* out = z + k * stride + base;
            const double* in = correction[k] - c0;
#pragma omp simd
            for (int c = c0; c < c1; ++c)
              if (mass[base + static_cast<std::size_t>(c)] > 0.0)
                out[c] += static_cast<Real>(in[c]);
          }
        });
    // Post-smoothing from z: the same polynomial, its first residual r - A z.
    ChebyshevSteps post(lambda_max_);
    product(z, image);
    for_each_active(system, [&](uint32_t begin, uint32_t end) {
      const ChebyshevSteps::Step first{0.0, first_scale};
      if (sweeps_ == 1)
        return chebyshev_steps<true, true, false, true>(begin, end, stride, r, image, first,
                                                        residual, direction, z);
      chebyshev_steps<true, true, false>(begin, end, stride, r, image, first, residual, direction,
                                         z);
    });
    for (long step = 1; step < sweeps_; ++step) {
      product(direction, image);
      const ChebyshevSteps::Step next = post.next();
      for_each_active(system, [&](uint32_t begin, uint32_t end) {
        if (step + 1 == sweeps_)
          return chebyshev_steps<true, false, false, true>(begin, end, stride, residual, image,
                                                           next, residual, direction, z);
        chebyshev_steps<true, false, false>(begin, end, stride, residual, image, next, residual,
                                            direction, z);
      });
    }
  }

 private:
  // S's fine blocks written (M A): symmetrises them and rebuilds the levels.
  template <class Real>
  void finish_fine_level(const sdk::System<Real>& system) {
    GridLevel& fine = hierarchy_.level(0);
    symmetrise(fine);
    ++rebuild_count_;
    require_definite(hierarchy_.rebuild(cycle_.threads()));
    if (hierarchy_.level_count() > 1) prepare_chebyshev(system);
  }

  static void require_definite(bool built) {
    if (!built)
      throw sdk::Error(CLOTHLAB_ERROR_NUMERICAL,
                       "multigrid: the linearised matrix is not positive definite (definite = 0 "
                       "with compressed springs?)");
  }

  // Per block of `pattern`, the slot of its transpose; one line of sdk::Error where one is
  // missing (the table must be structurally symmetric).
  static std::vector<uint32_t> transposed_slots(const clothlab_block_pattern& pattern) {
    std::vector<uint32_t> slots(pattern.block_count);
    for (uint32_t i = 0; i < pattern.row_count; ++i)
      for (uint32_t k = pattern.row_offsets[i]; k < pattern.row_offsets[i + 1]; ++k) {
        const uint32_t j = pattern.columns[k];
        const uint32_t* first = pattern.columns + pattern.row_offsets[j];
        const uint32_t* last = pattern.columns + pattern.row_offsets[j + 1];
        const uint32_t* at = std::lower_bound(first, last, i);
        if (at == last || *at != i)
          throw sdk::Error(CLOTHLAB_ERROR_INVALID_ARGUMENT,
                           "multigrid = 1: the host's block table (clothlab.jacobian/1 pattern) "
                           "couples particle " +
                               std::to_string(i) + " to " + std::to_string(j) + " but not " +
                               std::to_string(j) + " to " + std::to_string(i));
        slots[k] = static_cast<uint32_t>(at - pattern.columns);
      }
    return slots;
  }

  static constexpr int kWindowWidth = 2 * GridLevel::reach + 1;
  static constexpr int kProbePeriod = kWindowWidth;
  // Particles of a range worth splitting among the V-cycle's threads.
  static constexpr uint32_t kParticlesWorthATeam = 4096;

  // body(begin, end) over the active particles in [begin, end), a large range split among the
  // V-cycle's threads in contiguous parts (each particle's work is its own: the same bits on
  // any count).
  template <class Real, class Body>
  void for_each_active(const sdk::System<Real>& system, Body&& body) const {
    const int threads = cycle_.threads();
    for (const clothlab_range& range : system.active()) {
      if (threads > 1 && range.end - range.begin >= kParticlesWorthATeam) {
        const uint64_t count = range.end - range.begin;
#pragma omp parallel for schedule(static) num_threads(threads)
        for (int part = 0; part < threads; ++part)
          body(static_cast<uint32_t>(range.begin + count * static_cast<uint64_t>(part) /
                                                       static_cast<uint64_t>(threads)),
               static_cast<uint32_t>(range.begin + count * static_cast<uint64_t>(part + 1) /
                                                       static_cast<uint64_t>(threads)));
      } else {
        body(range.begin, range.end);
      }
    }
  }

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

  // One fine Chebyshev step at the particles [begin, end), each vector `stride` apart per
  // component: residual = from - image (image = A u for the step's u; from alone without
  // kImage), direction = step.keep direction + step.scale D^-1 residual (the old direction
  // unread on the kFirst step, whose keep is 0), z += direction (z = direction where kStart).
  // residual and from may be the same vector: each particle reads its own entries before it
  // writes them. Without kImage the residual is `from` itself and is not written; the cycle's
  // last step (kLast) writes z alone.
  template <bool kImage, bool kFirst, bool kStart, bool kLast = false, class Real>
  void chebyshev_steps(uint32_t begin, uint32_t end, std::size_t stride, const Real* from,
                       const Real* image, ChebyshevSteps::Step step, Real* residual,
                       Real* direction, Real* z) const {
    const std::size_t n = mass_.size();
    const Real* d = [&] {
      if constexpr (std::is_same_v<Real, float>)
        return jacobi_single_.data();
      else
        return jacobi_.data();
    }();
#pragma omp simd
    for (uint32_t i = begin; i < end; ++i) {
      double res[3];
      for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t at = k * stride + i;
        const Real value = kImage ? from[at] - image[at] : from[at];
        if constexpr (kImage && !kLast) residual[at] = value;
        res[k] = value;
      }
      for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t at = k * stride + i;
        const double jacobi = d[kSymmetricEntry[3 * k] * n + i] * res[0] +
                              d[kSymmetricEntry[3 * k + 1] * n + i] * res[1] +
                              d[kSymmetricEntry[3 * k + 2] * n + i] * res[2];
        const double kept = kFirst ? 0.0 : step.keep * direction[at];
        const auto next = static_cast<Real>(kept + step.scale * jacobi);
        if constexpr (!kLast) direction[at] = next;
        z[at] = kStart ? next : z[at] + next;
      }
    }
  }

  // The host's table `values` with what the preconditioner keeps of its pattern, D^-1 (in the
  // system's precision) and the fine rows' bounds.
  BlockTable block_table(const double* values) {
    return {values,
            &*pattern_,
            transposed_.data(),
            window_places_.data(),
            diagonal_slots_.data(),
            mass_.data(),
            mass_.size(),
            jacobi_.data(),
            jacobi_single_.empty() ? nullptr : jacobi_single_.data(),
            row_bounds_.data()};
  }

  // D^-1 from the fine level's exact diagonal blocks (D = S_ii / m_i), and the fine smoother's
  // bound on D^-1 A's eigenvalues (those of D_S^-1 S) from the hierarchy's.
  template <class Real>
  void prepare_chebyshev(const sdk::System<Real>& system) {
    const BlockChebyshev& fine = hierarchy_.chebyshev(0);
    const std::vector<double>& inverse = fine.inverse_diagonal();
    for (const clothlab_range& range : system.active())
      for (uint32_t i = range.begin; i < range.end; ++i)
        store_jacobi(i, mass_[i], &inverse[9 * std::size_t{i}], mass_.size(), jacobi_.data(),
                     jacobi_single_.empty() ? nullptr : jacobi_single_.data());
    lambda_max_ = fine.lambda_max();
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

  // One line of sdk::Error unless `pattern` (the host's, for its block table) has a row per
  // particle of the grid, ascending rows that each hold their diagonal, and no column beyond
  // the fine level's window.
  static void check_block_pattern(const clothlab_block_pattern& pattern, const GridLevel& fine) {
    const auto fail = [](const std::string& what) {
      throw sdk::Error(
          CLOTHLAB_ERROR_INVALID_ARGUMENT,
          "multigrid = 1: the host's block table (clothlab.jacobian/1 pattern) " + what);
    };
    if (pattern.row_count != fine.node_count())
      fail("has " + std::to_string(pattern.row_count) + " rows; the " +
           std::to_string(fine.rows()) + " x " + std::to_string(fine.cols()) + " grid has " +
           std::to_string(fine.node_count()) + " particles");
    if (pattern.row_offsets[0] != 0 ||
        pattern.row_offsets[pattern.row_count] != pattern.block_count)
      fail("has row offsets from " + std::to_string(pattern.row_offsets[0]) + " to " +
           std::to_string(pattern.row_offsets[pattern.row_count]) + "; its blocks are 0 to " +
           std::to_string(pattern.block_count));
    for (uint32_t i = 0; i < pattern.row_count; ++i) {
      if (pattern.row_offsets[i + 1] < pattern.row_offsets[i])
        fail("has row " + std::to_string(i) + " ending before it begins");
      const int r = static_cast<int>(i / static_cast<uint32_t>(fine.cols()));
      const int c = static_cast<int>(i % static_cast<uint32_t>(fine.cols()));
      const GridLevel::Window w = fine.window(r, c);
      bool diagonal = false;
      for (uint32_t k = pattern.row_offsets[i]; k < pattern.row_offsets[i + 1]; ++k) {
        const uint32_t j = pattern.columns[k];
        const auto r2 = static_cast<int>(j / static_cast<uint32_t>(fine.cols()));
        const auto c2 = static_cast<int>(j % static_cast<uint32_t>(fine.cols()));
        if (j >= pattern.row_count || r2 < w.row_begin || r2 >= w.row_end || c2 < w.col_begin ||
            c2 >= w.col_end || (k > pattern.row_offsets[i] && j <= pattern.columns[k - 1]))
          fail("couples particle " + std::to_string(i) + " to " + std::to_string(j) +
               " (columns must ascend and lie within two grid spacings)");
        diagonal = diagonal || j == i;
      }
      if (!diagonal) fail("has no diagonal block in row " + std::to_string(i));
    }
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
  long sweeps_;               // Chebyshev steps on the fine level before and after
  // D^-1, A's inverted diagonal blocks, symmetric: their 6 upper entries (kSymmetricEntry),
  // entry k of particle i at k n + i, in the system's precision (double, or float: single).
  std::vector<double> jacobi_;
  std::vector<float> jacobi_single_;
  double lambda_max_ = 0.0;  // bounds D^-1 A's eigenvalues from above
  // System vectors in its precision: the probe, and A times it for each of its components.
  void* probe_;
  std::array<void*, 3> probe_products_;
  // With block_table: the host's pattern and its table's values (9 per block).
  std::optional<clothlab_block_pattern> pattern_;
  std::vector<double> block_values_;
  std::vector<uint32_t> transposed_;  // per block of the pattern, its transpose's slot
  // Per block of the pattern, its place in its row's window: (r2 - r + 2) 5 + c2 - c + 2.
  std::vector<uint8_t> window_places_;
  std::vector<uint32_t> diagonal_slots_;  // per row of the pattern, its diagonal block's slot
  std::vector<double> row_bounds_;        // per fine row of nodes, its part of lambda_max
};

}  // namespace clothlab::builtin
