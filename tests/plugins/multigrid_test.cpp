// implicit_euler's multigrid (plugins/integrators/multigrid_*.hpp): the Galerkin operator
// against R A P formed here from the bilinear rule, the V-cycle's symmetry (and a non-symmetric
// cycle the check catches), the two-grid method's convergence factor, multigrid-preconditioned
// CG (Eigen's CG around the V-cycle) against Eigen's SimplicialLDLT and its iteration count
// over grid sizes, the matrix the plugin assembles by probing against the host's products, and
// the plugin's steps and refusals through the C ABI.
#include <clothlab/ext/solver_statistics.h>
#include <gtest/gtest.h>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "integrator_harness.hpp"
#include "multigrid_cycle.hpp"
#include "multigrid_preconditioner.hpp"
#include "preconditioned_cg.hpp"
#include "spring_host.hpp"

namespace clothlab::test {
namespace {

using builtin::GridLevel;
using builtin::MultigridHierarchy;
using builtin::VCycle;
using SparseMatrix = Eigen::SparseMatrix<double>;

// S = m I + h^2 K of a Provot grid (structural, shear and flexion springs) in a wavy layout,
// each spring of stiffness k along it and k / 10 across (positive definite like the definite
// Jacobian), row 0's first and last nodes pinned: as a GridLevel and as an Eigen matrix over all
// 3 n unknowns (identity rows for the pins, whose right-hand side is 0).
struct ClothMatrix {
  ClothMatrix(int rows, int cols, double stiffness_ratio = 2e4)
      : rows(rows), cols(cols), fixed(static_cast<std::size_t>(rows * cols), 0) {
    fixed[0] = fixed[static_cast<std::size_t>(cols - 1)] = 1;
    std::vector<Eigen::Vector3d> x;
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c)
        x.emplace_back(c, -r + 0.3 * std::sin(0.7 * c), 0.4 * std::cos(0.5 * r + 0.3 * c));
    for (int i = 0; i < rows * cols; ++i)
      if (!fixed[static_cast<std::size_t>(i)]) block(i, i) = Eigen::Matrix3d::Identity();
    const int stencils[6][2] = {{0, 1}, {1, 0}, {1, 1}, {1, -1}, {0, 2}, {2, 0}};
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c)
        for (const auto& s : stencils) {
          const int r2 = r + s[0], c2 = c + s[1];
          if (r2 >= rows || c2 < 0 || c2 >= cols) continue;
          const int i = r * cols + c, j = r2 * cols + c2;
          const Eigen::Vector3d n =
              (x[static_cast<std::size_t>(j)] - x[static_cast<std::size_t>(i)]).normalized();
          const Eigen::Matrix3d along = n * n.transpose();
          const Eigen::Matrix3d b =
              stiffness_ratio * (along + 0.1 * (Eigen::Matrix3d::Identity() - along));
          const bool free_i = !fixed[static_cast<std::size_t>(i)],
                     free_j = !fixed[static_cast<std::size_t>(j)];
          if (free_i) block(i, i) += b;
          if (free_j) block(j, j) += b;
          if (free_i && free_j) block(i, j) -= b, block(j, i) -= b;
        }
  }

  Eigen::Matrix3d& block(int i, int j) {
    const auto [at, inserted] = blocks.try_emplace({i, j}, Eigen::Matrix3d::Zero());
    return at->second;
  }

  GridLevel level() {
    GridLevel level(static_cast<uint32_t>(rows), static_cast<uint32_t>(cols), fixed);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        const GridLevel::Window w = level.window(r, c);
        for (int r2 = w.row_begin; r2 < w.row_end; ++r2)
          for (int c2 = w.col_begin; c2 < w.col_end; ++c2) {
            const auto at = blocks.find({r * cols + c, r2 * cols + c2});
            if (at == blocks.end()) continue;
            const Eigen::Matrix3d& b = at->second;
            double* out = level.block(r, c, r2, c2);
            for (int k = 0; k < 9; ++k) out[k] = b(k / 3, k % 3);
          }
      }
    return level;
  }

  SparseMatrix sparse() {
    std::vector<Eigen::Triplet<double>> entries;
    for (int i = 0; i < rows * cols; ++i)
      if (fixed[static_cast<std::size_t>(i)])
        for (int k = 0; k < 3; ++k) entries.emplace_back(3 * i + k, 3 * i + k, 1.0);
    for (const auto& [at, b] : blocks)
      for (int k = 0; k < 9; ++k)
        entries.emplace_back(3 * at.first + k / 3, 3 * at.second + k % 3, b(k / 3, k % 3));
    SparseMatrix matrix(3 * rows * cols, 3 * rows * cols);
    matrix.setFromTriplets(entries.begin(), entries.end());
    return matrix;
  }

  // A right-hand side with 0 on the pins.
  Eigen::VectorXd rhs(unsigned seed) const {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    Eigen::VectorXd b(3 * rows * cols);
    for (int i = 0; i < 3 * rows * cols; ++i)
      b(i) = fixed[static_cast<std::size_t>(i / 3)] ? 0.0 : uniform(random);
    return b;
  }

  int rows, cols;
  std::vector<uint8_t> fixed;
  std::map<std::pair<int, int>, Eigen::Matrix3d> blocks;  // (i, j): S_ij, the nonzero ones
};

// The hierarchy for the cloth's matrix, coarsened (every `coarsening`-th node) while a level has
// more than `coarsest` nodes, its single levels smoothed in `lanes`' precision.
MultigridHierarchy hierarchy_for(ClothMatrix& cloth, long coarsest,
                                 builtin::LanePrecision lanes = builtin::LanePrecision::float64,
                                 builtin::Smoothing smoothing = builtin::Smoothing::gauss_seidel,
                                 int coarsening = builtin::kMinCoarsening) {
  MultigridHierarchy hierarchy(
      builtin::plan_levels(static_cast<uint32_t>(cloth.rows), static_cast<uint32_t>(cloth.cols),
                           coarsest, coarsening),
      cloth.fixed, GridLevel::Blocks::single, lanes, smoothing, coarsening);
  const GridLevel fine = cloth.level();
  for (int r = 0; r < cloth.rows; ++r)
    for (int c = 0; c < cloth.cols; ++c) {
      const GridLevel::Window w = fine.window(r, c);
      for (int r2 = w.row_begin; r2 < w.row_end; ++r2)
        for (int c2 = w.col_begin; c2 < w.col_end; ++c2)
          std::copy_n(fine.block(r, c, r2, c2), 9, hierarchy.level(0).block(r, c, r2, c2));
    }
  EXPECT_TRUE(hierarchy.rebuild());
  return hierarchy;
}

// z = B b with the cycle.
Eigen::VectorXd apply_cycle(VCycle& cycle, const Eigen::VectorXd& b) {
  std::copy(b.data(), b.data() + b.size(), cycle.fine_rhs());
  const double* z = cycle.apply();
  return Eigen::Map<const Eigen::VectorXd>(z, b.size());
}

// Eigen's CG with the V-cycle as its preconditioner.
class VCyclePreconditioner {
 public:
  VCyclePreconditioner() = default;
  template <class Matrix>
  explicit VCyclePreconditioner(const Matrix&) {}
  template <class Matrix>
  VCyclePreconditioner& analyzePattern(const Matrix&) {
    return *this;
  }
  template <class Matrix>
  VCyclePreconditioner& factorize(const Matrix&) {
    return *this;
  }
  template <class Matrix>
  VCyclePreconditioner& compute(const Matrix&) {
    return *this;
  }
  Eigen::ComputationInfo info() const { return Eigen::Success; }
  template <class Rhs>
  Eigen::VectorXd solve(const Rhs& b) const {
    return apply_cycle(*cycle, b);
  }
  VCycle* cycle = nullptr;
};

// The bilinear prolongation written out from its definition (multigrid_transfer.hpp): along an
// axis of n nodes, coarse node k on fine node min(m k, n - 1) for every m-th node kept, and
// its weight at fine node f the hat function that is 1 there and falls linearly to 0 at its
// neighbours' fine nodes; no weight into or out of a fixed node.
SparseMatrix bilinear_prolongation(int rows, int cols, const std::vector<uint8_t>& fixed,
                                   int m = 2) {
  const auto coarse_count = [m](int n) { return (n - 2) / m + 2; };
  const auto axis_weights = [&](int n, int f) {
    std::vector<std::pair<int, double>> out;
    const int coarse = coarse_count(n);
    const auto at = [&](int k) { return std::min(m * k, n - 1); };
    for (int k = 0; k < coarse; ++k) {
      if (at(k) == f) return std::vector<std::pair<int, double>>{{k, 1.0}};
      if (k > 0 && at(k - 1) < f && f < at(k))
        out.emplace_back(k, 1.0 - static_cast<double>(at(k) - f) / (at(k) - at(k - 1)));
      if (k + 1 < coarse && at(k) < f && f < at(k + 1))
        out.emplace_back(k, 1.0 - static_cast<double>(f - at(k)) / (at(k + 1) - at(k)));
    }
    return out;
  };
  const int coarse_cols = coarse_count(cols);
  std::vector<uint8_t> coarse_fixed(static_cast<std::size_t>(coarse_count(rows) * coarse_cols), 0);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const auto wr = axis_weights(rows, r), wc = axis_weights(cols, c);
      if (wr.size() == 1 && wc.size() == 1 && fixed[static_cast<std::size_t>(r * cols + c)])
        coarse_fixed[static_cast<std::size_t>(wr[0].first * coarse_cols + wc[0].first)] = 1;
    }
  std::vector<Eigen::Triplet<double>> entries;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      if (fixed[static_cast<std::size_t>(r * cols + c)]) continue;
      for (const auto& [kr, w1] : axis_weights(rows, r))
        for (const auto& [kc, w2] : axis_weights(cols, c)) {
          const int coarse = kr * coarse_cols + kc;
          if (coarse_fixed[static_cast<std::size_t>(coarse)]) continue;
          for (int d = 0; d < 3; ++d)
            entries.emplace_back(3 * (r * cols + c) + d, 3 * coarse + d, w1 * w2);
        }
    }
  SparseMatrix p(3 * rows * cols, 3 * coarse_count(rows) * coarse_cols);
  p.setFromTriplets(entries.begin(), entries.end());
  return p;
}

// visit(r, c, r2, c2, k) for entry k of every block in the level's windows.
template <class Visit>
void for_each_block_entry(const GridLevel& level, Visit visit) {
  for (int r = 0; r < level.rows(); ++r)
    for (int c = 0; c < level.cols(); ++c) {
      const GridLevel::Window w = level.window(r, c);
      for (int r2 = w.row_begin; r2 < w.row_end; ++r2)
        for (int c2 = w.col_begin; c2 < w.col_end; ++c2)
          for (int k = 0; k < 9; ++k) visit(r, c, r2, c2, k);
    }
}

Eigen::MatrixXd dense_of(const GridLevel& level) {
  const auto n = static_cast<Eigen::Index>(3 * level.node_count());
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, n);
  for_each_block_entry(level, [&](int r, int c, int r2, int c2, int k) {
    out(static_cast<Eigen::Index>(3 * level.node(r, c)) + k / 3,
        static_cast<Eigen::Index>(3 * level.node(r2, c2)) + k % 3) = level.block(r, c, r2, c2)[k];
  });
  return out;
}

// Even and odd sides both, every other and every third node kept: an axis may end in a
// shorter coarse interval (one fine spacing, or two).
TEST(Multigrid, TheGalerkinOperatorIsRapFromTheBilinearRule) {
  // 20 x 7 and 26 x 7: more coarse rows than one band of the threaded product. 20 x 22: rows
  // far enough from the edges and pins to follow their class's plan.
  for (const int m : {2, 3})
    for (const auto& [rows, cols] : {std::pair{10, 9}, std::pair{9, 12}, std::pair{20, 7},
                                     std::pair{26, 7}, std::pair{20, 22}}) {
      ClothMatrix cloth(rows, cols, 30.0);
      MultigridHierarchy hierarchy =
          hierarchy_for(cloth, rows * cols - 1, builtin::LanePrecision::float64,
                        builtin::Smoothing::gauss_seidel, m);
      ASSERT_EQ(hierarchy.level_count(), 2u);  // two levels
      if (cols == 22) {
        EXPECT_GT(hierarchy.transfer(0).planned_nodes(), 0u) << m;
      }
      const SparseMatrix p = bilinear_prolongation(rows, cols, cloth.fixed, m);
      Eigen::MatrixXd fine = dense_of(hierarchy.level(0));
      const Eigen::MatrixXd expected = Eigen::MatrixXd(p.transpose()) * fine * Eigen::MatrixXd(p);
      const Eigen::MatrixXd coarse = dense_of(hierarchy.level(1));
      ASSERT_EQ(coarse.rows(), expected.rows()) << m << ": " << rows << " x " << cols;
      EXPECT_LT((coarse - expected).norm(), 1e-12 * expected.norm())
          << m << ": " << rows << " x " << cols;
      EXPECT_GT(expected.norm(), 0.0);
      // The restriction is P's transpose.
      const Eigen::VectorXd r = cloth.rhs(4);
      std::vector<double> restricted(3 * hierarchy.level(1).node_count());
      hierarchy.transfer(0).restrict_to(hierarchy.level(0), r.data(), hierarchy.level(1),
                                        restricted.data());
      const Eigen::VectorXd expected_restricted = p.transpose() * r;
      double worst = 0.0;
      for (Eigen::Index k = 0; k < expected_restricted.size(); ++k)
        worst = std::max(
            worst, std::abs(restricted[static_cast<std::size_t>(k)] - expected_restricted(k)));
      EXPECT_LT(worst, 1e-12 * expected_restricted.norm()) << m << ": " << rows << " x " << cols;
    }
}

// The largest difference between two levels' blocks.
double level_difference(const GridLevel& a, const GridLevel& b) {
  double worst = 0.0;
  for_each_block_entry(a, [&](int r, int c, int r2, int c2, int k) {
    worst = std::max(worst, std::abs(a.block(r, c, r2, c2)[k] - b.block(r, c, r2, c2)[k]));
  });
  return worst;
}

// The Galerkin product splits the coarse rows among the threads in bands, each coarse block
// summed in the fine rows' order: 1, 2 and 3 threads give the same bits (65 x 65: the fine level
// splits; its 33 coarse rows make five bands).
TEST(Multigrid, TheGalerkinProductHasTheSameBitsOnOneTwoAndThreeThreads) {
  for (const int m : {2, 3}) {  // 33 or 23 coarse rows: five or three bands
    ClothMatrix cloth(65, 65, 30.0);
    MultigridHierarchy hierarchy = hierarchy_for(cloth, 1000, builtin::LanePrecision::float64,
                                                 builtin::Smoothing::gauss_seidel, m);
    ASSERT_EQ(hierarchy.level(1).rows(), m == 2 ? 33 : 23);
    ASSERT_TRUE(hierarchy.level(0).splits(2));
    hierarchy.galerkin_products().levels(hierarchy.transfer(0), hierarchy.level(0),
                                         hierarchy.level(1), 1);  // not yet rounded
    const GridLevel one_thread = hierarchy.level(1);
    for (int threads : {2, 3}) {
      hierarchy.galerkin_products().levels(hierarchy.transfer(0), hierarchy.level(0),
                                           hierarchy.level(1), threads);
      const GridLevel& coarse = hierarchy.level(1);
      for (int r = 0; r < coarse.rows(); ++r)
        for (int c = 0; c < coarse.cols(); ++c)
          for (int e = 0; e < 9; ++e)
            ASSERT_EQ(coarse.block(r, c, r, c)[e], one_thread.block(r, c, r, c)[e])
                << threads << " threads, node " << r << " x " << c;
      EXPECT_EQ(level_difference(coarse, one_thread), 0.0) << threads << " threads";
    }
  }
}

// The fine rows away from the edges and pins follow their class's plan (multigrid_transfer.hpp):
// the same terms in the same order as the general path, so the same bits, with pins inside the
// grid (a row whose window or span holds one takes the general path) and on 1 and 2 threads.
TEST(Multigrid, TheGalerkinProductsClassPlanGivesTheGeneralPathsBits) {
  for (const int m : {2, 3}) {
    ClothMatrix cloth(65, 62, 30.0);
    cloth.fixed[static_cast<std::size_t>(30 * 62 + 31)] = 1;  // a pin inside
    MultigridHierarchy hierarchy = hierarchy_for(cloth, 1000, builtin::LanePrecision::float64,
                                                 builtin::Smoothing::gauss_seidel, m);
    const builtin::GridTransfer& planned = hierarchy.transfer(0);
    const std::size_t fine_nodes = hierarchy.level(0).node_count();
    EXPECT_GT(planned.planned_nodes(), fine_nodes / 2) << m;
    EXPECT_LT(planned.planned_nodes(), fine_nodes - 4 * 62) << m;
    builtin::GridTransfer general = planned;
    general.drop_plan();
    ASSERT_EQ(general.planned_nodes(), 0u);
    hierarchy.galerkin_products().levels(general, hierarchy.level(0), hierarchy.level(1), 1);
    const GridLevel expected = hierarchy.level(1);
    for (int threads : {1, 2}) {
      hierarchy.galerkin_products().levels(planned, hierarchy.level(0), hierarchy.level(1),
                                           threads);
      const GridLevel& coarse = hierarchy.level(1);
      std::size_t differing = 0;
      for_each_block_entry(coarse, [&](int r, int c, int r2, int c2, int k) {
        differing += coarse.block(r, c, r2, c2)[k] != expected.block(r, c, r2, c2)[k];
      });
      EXPECT_EQ(differing, 0u) << m << ", " << threads << " threads";
    }
  }
}

// The residual reads interior rows from the packed single-precision blocks and the rows near
// the edges through their windows: b - A x on every row against a dense product of the level's
// (rounded) blocks, with the pins 0.
TEST(Multigrid, TheResidualIsBMinusAxOnEveryRow) {
  ClothMatrix cloth(11, 14, 30.0);
  MultigridHierarchy hierarchy = hierarchy_for(cloth, 11 * 14 - 1);  // two levels
  const GridLevel& fine = hierarchy.level(0);
  ASSERT_TRUE(fine.packed());
  const Eigen::VectorXd b = cloth.rhs(5), x = cloth.rhs(6);
  Eigen::VectorXd residual(b.size());
  fine.residual(b.data(), x.data(), residual.data());
  Eigen::VectorXd expected = b - dense_of(fine) * x;
  for (std::size_t i = 0; i < fine.node_count(); ++i)
    if (fine.fixed(i)) expected.segment<3>(3 * static_cast<Eigen::Index>(i)).setZero();
  EXPECT_LT((residual - expected).norm(), 1e-12 * expected.norm());
  EXPECT_GT(expected.norm(), 0.0);
  // Without the diagonal block (the smoother's sums): -(A x - A_ii x_i) on every row.
  const Eigen::MatrixXd a = dense_of(fine);
  for (int r = 0; r < fine.rows(); ++r)
    for (int c = 0; c < fine.cols(); ++c) {
      const auto i = static_cast<Eigen::Index>(3 * fine.node(r, c));
      double sum[3] = {0.0, 0.0, 0.0};
      fine.subtract_row_product(r, c, x.data(), sum, true);
      const Eigen::Vector3d off_diagonal =
          a.middleRows(i, 3) * x - a.block(i, i, 3, 3) * x.segment<3>(i);
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(sum[k], -off_diagonal[k], 1e-12 * (1.0 + off_diagonal.norm()))
            << "row " << r << ", " << c;
    }
}

// Coloured block Gauss-Seidel written out from its definition on the dense matrix: colours
// (r mod 3, c mod 3) in the order 0..8 (8..0 backward), x_i = A_ii^-1 (b_i - sum_{j != i} A_ij
// x_j) on each free node of a colour, the pins left at 0.
void reference_sweeps(const Eigen::MatrixXd& a, const GridLevel& level, bool backward, long sweeps,
                      const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  for (long s = 0; s < sweeps; ++s)
    for (int step = 0; step < 9; ++step) {
      const int colour = backward ? 8 - step : step;
      for (int r = colour / 3; r < level.rows(); r += 3)
        for (int c = colour % 3; c < level.cols(); c += 3) {
          const std::size_t node = level.node(r, c);
          if (level.fixed(node)) continue;
          const auto i = static_cast<Eigen::Index>(3 * node);
          const Eigen::Vector3d off_diagonal =
              a.middleRows(i, 3) * x - a.block(i, i, 3, 3) * x.segment<3>(i);
          x.segment<3>(i) = a.block(i, i, 3, 3).ldlt().solve(b.segment<3>(i) - off_diagonal);
        }
    }
}

// A random vector on a level's nodes, 0 on its fixed ones.
Eigen::VectorXd level_vector(const GridLevel& level, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd v(3 * static_cast<Eigen::Index>(level.node_count()));
  for (Eigen::Index i = 0; i < v.size(); ++i)
    v(i) = level.fixed(static_cast<std::size_t>(i / 3)) ? 0.0 : uniform(random);
  return v;
}

// The smoother's passes run as a wave over the rows in chunks of steps (multigrid_smoother.hpp);
// whatever the chunk, forward and backward passes of 1 to 3 sweeps, and the residual after a
// forward pass, are those of the colour order. A wave whose sweeps lag one step less than
// they must reads a row before the previous sweep has updated it, and the check sees it.
// The lanes in single precision (a float32 system's V-cycle) give the same sweeps to single
// precision's rounding. Both the fine level (12 couplings) and the first Galerkin level (24).
TEST(Multigrid, TheSmootherSweepsTheColoursInOrderInEveryChunkOfTheWave) {
  using builtin::LanePrecision;
  for (const LanePrecision precision : {LanePrecision::float64, LanePrecision::float32})
    for (int rows : {28, 29, 30})  // every remainder of the rows' period
      for (std::size_t l : {0u, 1u}) {
        ClothMatrix cloth(rows, 16);
        MultigridHierarchy hierarchy = hierarchy_for(cloth, 100);
        const GridLevel& level = hierarchy.level(l);
        const Eigen::MatrixXd a = dense_of(level);
        builtin::BlockGaussSeidel smoother(level, precision);
        ASSERT_TRUE(smoother.factor(level));
        const double tolerance = precision == LanePrecision::float64 ? 1e-10 : 1e-4;
        const Eigen::VectorXd b = level_vector(level, 5), start = level_vector(level, 6);
        for (const bool backward : {false, true})
          for (long sweeps : {1L, 2L, 3L}) {
            Eigen::VectorXd expected = start;
            reference_sweeps(a, level, backward, sweeps, b, expected);
            const double scale = expected.norm();
            for (int steps_per_chunk : {1, 2, 5, 1000}) {
              smoother.set_steps_per_chunk(level, steps_per_chunk);
              const std::string where =
                  "level " + std::to_string(l) + ", " + std::to_string(rows) + " rows, " +
                  (precision == LanePrecision::float64 ? "double, " : "float, ") +
                  (backward ? "backward, " : "forward, ") + std::to_string(sweeps) + " sweeps, " +
                  std::to_string(steps_per_chunk) + " steps per chunk";
              Eigen::VectorXd x = start, residual(x.size());
              if (backward) {
                smoother.backward(level, b.data(), x.data(), sweeps);
              } else {
                smoother.forward(level, b.data(), x.data(), sweeps, residual.data());
                Eigen::VectorXd expected_residual = b - a * x;
                for (std::size_t i = 0; i < level.node_count(); ++i)
                  if (level.fixed(i)) expected_residual.segment<3>(3 * i).setZero();
                // In single precision b - A x cancels: its rounding scales with |A| |x|.
                const double residual_scale = precision == LanePrecision::float64
                                                  ? b.norm()
                                                  : (a.cwiseAbs() * x.cwiseAbs()).norm();
                EXPECT_LT((residual - expected_residual).norm(), tolerance * residual_scale)
                    << where;
              }
              EXPECT_LT((x - expected).norm(), tolerance * scale) << where;
            }
          }
      }
}

double asymmetry(VCycle& cycle, const ClothMatrix& cloth) {
  const Eigen::VectorXd x = cloth.rhs(1), y = cloth.rhs(2);
  const double xBy = x.dot(apply_cycle(cycle, y)), yBx = y.dot(apply_cycle(cycle, x));
  return std::abs(xBy - yBx) / std::abs(xBy);
}

// x^T B y = y^T B x to rounding; a cycle with forward Gauss-Seidel after the coarse correction
// too (not the pre-smoother's adjoint) is not symmetric, and the check sees it.
TEST(Multigrid, TheVCycleIsSymmetric) {
  ClothMatrix cloth(23, 18);
  MultigridHierarchy hierarchy = hierarchy_for(cloth, 100);  // 23 x 18, 12 x 10, 7 x 6
  ASSERT_EQ(hierarchy.level_count(), 3u);
  for (long sweeps : {1L, 2L}) {
    VCycle cycle(hierarchy, sweeps);
    EXPECT_LT(asymmetry(cycle, cloth), 1e-12) << sweeps << " sweeps";
  }
  // The mutant: one level, forward smoothing on both sides of the coarse solve.
  MultigridHierarchy two_grid = hierarchy_for(cloth, 23 * 18 - 1);
  const GridLevel& fine = two_grid.level(0);
  const auto forward_twice = [&](const Eigen::VectorXd& b) {
    Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size()), r(b.size());
    std::vector<double> coarse_b(3 * two_grid.level(1).node_count()), coarse_x(coarse_b.size());
    two_grid.smoother(0).forward(fine, b.data(), x.data(), 1, r.data());
    two_grid.transfer(0).restrict_to(fine, r.data(), two_grid.level(1), coarse_b.data());
    two_grid.coarsest_solve().solve(two_grid.level(1), coarse_b.data(), coarse_x.data());
    two_grid.transfer(0).prolong_add(fine, two_grid.level(1), coarse_x.data(), x.data());
    two_grid.smoother(0).forward(fine, b.data(), x.data(), 1, nullptr);
    return x;
  };
  const Eigen::VectorXd x = cloth.rhs(1), y = cloth.rhs(2);
  const double xBy = x.dot(forward_twice(y)), yBx = y.dot(forward_twice(x));
  EXPECT_GT(std::abs(xBy - yBx) / std::abs(xBy), 1e-6);
}

// The coarse levels' Chebyshev smoothing (implicit_euler's): level 1's cycle B_1 = (pre-smooth,
// coarse solve, post-smooth) is symmetric where pre- and post-smoothing apply the same
// polynomial, and so is the fine level's coarse correction P B_1 R. The mutants, one step fewer
// or more after the coarse solve than before it (another polynomial), make B_1 unsymmetric, and
// the check sees it.
TEST(Multigrid, TheChebyshevLevelsKeepTheCycleSymmetric) {
  ClothMatrix cloth(23, 18);
  MultigridHierarchy hierarchy =
      hierarchy_for(cloth, 100, builtin::LanePrecision::float64, builtin::Smoothing::chebyshev);
  ASSERT_EQ(hierarchy.level_count(), 3u);  // 23 x 18, 12 x 10, 7 x 6
  const GridLevel& fine = hierarchy.level(0);
  const GridLevel& level = hierarchy.level(1);
  const GridLevel& coarse = hierarchy.level(2);
  EXPECT_GT(hierarchy.chebyshev(1).lambda_max(), 1.0);
  for (long sweeps : {1L, 2L, 3L}) {
    VCycle cycle(hierarchy, sweeps);
    const auto correction = [&](const Eigen::VectorXd& r) {
      Eigen::VectorXd x = Eigen::VectorXd::Zero(r.size());
      cycle.correct(r.data(), x.data());
      return x;
    };
    const Eigen::VectorXd x = cloth.rhs(1), y = cloth.rhs(2);
    const double xBy = x.dot(correction(y)), yBx = y.dot(correction(x));
    EXPECT_LT(std::abs(xBy - yBx), 1e-12 * std::abs(xBy)) << sweeps << " sweeps";
    EXPECT_GT(x.dot(correction(x)), 0.0) << sweeps << " sweeps";
  }
  // B_1 by hand, on level 1's right-hand sides (the fine ones restricted).
  const auto level_rhs = [&](unsigned seed) {
    const Eigen::VectorXd fine_b = cloth.rhs(seed);
    Eigen::VectorXd b(static_cast<Eigen::Index>(3 * level.node_count()));
    hierarchy.transfer(0).restrict_to(fine, fine_b.data(), level, b.data());
    return b;
  };
  const auto two_grid = [&](const Eigen::VectorXd& b, long pre, long post) {
    Eigen::VectorXd x(b.size()), r(b.size());
    std::vector<double> coarse_b(3 * coarse.node_count()), coarse_x(coarse_b.size());
    hierarchy.pre_smooth(1, b.data(), x.data(), pre, r.data(), 1);
    hierarchy.transfer(1).restrict_to(level, r.data(), coarse, coarse_b.data());
    hierarchy.coarsest_solve().solve(coarse, coarse_b.data(), coarse_x.data());
    hierarchy.transfer(1).prolong_add(level, coarse, coarse_x.data(), x.data());
    hierarchy.post_smooth(1, b.data(), x.data(), post, 1);
    return x;
  };
  const Eigen::VectorXd x = level_rhs(1), y = level_rhs(2);
  const auto asymmetry_of = [&](long pre, long post) {
    const double xBy = x.dot(two_grid(y, pre, post)), yBx = y.dot(two_grid(x, pre, post));
    return std::abs(xBy - yBx) / std::abs(xBy);
  };
  EXPECT_LT(asymmetry_of(2, 2), 1e-12);
  EXPECT_GT(asymmetry_of(2, 1), 1e-6);
  EXPECT_GT(asymmetry_of(3, 2), 1e-6);
}

// The smoothing and the residual split a level's rows among the threads; a colour's nodes do
// not couple (and Chebyshev's rows read only the last iterate), so the V-cycle has the same
// bits on any count and in chunks of any size (70 x 70:
// the finest level is large enough to split).
TEST(Multigrid, TheVCycleHasTheSameBitsOnOneAndTwoThreads) {
  using builtin::LanePrecision;
  for (const LanePrecision precision : {LanePrecision::float64, LanePrecision::float32}) {
    SCOPED_TRACE(precision == LanePrecision::float64 ? "double lanes" : "float lanes");
    ClothMatrix cloth(70, 70);
    MultigridHierarchy hierarchy = hierarchy_for(cloth, builtin::kDefaultCoarsestNodes, precision);
    ASSERT_TRUE(hierarchy.level(0).splits(2));
    const Eigen::VectorXd b = cloth.rhs(4);
    VCycle one(hierarchy, 2, 1), two(hierarchy, 2, 2);
    const Eigen::VectorXd alone = apply_cycle(one, b), team = apply_cycle(two, b);
    ASSERT_EQ(alone.size(), team.size());
    for (Eigen::Index i = 0; i < alone.size(); ++i) ASSERT_EQ(alone[i], team[i]) << "entry " << i;
    EXPECT_GT(alone.norm(), 0.0);
    // The fine level's smoothing in chunks of 3 steps (a team of two rounds them to 2) on 1 and 2
    // threads, against the whole level at once on one thread.
    const GridLevel& fine = hierarchy.level(0);
    builtin::BlockGaussSeidel chunked(fine, precision), whole(fine, precision);
    ASSERT_TRUE(chunked.factor(fine) && whole.factor(fine));
    chunked.set_steps_per_chunk(fine, 3);
    whole.set_steps_per_chunk(fine, 1000);
    Eigen::VectorXd y = cloth.rhs(7), ry(y.size());
    whole.forward(fine, b.data(), y.data(), 2, ry.data());
    whole.backward(fine, b.data(), y.data(), 2);
    for (int threads : {1, 2}) {
      Eigen::VectorXd x = cloth.rhs(7), rx(x.size());
      chunked.forward(fine, b.data(), x.data(), 2, rx.data(), threads);
      chunked.backward(fine, b.data(), x.data(), 2, threads);
      for (Eigen::Index i = 0; i < x.size(); ++i) {
        ASSERT_EQ(x[i], y[i]) << threads << " threads, entry " << i;
        ASSERT_EQ(rx[i], ry[i]) << threads << " threads, residual entry " << i;
      }
    }
    // Chebyshev smoothing on the fine level's lanes (implicit_euler's on its coarse levels):
    // its rows are independent, so 1, 2 and 3 threads give the same bits.
    builtin::BlockChebyshev chebyshev(fine, precision);
    ASSERT_TRUE(chebyshev.factor(fine));
    std::vector<Eigen::VectorXd> smoothed;
    for (int threads : {1, 2, 3}) {
      Eigen::VectorXd x(b.size()), r(b.size());
      chebyshev.smooth_from_zero(fine, b.data(), x.data(), 2, r.data(), threads);
      chebyshev.smooth(fine, b.data(), x.data(), 2, threads);
      smoothed.push_back(x);
      smoothed.push_back(r);
    }
    EXPECT_GT(smoothed[0].norm(), 0.0);
    // The factor (inverted diagonal, bound, lanes) on 2 and 3 threads: the same bits.
    for (int threads : {2, 3}) {
      builtin::BlockChebyshev team(fine, precision);
      ASSERT_TRUE(team.factor(fine, threads));
      EXPECT_EQ(team.lambda_max(), chebyshev.lambda_max()) << threads << " threads";
      EXPECT_EQ(team.inverse_diagonal(), chebyshev.inverse_diagonal()) << threads << " threads";
      Eigen::VectorXd x(b.size()), r(b.size());
      team.smooth_from_zero(fine, b.data(), x.data(), 2, r.data(), 1);
      team.smooth(fine, b.data(), x.data(), 2, 1);
      for (Eigen::Index i = 0; i < x.size(); ++i) {
        ASSERT_EQ(x[i], smoothed[0][i]) << threads << " threads, entry " << i;
        ASSERT_EQ(r[i], smoothed[1][i]) << threads << " threads, residual entry " << i;
      }
    }
    // The lanes' steps against the recurrence written out on the level's own residual: the
    // same polynomial, to rounding in double lanes.
    if (precision == LanePrecision::float64) {
      const std::vector<double>& inverse = chebyshev.inverse_diagonal();
      const auto jacobi = [&](const Eigen::VectorXd& r) {
        Eigen::VectorXd out = Eigen::VectorXd::Zero(r.size());
        for (std::size_t i = 0; i < fine.node_count(); ++i)
          for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j)
              out[static_cast<Eigen::Index>(3 * i) + k] +=
                  inverse[9 * i + static_cast<std::size_t>(3 * k + j)] *
                  r[static_cast<Eigen::Index>(3 * i) + j];
        return out;
      };
      builtin::ChebyshevSteps steps(chebyshev.lambda_max());
      Eigen::VectorXd direction = steps.first_scale() * jacobi(b), x = direction, r(b.size());
      fine.residual(b.data(), x.data(), r.data());
      const builtin::ChebyshevSteps::Step next = steps.next();
      direction = next.keep * direction + next.scale * jacobi(r);
      x += direction;
      fine.residual(b.data(), x.data(), r.data());
      Eigen::VectorXd wave_x(b.size()), wave_r(b.size());
      chebyshev.smooth_from_zero(fine, b.data(), wave_x.data(), 2, wave_r.data(), 1);
      EXPECT_LT((wave_x - x).norm(), 1e-10 * x.norm());
      EXPECT_LT((wave_r - r).norm(), 1e-10 * r.norm());
    }
    for (std::size_t k = 2; k < smoothed.size(); ++k)
      for (Eigen::Index i = 0; i < b.size(); ++i)
        ASSERT_EQ(smoothed[k][i], smoothed[k % 2][i]) << k / 2 + 1 << " threads, entry " << i;
  }
}

// The two-grid method (exact coarse solve) as a stationary iteration e <- (I - B A) e: its
// convergence factor is well below 1 and nearly the same at every size, the property the
// V-cycle's resolution independence rests on.
TEST(Multigrid, TheTwoGridFactorIsSmallAndIndependentOfTheGrid) {
  std::vector<double> factors;
  for (int side : {9, 17, 33}) {
    ClothMatrix cloth(side, side);
    MultigridHierarchy hierarchy = hierarchy_for(cloth, side * side - 1);  // two levels
    VCycle cycle(hierarchy, 1);
    const SparseMatrix a = cloth.sparse();
    Eigen::VectorXd e = cloth.rhs(3);
    const auto energy = [&](const Eigen::VectorXd& v) { return std::sqrt(v.dot(a * v)); };
    double before = 0.0;
    for (int k = 0; k < 30; ++k) {
      if (k == 20) before = energy(e);
      e -= apply_cycle(cycle, a * e);
    }
    factors.push_back(std::pow(energy(e) / before, 1.0 / 10.0));
  }
  for (double factor : factors) EXPECT_LT(factor, 0.6);
  const auto [low, high] = std::minmax_element(factors.begin(), factors.end());
  EXPECT_LT(*high, *low + 0.15) << factors[0] << " " << factors[1] << " " << factors[2];
}

struct CgOutcome {
  Eigen::VectorXd x;
  long iterations;
};

CgOutcome multigrid_cg(ClothMatrix& cloth, const Eigen::VectorXd& b, double tolerance) {
  MultigridHierarchy hierarchy = hierarchy_for(cloth, builtin::kDefaultCoarsestNodes);
  VCycle cycle(hierarchy, 1);
  const SparseMatrix a = cloth.sparse();
  Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper, VCyclePreconditioner> cg;
  cg.preconditioner().cycle = &cycle;
  cg.setTolerance(tolerance);
  cg.setMaxIterations(500);
  cg.compute(a);
  return {cg.solve(b), static_cast<long>(cg.iterations())};
}

TEST(Multigrid, PreconditionedCgMatchesADirectSolve) {
  ClothMatrix cloth(21, 26);
  const SparseMatrix a = cloth.sparse();
  const Eigen::VectorXd b = cloth.rhs(4);
  Eigen::SimplicialLDLT<SparseMatrix> direct(a);
  ASSERT_EQ(direct.info(), Eigen::Success);
  const Eigen::VectorXd exact = direct.solve(b);
  for (double tolerance : {1e-6, 1e-10}) {
    const CgOutcome cg = multigrid_cg(cloth, b, tolerance);
    EXPECT_LE((b - a * cg.x).norm(), tolerance * b.norm());
    const Eigen::VectorXd error = cg.x - exact;
    // The error in the energy norm is bounded by the residual's in the inverse one.
    EXPECT_LE(std::sqrt(error.dot(a * error)), 1e3 * tolerance * std::sqrt(exact.dot(a * exact)))
        << tolerance;
    EXPECT_LT(cg.iterations, 40);
  }
}

// The iteration count to 1e-6 stays within 1.5x as the grid's side grows 4x, while CG with
// Eigen's diagonal preconditioner needs several times more.
TEST(Multigrid, CgIterationsBarelyGrowWithTheGrid) {
  std::vector<long> multigrid, jacobi;
  for (int side : {17, 33, 65}) {
    ClothMatrix cloth(side, side);
    const Eigen::VectorXd b = cloth.rhs(5);
    multigrid.push_back(multigrid_cg(cloth, b, 1e-6).iterations);
    const SparseMatrix a = cloth.sparse();
    Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper> diagonal(a);
    diagonal.setTolerance(1e-6);
    diagonal.setMaxIterations(5000);
    const Eigen::VectorXd x = diagonal.solve(b);  // solve() is lazy: evaluate it
    EXPECT_EQ(diagonal.info(), Eigen::Success) << x.norm();
    jacobi.push_back(static_cast<long>(diagonal.iterations()));
  }
  const auto [low, high] = std::minmax_element(multigrid.begin(), multigrid.end());
  EXPECT_LE(*high, 1.5 * *low) << multigrid[0] << " " << multigrid[1] << " " << multigrid[2];
  EXPECT_GT(jacobi.back(), 3 * jacobi.front()) << jacobi[0] << " " << jacobi[2];
  EXPECT_GT(jacobi.back(), 5 * multigrid.back());
}

TEST(Multigrid, CoarsensAsFarAsAsked) {
  EXPECT_EQ(builtin::plan_levels(60, 60, 256).back().rows, 16u);  // 60, 31, 16: 256 nodes
  EXPECT_EQ(builtin::plan_levels(60, 60, 1).size(), 7u);          // 60, 31, 16, 9, 5, 3, 2
  EXPECT_EQ(builtin::plan_levels(60, 60, 1).back().rows, 2u);
  // A strip two particles wide does not coarsen: its 4000 nodes are too many for the dense solve.
  try {
    (void)builtin::plan_levels(2, 2000, 256);
    ADD_FAILURE() << "a 2 x 2000 coarsest level accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(),
                 "the 2 x 2000 grid coarsens to no fewer than 2 x 2000 particles (a side "
                 "needs 3 to coarsen); the direct solve there takes at most 1024");
  }
}

// ---------------------------------------------------------------- through the plugin

// A rows x cols Provot net (structural, shear, flexion springs) 5 cm apart in a tilted plane,
// hanging from its top corners, offered as a grid.
template <class Real>
struct GridNetOf {
  static constexpr double kSpacing = 0.05;
  GridNetOf(uint32_t rows, uint32_t cols, bool on_grid = true)
      : host(rows * cols, {0, cols - 1}, provot_net_springs(rows, cols, kSpacing, 5e3, 50.0, 0.05),
             {0, -9.81, 0}) {
    for (uint32_t r = 0; r < rows; ++r)
      for (uint32_t c = 0; c < cols; ++c)
        host.system().set_position(r * cols + c, {kSpacing * c, -0.8 * kSpacing * r,
                                                  0.6 * kSpacing * r + 0.01 * std::sin(c)});
    if (on_grid) host.set_grid(rows, cols, kSpacing, {});
  }
  SpringHost<Real> host;
};
using GridNet = GridNetOf<double>;

// The preconditioner's product on a system: out = A u = u + J u, J the host's definite Jacobian
// at the system's state for backward Euler's step h.
template <class Real>
auto shifted_definite_product(const sdk::System<Real>& system, double h) {
  return [&system, h](const Real* in, Real* out) {
    system.definite_jacobian().apply(0.0, system.x(), system.v(), -h * h, -h, in, out);
    system.axpy(out, 1.0, in);
  };
}

// The matrix the plugin assembles by probing is M (I + J) for the host's definite J: its
// product with a vector against M (u + J u) from the host's own product and an axpy, with
// unequal masses.
TEST(Multigrid, TheProbedMatrixIsTheHostsOperator) {
  GridNet net(11, 13);
  MockSystem<double>& mock = net.host.system();
  for (uint32_t i = 0; i < 11 * 13; ++i) mock.set_mass(i, 0.5 + 0.125 * (i % 9));
  const sdk::System<double> system(mock.raw());
  mock.allocation_allowed = true;
  builtin::MultigridPreconditioner preconditioner(system, 0, 1);
  double* u = system.alloc_vector();
  double* au = system.alloc_vector();
  mock.allocation_allowed = false;
  const double h = 1.0 / 60.0;
  const auto product = shifted_definite_product(system, h);
  preconditioner.linearise(system, product);
  const std::size_t stride = system.stride(), n = system.particle_count();
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (std::size_t k = 0; k < 3 * stride; ++k) u[k] = uniform(random);
  // The ABI's products ignore u's pinned entries; this mock host does not.
  for (std::size_t d = 0; d < 3; ++d) u[d * stride] = u[d * stride + 12] = 0.0;
  product(u, au);
  const GridLevel& fine = preconditioner.hierarchy().level(0);
  std::vector<double> packed(3 * n, 0.0), su(3 * n, 0.0), zero(3 * n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t d = 0; d < 3; ++d) packed[3 * i + d] = fine.fixed(i) ? 0.0 : u[d * stride + i];
  fine.residual(zero.data(), packed.data(), su.data());  // -S u
  double worst = 0.0, scale = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (fine.fixed(i)) continue;
    for (std::size_t d = 0; d < 3; ++d) {
      const double expected = au[d * stride + i] / system.inverse_mass()[i];
      worst = std::max(worst, std::abs(-su[3 * i + d] - expected));
      scale = std::max(scale, std::abs(expected));
    }
  }
  // The fine level is stored rounded to single precision (a block wrong by probing is off by
  // its whole size).
  EXPECT_LT(worst, 1e-6 * scale);
}

// A block table of the host's definite J in the pattern of every 5 x 5 window, probed column
// by column with unit vectors (not the plugin's 25 classes): the table a host offers through
// clothlab.definite-jacobian/2.
struct ProbedTable {
  ProbedTable(const sdk::System<double>& system, int rows, int cols, double h) {
    const std::size_t n = system.particle_count(), stride = system.stride();
    offsets.push_back(0);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        for (int r2 = std::max(r - 2, 0); r2 < std::min(r + 3, rows); ++r2)
          for (int c2 = std::max(c - 2, 0); c2 < std::min(c + 3, cols); ++c2)
            columns.push_back(static_cast<uint32_t>(r2 * cols + c2));
        offsets.push_back(static_cast<uint32_t>(columns.size()));
      }
    values.assign(9 * columns.size(), 0.0);
    std::vector<double> unit(3 * stride, 0.0), image(3 * stride, 0.0);
    for (std::size_t j = 0; j < n; ++j)
      for (std::size_t d = 0; d < 3; ++d) {
        unit[d * stride + j] = 1.0;
        system.definite_jacobian().apply(0.0, system.x(), system.v(), -h * h, -h, unit.data(),
                                         image.data());
        unit[d * stride + j] = 0.0;
        for (std::size_t i = 0; i < n; ++i)
          for (uint32_t k = offsets[i]; k < offsets[i + 1]; ++k)
            if (columns[k] == j)
              for (std::size_t e = 0; e < 3; ++e) values[9 * k + 3 * e + d] = image[e * stride + i];
      }
  }
  clothlab_block_pattern pattern() const {
    return {sizeof(clothlab_block_pattern),
            static_cast<uint32_t>(offsets.size() - 1),
            static_cast<uint32_t>(columns.size()),
            0,
            offsets.data(),
            columns.data()};
  }
  std::vector<uint32_t> offsets, columns;
  std::vector<double> values;
};

// The net the table tests share: 24 x 19 (9 coarse rows, every third fine one kept: two bands
// of the Galerkin product, a fine row read by both; the middle rows follow their class's plan),
// masses that differ from particle to particle (a table block weighted by the wrong particle's
// mass shows), and the host's table of its definite J for a step of 1/60 s. The mock allows
// allocations until the test has made its own.
struct TabledNet {
  static constexpr int kRows = 24, kCols = 19;
  static constexpr double kStep = 1.0 / 60.0;
  static MockSystem<double>& with_uneven_masses(MockSystem<double>& mock) {
    for (uint32_t i = 0; i < kRows * kCols; ++i) mock.set_mass(i, 0.5 + 0.125 * (i % 9));
    mock.allocation_allowed = true;
    return mock;
  }
  GridNet net{kRows, kCols};
  MockSystem<double>& mock = with_uneven_masses(net.host.system());
  const sdk::System<double> system{mock.raw()};
  ProbedTable table{system, kRows, kCols, kStep};
};

// From a host's block table the fine level keeps no blocks: level 1 (its Galerkin product),
// D^-1 and the fine smoother's bound come straight from the table in one pass, and are the
// probed ones (to the single-precision rounding of the probed fine level's off-diagonal
// blocks), as is the V-cycle they make; a table with one off-diagonal block halved is caught.
TEST(Multigrid, LevelOneFromTheHostsBlockTableIsTheProbedOne) {
  TabledNet tabled_net;
  const sdk::System<double>& system = tabled_net.system;
  const ProbedTable& table = tabled_net.table;
  const double h = TabledNet::kStep;
  builtin::MultigridPreconditioner probed(system, 0, 1);
  builtin::MultigridPreconditioner tabled(system, 0, 1, 1, table.pattern());
  double* r = system.alloc_vector();
  double* z_probed = system.alloc_vector();
  double* z_tabled = system.alloc_vector();
  tabled_net.mock.allocation_allowed = false;
  const auto product = shifted_definite_product(system, h);
  probed.linearise(system, product);
  tabled.assemble(table.values.data());
  ASSERT_GT(tabled.hierarchy().transfer(0).planned_nodes(), 0u);
  const std::size_t vector_size = 3 * std::size_t{system.stride()};
  std::mt19937 random(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (std::size_t k = 0; k < vector_size; ++k) r[k] = uniform(random);
  std::fill_n(z_probed, vector_size, 0.0);
  std::fill_n(z_tabled, vector_size, 0.0);
  probed.apply(system, r, z_probed, product);
  tabled.apply(system, r, z_tabled, product);
  double z_size = 0.0, z_difference = 0.0;
  for (std::size_t k = 0; k < vector_size; ++k) {
    z_size = std::max(z_size, std::abs(z_probed[k]));
    z_difference = std::max(z_difference, std::abs(z_probed[k] - z_tabled[k]));
  }
  ASSERT_GT(z_size, 1e-3);
  EXPECT_LT(z_difference, 1e-6 * z_size);
  ASSERT_GT(tabled.hierarchy().level_count(), 2u);
  // The fine level's storage is its pin flags alone.
  EXPECT_EQ(tabled.hierarchy().level(0).storage_bytes(), tabled.hierarchy().level(0).node_count());
  const GridLevel& expected = probed.hierarchy().level(1);
  double size = 0.0;
  for (int r = 0; r < expected.rows(); ++r)
    for (int c = 0; c < expected.cols(); ++c)
      for (int e = 0; e < 9; ++e) size = std::max(size, std::abs(expected.block(r, c, r, c)[e]));
  ASSERT_GT(size, 1e-3);
  EXPECT_LT(level_difference(tabled.hierarchy().level(1), expected), 1e-6 * size);
  EXPECT_NEAR(tabled.lambda_max(), probed.lambda_max(), 1e-6 * probed.lambda_max());
  ASSERT_GT(probed.lambda_max(), 1.0);
  // The mutant: particle 5 x 6's block coupling it to 5 x 7 halved (the upper triangle's, which
  // both blocks of the pair are formed from: half of them off).
  std::vector<double> halved = table.values;
  const uint32_t row = 5 * TabledNet::kCols + 6;
  for (uint32_t k = table.offsets[row]; k < table.offsets[row + 1]; ++k)
    if (table.columns[k] == row + 1)
      for (std::size_t e = 0; e < 9; ++e) halved[9 * k + e] *= 0.5;
  tabled.assemble(halved.data());
  EXPECT_GT(level_difference(tabled.hierarchy().level(1), expected), 1e-3 * size);
}

// The Galerkin product's bands are fixed by the level, never by the thread count, and any band
// plan gives the same bits, from the host's table too, where a fine row under two bands is read
// by both (its D^-1 and bound formed on one of the reads): the V-cycle, level 1 and the fine
// bound with one band, the default two (9 coarse rows) and one coarse row per band.
TEST(Multigrid, TheTablesGalerkinProductHasTheSameBitsInOneBandAndSeveral) {
  TabledNet tabled_net;
  const sdk::System<double>& system = tabled_net.system;
  const ProbedTable& table = tabled_net.table;
  const double h = TabledNet::kStep;
  builtin::MultigridPreconditioner tabled(system, 0, 1, 1, table.pattern());
  double* r = system.alloc_vector();
  double* z = system.alloc_vector();
  tabled_net.mock.allocation_allowed = false;
  ASSERT_EQ(tabled.hierarchy().level(1).rows(), 9);
  const auto product = shifted_definite_product(system, h);
  const std::size_t size = 3 * std::size_t{system.stride()};
  std::mt19937 random(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (std::size_t k = 0; k < size; ++k) r[k] = uniform(random);
  std::vector<std::vector<double>> cycles;
  std::vector<GridLevel> levels;
  std::vector<double> bounds;
  for (const int band_rows : {9, 8, 1}) {
    tabled.set_band_rows(band_rows);
    tabled.assemble(table.values.data());
    std::fill_n(z, size, 0.0);
    tabled.apply(system, r, z, product);
    cycles.emplace_back(z, z + size);
    levels.push_back(tabled.hierarchy().level(1));
    bounds.push_back(tabled.lambda_max());
  }
  double z_size = 0.0;
  for (const double value : cycles[0]) z_size = std::max(z_size, std::abs(value));
  ASSERT_GT(z_size, 1e-3);
  for (std::size_t t = 1; t < cycles.size(); ++t) {
    EXPECT_EQ(level_difference(levels[t], levels[0]), 0.0) << t;
    EXPECT_EQ(bounds[t], bounds[0]) << t;
    std::size_t differing = 0;
    for (std::size_t k = 0; k < size; ++k) differing += cycles[t][k] != cycles[0][k];
    EXPECT_EQ(differing, 0u) << t;
  }
}

// A lower block of S = M (I + J) is read as the transpose of its upper one, so S is exactly
// symmetric. A host's blocks need not be symmetric themselves (a spring's are): with the upper
// blocks skewed, level 1 is P^T S P for S formed from the table's upper triangle (dense, in
// double), to the single-precision rounding of level 1's off-diagonal blocks.
TEST(Multigrid, LevelOneFromATableOfAsymmetricBlocksIsRapOfItsUpperTriangle) {
  TabledNet tabled_net;
  const sdk::System<double>& system = tabled_net.system;
  ProbedTable& table = tabled_net.table;
  builtin::MultigridPreconditioner tabled(system, 0, 1, 1, table.pattern());
  tabled_net.mock.allocation_allowed = false;
  const GridLevel& fine = tabled.hierarchy().level(0);
  const std::size_t n = fine.node_count();
  Eigen::MatrixXd s =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(3 * n), static_cast<Eigen::Index>(3 * n));
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t k = table.offsets[i]; k < table.offsets[i + 1]; ++k) {
      const uint32_t j = table.columns[k];
      double* d = &table.values[9 * std::size_t{k}];
      if (j < i || fine.fixed(i) || fine.fixed(j)) continue;
      if (j > i) d[1] += 0.1 * std::abs(d[0]) + 0.05 * std::abs(d[4]);  // skewed
      const double m = 1.0 / system.inverse_mass()[i];
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col) {
          const double entry =
              j == i ? m * d[3 * std::min(row, col) + std::max(row, col)] + (row == col ? m : 0.0)
                     : m * d[3 * row + col];
          s(3 * i + row, 3 * j + col) = s(3 * j + col, 3 * i + row) = entry;
        }
    }
  tabled.assemble(table.values.data());
  ASSERT_GT(tabled.hierarchy().transfer(0).planned_nodes(), 0u);
  std::vector<uint8_t> fixed(n);
  for (std::size_t i = 0; i < n; ++i) fixed[i] = fine.fixed(i) ? 1 : 0;
  const SparseMatrix p = bilinear_prolongation(TabledNet::kRows, TabledNet::kCols, fixed,
                                               builtin::kPreconditionerCoarsening);
  const Eigen::MatrixXd expected = Eigen::MatrixXd(p.transpose()) * s * Eigen::MatrixXd(p);
  const Eigen::MatrixXd coarse = dense_of(tabled.hierarchy().level(1));
  ASSERT_EQ(coarse.rows(), expected.rows());
  ASSERT_GT(expected.norm(), 0.0);
  EXPECT_LT((coarse - expected).norm(), 1e-6 * expected.norm());
}

// A block table whose pattern disagrees with the grid: one line naming the table and the
// disagreement, at construction.
TEST(Multigrid, RefusesABlockTableThatDisagreesWithTheGrid) {
  constexpr int kRows = 9, kCols = 10;
  GridNet net(kRows, kCols);
  MockSystem<double>& mock = net.host.system();
  const sdk::System<double> system(mock.raw());
  mock.allocation_allowed = true;
  ProbedTable table(system, kRows, kCols, 0.01);
  const auto message = [&](clothlab_block_pattern pattern) -> std::string {
    try {
      builtin::MultigridPreconditioner preconditioner(system, 0, 1, 1, pattern);
    } catch (const sdk::Error& error) {
      return error.what();
    }
    return "accepted";
  };
  clothlab_block_pattern short_by_a_row = table.pattern();
  short_by_a_row.row_count -= 1;
  EXPECT_EQ(message(short_by_a_row),
            "multigrid = 1: the host's block table (clothlab.jacobian/1 pattern) has 89 rows; "
            "the 9 x 10 grid has 90 particles");
  clothlab_block_pattern one_block_short = table.pattern();
  one_block_short.block_count -= 1;
  EXPECT_NE(message(one_block_short).find("its blocks are 0 to"), std::string::npos);
  // Row 1 without its block of particle 0, which row 0 has: no transpose to symmetrise with.
  std::vector<uint32_t> offsets = table.offsets, columns = table.columns;
  columns.erase(columns.begin() + offsets[1]);
  for (std::size_t k = 2; k < offsets.size(); ++k) --offsets[k];
  const clothlab_block_pattern lopsided{sizeof(clothlab_block_pattern),
                                        static_cast<uint32_t>(offsets.size() - 1),
                                        static_cast<uint32_t>(columns.size()),
                                        0,
                                        offsets.data(),
                                        columns.data()};
  EXPECT_EQ(message(lopsided),
            "multigrid = 1: the host's block table (clothlab.jacobian/1 pattern) couples particle "
            "0 to 1 but not 1 to 0");
  table.columns[0] = 3;  // particle 0 to particle 3: three spacings along its row
  EXPECT_EQ(message(table.pattern()),
            "multigrid = 1: the host's block table (clothlab.jacobian/1 pattern) couples particle "
            "0 to 3 (columns must ascend and lie within two grid spacings)");
}

// The fine level's matrix-free Chebyshev smoother: its bound on D^-1 A's eigenvalues (D the
// diagonal blocks) lies above the largest one and within 1.5 times it (lambda D - S positive
// definite or not, for the probed S = M A and its diagonal blocks D_S); a bound below would let
// the polynomial amplify the stiffest modes. The whole cycle z = B M r is symmetric and positive in
// the mass inner product (r1^T M z2 = r2^T M z1, r^T M z > 0).
TEST(Multigrid, TheFineChebyshevSmootherBoundsTheSpectrumAndKeepsTheCycleSymmetric) {
  GridNet net(14, 17);
  MockSystem<double>& mock = net.host.system();
  const sdk::System<double> system(mock.raw());
  mock.allocation_allowed = true;
  builtin::MultigridPreconditioner preconditioner(system, 0, 2);
  double* r1 = system.alloc_vector();
  double* r2 = system.alloc_vector();
  double* z1 = system.alloc_vector();
  double* z2 = system.alloc_vector();
  mock.allocation_allowed = false;
  const double h = 1.0 / 60.0;
  const auto product = shifted_definite_product(system, h);
  preconditioner.linearise(system, product);
  ASSERT_GT(preconditioner.hierarchy().level_count(), 1u);

  const GridLevel& fine = preconditioner.hierarchy().level(0);
  std::vector<Eigen::Index> free_unknowns;
  for (std::size_t i = 0; i < fine.node_count(); ++i)
    if (!fine.fixed(i))
      for (Eigen::Index d = 0; d < 3; ++d)
        free_unknowns.push_back(3 * static_cast<Eigen::Index>(i) + d);
  const Eigen::MatrixXd all = dense_of(fine);
  const auto n = static_cast<Eigen::Index>(free_unknowns.size());
  Eigen::MatrixXd s(n, n), diagonal = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index a = 0; a < n; ++a)
    for (Eigen::Index b = 0; b < n; ++b) {
      s(a, b) = all(free_unknowns[a], free_unknowns[b]);
      if (free_unknowns[a] / 3 == free_unknowns[b] / 3) diagonal(a, b) = s(a, b);
    }
  // lambda D - S is positive definite for lambda above D^-1 S's largest eigenvalue only.
  const auto above_the_spectrum = [&](double lambda) {
    return Eigen::LLT<Eigen::MatrixXd>(lambda * diagonal - s).info() == Eigen::Success;
  };
  const double bound = preconditioner.lambda_max();
  EXPECT_TRUE(above_the_spectrum(bound * (1.0 + 1e-9))) << bound;
  EXPECT_FALSE(above_the_spectrum(bound / 1.5)) << bound;

  const std::size_t stride = system.stride();
  std::mt19937 random(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (std::size_t k = 0; k < 3 * stride; ++k) r1[k] = uniform(random), r2[k] = uniform(random);
  preconditioner.apply(system, r1, z1, product);
  preconditioner.apply(system, r2, z2, product);
  const auto mass_dot = [&](const double* a, const double* b) {
    double sum = 0.0;
    for (const clothlab_range& range : system.active())
      for (uint32_t i = range.begin; i < range.end; ++i)
        for (std::size_t d = 0; d < 3; ++d)
          sum += a[d * stride + i] * b[d * stride + i] / system.inverse_mass()[i];
    return sum;
  };
  const double r1z2 = mass_dot(r1, z2), r2z1 = mass_dot(r2, z1);
  EXPECT_LT(std::abs(r1z2 - r2z1), 1e-10 * std::abs(r1z2));
  EXPECT_GT(mass_dot(r1, z1), 0.0);
  EXPECT_GT(mass_dot(r2, z2), 0.0);
}

// A float32 system's V-cycle (D^-1 kept in single precision, the fine passes over its float
// products, the coarse levels in float lanes) gives the float64 system's z = B M r for the same
// cloth and r to single precision's rounding. The masses differ from particle to particle, so a
// mass left out of either precision's D^-1 shows.
TEST(Multigrid, TheSinglePrecisionCycleIsTheDoubleOneToRounding) {
  constexpr uint32_t kRows = 21, kCols = 13;
  const double h = 1.0 / 60.0;
  std::vector<double> r_values(3 * kRows * kCols);
  std::mt19937 random(9);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  for (double& value : r_values) value = uniform(random);  // exact in both precisions
  const auto cycle = [&](auto zero) {
    using Real = decltype(zero);
    GridNetOf<Real> net(kRows, kCols);
    MockSystem<Real>& mock = net.host.system();
    for (uint32_t i = 0; i < kRows * kCols; ++i) mock.set_mass(i, 0.5 + 0.125 * (i % 9));
    const sdk::System<Real> system(mock.raw());
    mock.allocation_allowed = true;
    builtin::MultigridPreconditioner preconditioner(system, 0, 2);
    Real* r = system.alloc_vector();
    Real* z = system.alloc_vector();
    mock.allocation_allowed = false;
    const auto product = shifted_definite_product(system, h);
    preconditioner.linearise(system, product);
    EXPECT_GT(preconditioner.hierarchy().level_count(), 2u);
    const std::size_t stride = system.stride();
    for (std::size_t i = 0; i < kRows * kCols; ++i)
      for (std::size_t d = 0; d < 3; ++d)
        r[d * stride + i] = static_cast<Real>(r_values[3 * i + d]);
    std::fill_n(z, 3 * stride, Real{0});
    preconditioner.apply(system, r, z, product);
    std::vector<double> out(3 * kRows * kCols);
    for (std::size_t i = 0; i < kRows * kCols; ++i)
      for (std::size_t d = 0; d < 3; ++d) out[3 * i + d] = z[d * stride + i];
    return out;
  };
  const std::vector<double> single = cycle(0.0f), exact = cycle(0.0);
  double size = 0.0, difference = 0.0;
  for (std::size_t k = 0; k < exact.size(); ++k) {
    size = std::max(size, std::abs(exact[k]));
    difference = std::max(difference, std::abs(single[k] - exact[k]));
  }
  ASSERT_GT(size, 1e-3);
  EXPECT_LT(difference, 1e-5 * size) << "largest |z| " << size;
}

// The multigrid-preconditioned CG splits the V-cycle's passes (the fine level's vector
// passes, the transfers, the coarse levels' Chebyshev steps) among the host's threads; every
// entry is summed in one order on any count, so CG's iterates have the same bits on 1, 2 and 3
// threads (65 x 65: the fine level is large enough to split; the coarse levels' Chebyshev on a
// level that splits is TheVCycleHasTheSameBitsOnOneAndTwoThreads').
TEST(Multigrid, CgIteratesHaveTheSameBitsOnOneTwoAndThreeThreads) {
  constexpr uint32_t kSide = 65;
  constexpr int kIterations = 4;
  const double h = 1.0 / 60.0;
  std::vector<std::vector<double>> iterates;
  for (uint32_t threads : {1u, 2u, 3u}) {
    GridNet net(kSide, kSide);
    net.host.set_threads(threads);
    MockSystem<double>& mock = net.host.system();
    const sdk::System<double> system(mock.raw());
    mock.allocation_allowed = true;
    builtin::MultigridPreconditioner preconditioner(system, builtin::kDefaultCoarsestNodes, 2);
    std::array<double*, builtin::PreconditionedCg<double>::vector_count> vectors{};
    for (double*& vector : vectors) vector = system.alloc_vector();
    double* rhs = system.alloc_vector();
    double* solution = system.alloc_vector();
    mock.allocation_allowed = false;
    const std::size_t size = 3 * std::size_t{system.stride()};
    std::vector<double> inverse_blocks(9 * std::size_t{system.particle_count()});
    builtin::PreconditionedCg<double> cg(system, vectors, inverse_blocks, true, false,
                                         &preconditioner);
    std::mt19937 random(5);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    for (std::size_t k = 0; k < size; ++k) rhs[k] = uniform(random);
    std::fill_n(solution, size, 0.0);
    cg.start(0.0, h, system.x(), system.v(), rhs, solution, false, 1e-12);
    ASSERT_TRUE(preconditioner.hierarchy().level(0).splits(static_cast<int>(threads)) ||
                threads == 1);
    for (int k = 0; k < kIterations; ++k)
      ASSERT_EQ(cg.iterate(), builtin::PreconditionedCg<double>::Outcome::kRunning) << k;
    cg.finish();
    EXPECT_LT(cg.residual_norm(), 0.1 * cg.rhs_norm()) << threads << " threads";
    iterates.emplace_back(solution, solution + size);
  }
  for (std::size_t t = 1; t < iterates.size(); ++t)
    for (std::size_t k = 0; k < iterates[0].size(); ++k)
      ASSERT_EQ(iterates[t][k], iterates[0][k]) << t + 1 << " threads, entry " << k;
}

// implicit_euler's positions after `steps` steps of 1/60 s on a rows x cols net, solved tightly
// (`configure` adds settings), and its CG iterations; every step must converge.
struct TightSteps {
  std::vector<Vec3> positions;
  uint64_t iterations = 0;
};
template <class Configure>
TightSteps tight_implicit_euler_steps(uint32_t rows, uint32_t cols, int steps,
                                      Configure&& configure) {
  TightSteps out;
  GridNet net(rows, cols);
  Integrator integrator("implicit_euler");
  integrator.with("tolerance", 1e-10).with("max_iterations", 5000);
  configure(integrator);
  integrator.start(net.host.system());
  for (int n = 0; n < steps; ++n) {
    EXPECT_EQ(integrator.step(net.host.system(), n / 60.0, 1 / 60.0), CLOTHLAB_OK)
        << integrator.message();
    const clothlab_solver_step_statistics stats = solver_statistics_of(integrator);
    EXPECT_EQ(stats.converged, 1u) << "step " << n;
    out.iterations += stats.iterations;
  }
  for (uint32_t i = 0; i < rows * cols; ++i) out.positions.push_back(net.host.system().position(i));
  return out;
}

// Steps with the multigrid preconditioner reach the state block-Jacobi's reach (both solved
// tightly) in fewer iterations.
TEST(Multigrid, ImplicitEulerWithMultigridMatchesBlockJacobi) {
  const auto run = [](double multigrid) {
    return tight_implicit_euler_steps(14, 17, 5,
                                      [&](Integrator& i) { i.with("multigrid", multigrid); });
  };
  const TightSteps jacobi = run(0.0), multigrid = run(1.0);
  EXPECT_LT(largest_difference(jacobi.positions, multigrid.positions), 1e-8);
  EXPECT_LT(2 * multigrid.iterations, jacobi.iterations)
      << multigrid.iterations << " vs " << jacobi.iterations;
}

// multigrid_rebuild = 4 builds the hierarchy (one coarsest factorisation each, in the step
// statistics) on steps 0 and 4 only, again when the step size changes and after a new prepare,
// and its steps reach rebuild = 1's state to the CG tolerance: CG's products use the current
// matrix whichever hierarchy preconditions them.
TEST(Multigrid, ImplicitEulerReusesTheHierarchyBetweenRebuilds) {
  const double h = 1.0 / 60.0;
  const std::vector<double> steps{h, h, h, h, h, h, 0.5 * h, 0.5 * h};
  std::vector<Vec3> positions[2];
  std::vector<uint64_t> factorizations[2];
  for (const int rebuild : {1, 4}) {
    const bool reusing = rebuild > 1;
    GridNet net(14, 17);
    Integrator integrator("implicit_euler");
    integrator.with("multigrid", 1.0)
        .with("multigrid_rebuild", rebuild)
        .with("tolerance", 1e-10)
        .with("max_iterations", 5000);
    integrator.start(net.host.system());
    double t = 0.0;
    for (const double dt : steps) {
      ASSERT_EQ(integrator.step(net.host.system(), t, dt), CLOTHLAB_OK) << integrator.message();
      t += dt;
      const clothlab_solver_step_statistics stats = solver_statistics_of(integrator);
      ASSERT_EQ(stats.converged, 1u) << "t " << t << " rebuild " << rebuild;
      factorizations[reusing].push_back(stats.factorizations);
    }
    ASSERT_EQ(integrator.prepare(net.host.system()), CLOTHLAB_OK) << integrator.message();
    ASSERT_EQ(integrator.step(net.host.system(), t, 0.5 * h), CLOTHLAB_OK) << integrator.message();
    factorizations[reusing].push_back(solver_statistics_of(integrator).factorizations);
    for (uint32_t i = 0; i < 14 * 17; ++i)
      positions[reusing].push_back(net.host.system().position(i));
  }
  EXPECT_EQ(factorizations[0], std::vector<uint64_t>(steps.size() + 1, 1));
  // Steps 0 and 4 by the interval, 6 for the new h, then the first after prepare.
  EXPECT_EQ(factorizations[1], (std::vector<uint64_t>{1, 0, 0, 0, 1, 0, 1, 0, 1}));
  EXPECT_LT(largest_difference(positions[0], positions[1]), 1e-8);
}

TEST(Multigrid, ImplicitEulerRefusesARebuildIntervalOutOfRange) {
  for (const double rebuild : {0.0, 1025.0}) {
    Integrator integrator("implicit_euler");
    integrator.with("multigrid_rebuild", rebuild);
    EXPECT_NE(integrator.create(), CLOTHLAB_OK);
    EXPECT_NE(integrator.message().find("multigrid_rebuild"), std::string::npos)
        << integrator.message();
  }
}

// implicit_euler refuses `setting` at each of `values` in one line naming it and its `range`.
void expect_implicit_euler_refuses(const std::string& setting, std::initializer_list<double> values,
                                   const std::string& range) {
  for (const double value : values) {
    Integrator integrator("implicit_euler");
    integrator.with(setting, value);
    EXPECT_NE(integrator.create(), CLOTHLAB_OK) << setting << " = " << value;
    const std::string message = integrator.message();
    EXPECT_NE(message.find(setting), std::string::npos) << message;
    EXPECT_NE(message.find(range), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

// The V-cycle's smoothing budget (Chebyshev products on the fine level, sweeps below): 0 or more
// than 8 is refused in one line naming the setting and its range.
TEST(Multigrid, ImplicitEulerRefusesASmoothingBudgetOutOfRange) {
  expect_implicit_euler_refuses("multigrid_sweeps", {0.0, 9.0}, "[1, 8]");
}

// multigrid_coarsening reaches the hierarchy: every other node kept (2) takes fewer CG
// iterations than every third (3) on the same steps, both solved tightly to the same state.
TEST(Multigrid, ImplicitEulerCoarsensByItsSetting) {
  const auto run = [](double coarsening) {
    return tight_implicit_euler_steps(40, 40, 3, [&](Integrator& i) {
      i.with("multigrid", 1.0)
          .with("multigrid_coarsening", coarsening)
          .with("multigrid_coarsest", 16.0);
    });
  };
  const TightSteps every_other = run(2.0), every_third = run(3.0);
  EXPECT_LT(largest_difference(every_other.positions, every_third.positions), 1e-8);
  EXPECT_LT(every_other.iterations, every_third.iterations)
      << every_other.iterations << " vs " << every_third.iterations;
}

// A coarsening other than 2 or 3 is refused in one line naming the setting and its range.
TEST(Multigrid, ImplicitEulerRefusesACoarseningOutOfRange) {
  expect_implicit_euler_refuses("multigrid_coarsening", {1.0, 4.0}, "[2, 3]");
}

TEST(Multigrid, ImplicitEulerRefusesANonGridAndAGridThatDoesNotCoarsen) {
  {
    GridNet net(6, 6, false);
    Integrator integrator("implicit_euler");
    integrator.with("multigrid", 1.0);
    ASSERT_EQ(integrator.create(), CLOTHLAB_OK);
    EXPECT_NE(integrator.prepare(net.host.system()), CLOTHLAB_OK);
    EXPECT_NE(integrator.message().find("needs a cloth laid out as a grid"), std::string::npos)
        << integrator.message();
  }
  {
    GridNet net(2, 600);
    Integrator integrator("implicit_euler");
    integrator.with("multigrid", 1.0);
    ASSERT_EQ(integrator.create(), CLOTHLAB_OK);
    EXPECT_NE(integrator.prepare(net.host.system()), CLOTHLAB_OK);
    EXPECT_EQ(integrator.message(),
              "multigrid = 1: the 2 x 600 grid coarsens to no fewer than 2 x 600 particles (a side "
              "needs 3 to coarsen); the direct solve there takes at most 1024");
  }
  {
    // A spring three columns long reaches past the levels' 5 x 5 block windows.
    std::vector<TestSpring> springs = provot_net_springs(6, 6, GridNet::kSpacing, 5e3, 50.0, 0.05);
    springs.push_back({0, 3, 3 * GridNet::kSpacing, 5e3, 0.05});
    SpringHost<double> host(36, {0, 5}, springs, {0, -9.81, 0});
    host.set_grid(6, 6, GridNet::kSpacing, {});
    Integrator integrator("implicit_euler");
    integrator.with("multigrid", 1.0);
    ASSERT_EQ(integrator.create(), CLOTHLAB_OK);
    EXPECT_NE(integrator.prepare(host.system()), CLOTHLAB_OK);
    EXPECT_EQ(integrator.message(),
              "multigrid = 1: spring " + std::to_string(springs.size() - 1) +
                  " joins particles 0 and 3, more than 2 grid spacings apart");
  }
}

}  // namespace
}  // namespace clothlab::test
