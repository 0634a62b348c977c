// clothlab.definite-jacobian/1 on the engine: where every spring is stretched it is the exact
// Hooke Jacobian plus the damping's velocity part (clothlab.jacobian/1, itself checked against
// finite differences); where springs are compressed it drops exactly their transverse
// stiffness; M D is symmetric and D (c_x, c_v < 0) positive, so I + D is definite; its
// diagonal blocks reproduce the product's diagonal; its block table (clothlab.definite-jacobian/2)
// is the product's matrix, column by column, on the grid and the spring-list path (and a
// table with one block halved or two swapped is caught); the same bits, product and table, on
// one and several threads.
#include <clothlab/ext/definite_jacobian.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "extension_support.hpp"

namespace clothlab {
namespace {

using testing::host_extension;
using testing::max_abs;
using testing::max_difference;
using testing::values_of;
using testing::vector_from;

// A float64 cloth scaled by `scale` about its first particle (> 1: every spring stretched,
// < 1: every spring compressed), with velocities and two directions u, w (0 where pinned).
struct Scaled {
  Scaled(double scale, PipelineOptions options = {}, uint32_t rows = 7, uint32_t cols = 6)
      : scene(windless(rows, cols)),
        cloth(scene, Precision::Float64, options),
        system(cloth.system()) {
    cloth.positions(x);
    v.assign(x.size(), 0.0);
    u.assign(x.size(), 0.0);
    w.assign(x.size(), 0.0);
    for (std::size_t e = 0; e < x.size(); ++e) {
      x[e] = x[e % 3] + scale * (x[e] - x[e % 3]);
      v[e] = std::cos(0.7 * static_cast<double>(e));
      u[e] = std::sin(0.37 * static_cast<double>(e) + 0.1);
      w[e] = std::cos(0.53 * static_cast<double>(e) + 0.4);
    }
    for (uint32_t pinned : scene.pinned)
      for (std::size_t k = 0; k < 3; ++k) u[3 * pinned + k] = w[3 * pinned + k] = 0;
    cloth.set_state(x, v);
    exact = &host_extension<clothlab_jacobian_extension>(system, CLOTHLAB_EXT_JACOBIAN);
    definite = &host_extension<clothlab_definite_jacobian_extension>(
        system, CLOTHLAB_EXT_DEFINITE_JACOBIAN);
    EXPECT_EQ(exact->reserve(system.context), CLOTHLAB_OK);
  }
  static Scene windless(uint32_t rows, uint32_t cols) {
    Scene scene = testing::busy_scene(rows, cols);
    scene.wind_strength = 0.0;
    return scene;
  }

  // The exact (clothlab.jacobian/1) or definite product at the stored state.
  std::vector<double> apply(bool use_definite, double c_x, double c_v, bool with_velocity,
                            const std::vector<double>& direction) {
    const auto call = use_definite ? definite->apply : exact->apply;
    void* out = system.alloc_vector(system.context);
    EXPECT_EQ(call(system.context, 0.0, system.x, with_velocity ? system.v : nullptr, c_x, c_v,
                   vector_from<double>(system, direction), out),
              CLOTHLAB_OK);
    return values_of<double>(system, out);
  }
  double inverse_mass(std::size_t i) const {
    return static_cast<const double*>(system.inverse_mass)[i];
  }
  double mass_dot(const std::vector<double>& a, const std::vector<double>& b) const {
    double sum = 0;
    for (std::size_t e = 0; e < a.size(); ++e) {
      if (inverse_mass(e / 3) > 0) sum += a[e] * b[e] / inverse_mass(e / 3);
    }
    return sum;
  }

  Scene scene;
  Cloth cloth;
  const clothlab_system& system;
  std::vector<double> x, v, u, w;
  const clothlab_jacobian_extension* exact = nullptr;
  const clothlab_definite_jacobian_extension* definite = nullptr;
};

TEST(DefiniteJacobian, OnAStretchedClothIsTheHookeJacobianPlusTheVelocityPart) {
  Scaled cloth(1.2);
  const std::vector<double> hooke = cloth.apply(false, 0.8, 0.0, false, cloth.u);
  const std::vector<double> velocity = cloth.apply(false, 0.0, 0.3, true, cloth.u);
  const std::vector<double> definite = cloth.apply(true, 0.8, 0.3, true, cloth.u);
  std::vector<double> sum(hooke.size());
  for (std::size_t e = 0; e < sum.size(); ++e) sum[e] = hooke[e] + velocity[e];
  ASSERT_GT(max_abs(velocity), 1e-5 * max_abs(hooke));  // both parts are there
  EXPECT_LT(max_difference(definite, sum), 1e-12 * max_abs(sum));
  // The exact x-derivative differs: it has the damping's turning term.
  EXPECT_GT(max_difference(cloth.apply(false, 0.8, 0.3, true, cloth.u), sum), 1e-6 * max_abs(sum));
}

TEST(DefiniteJacobian, OnACompressedClothDropsExactlyTheTransverseStiffness) {
  Scaled cloth(0.8);
  const std::vector<double> hooke = cloth.apply(false, 1.0, 0.0, false, cloth.u);
  const std::vector<double> definite = cloth.apply(true, 1.0, 0.0, false, cloth.u);
  // Exact minus definite: per spring ks (1 - l0/l) (I - n n^T) (u_j - u_i) / m at each end.
  const clothlab_topology topology = testing::topology_of(cloth.system);
  std::vector<double> transverse(hooke.size(), 0.0);
  for (uint32_t s = 0; s < topology.spring_count; ++s) {
    const std::size_t i = topology.first[s], j = topology.second[s];
    double d[3], du[3], length = 0, along = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      d[k] = cloth.x[3 * j + k] - cloth.x[3 * i + k];
      du[k] = cloth.u[3 * j + k] - cloth.u[3 * i + k];
      length += d[k] * d[k];
    }
    length = std::sqrt(length);
    for (std::size_t k = 0; k < 3; ++k) along += d[k] / length * du[k];
    const double stiffness = topology.ks[s] * (1.0 - topology.rest_length[s] / length);
    ASSERT_LT(stiffness, 0.0) << "spring " << s << " is not compressed";
    for (std::size_t k = 0; k < 3; ++k) {
      const double f = stiffness * (du[k] - along * d[k] / length);
      transverse[3 * i + k] += f * cloth.inverse_mass(i);
      transverse[3 * j + k] -= f * cloth.inverse_mass(j);
    }
  }
  std::vector<double> difference(hooke.size());
  for (std::size_t e = 0; e < hooke.size(); ++e) difference[e] = hooke[e] - definite[e];
  ASSERT_GT(max_abs(transverse), 1e-3 * max_abs(hooke));
  EXPECT_LT(max_difference(difference, transverse), 1e-10 * max_abs(hooke));
}

TEST(DefiniteJacobian, IsSymmetricInTheMassProductAndMakesTheNewtonMatrixDefinite) {
  for (const double scale : {0.8, 1.2}) {
    Scaled cloth(scale);
    const double h = 0.05;
    const std::vector<double> du = cloth.apply(true, -h * h, -h, true, cloth.u);
    const std::vector<double> dw = cloth.apply(true, -h * h, -h, true, cloth.w);
    const double uDw = cloth.mass_dot(cloth.u, dw), wDu = cloth.mass_dot(cloth.w, du);
    EXPECT_NEAR(uDw, wDu, 1e-10 * (std::abs(uDw) + std::abs(wDu))) << "scale " << scale;
    // With c_x, c_v < 0, D itself is positive (so I + D is definite), also where springs are
    // compressed: u^T M D u > 0 along u and w.
    EXPECT_GT(cloth.mass_dot(cloth.u, du), 0.0) << "scale " << scale;
    EXPECT_GT(cloth.mass_dot(cloth.w, dw), 0.0) << "scale " << scale;
  }
}

TEST(DefiniteJacobian, DiagonalBlocksAreTheProductsDiagonal) {
  Scaled cloth(0.9);
  std::vector<double> blocks(9 * std::size_t{cloth.system.particle_count});
  ASSERT_EQ(cloth.definite->diagonal_blocks(cloth.system.context, 0.0, cloth.system.x,
                                            cloth.system.v, 0.7, 0.2, blocks.data()),
            CLOTHLAB_OK);
  // D applied to a unit vector at particle i, component c: column c of block i at particle i.
  const std::size_t n = cloth.system.particle_count;
  for (const std::size_t i : {std::size_t{8}, n / 2, n - 2})
    for (std::size_t c = 0; c < 3; ++c) {
      std::vector<double> unit(3 * n, 0.0);
      unit[3 * i + c] = 1.0;
      const std::vector<double> column = cloth.apply(true, 0.7, 0.2, true, unit);
      for (std::size_t r = 0; r < 3; ++r)
        EXPECT_NEAR(column[3 * i + r], blocks[9 * i + 3 * r + c], 1e-12 * max_abs(blocks) + 1e-300)
            << i << " " << r << " " << c;
    }
}

// The largest difference between the matrix of a block table (the pattern's blocks, zero
// elsewhere) and the definite product's, probed with every unit vector of the free particles;
// rows and columns of pinned particles are zero in both (the table's checked block by block).
double table_against_products(Scaled& cloth, const clothlab_block_pattern& pattern,
                              const std::vector<double>& values, double c_x, double c_v) {
  const std::size_t n = cloth.system.particle_count;
  double worst = 0;
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t c = 0; c < 3; ++c) {
      if (cloth.inverse_mass(j) == 0.0) continue;
      std::vector<double> unit(3 * n, 0.0);
      unit[3 * j + c] = 1.0;
      const std::vector<double> column = cloth.apply(true, c_x, c_v, true, unit);
      std::vector<double> from_table(3 * n, 0.0);
      for (std::size_t i = 0; i < n; ++i)
        for (uint32_t k = pattern.row_offsets[i]; k < pattern.row_offsets[i + 1]; ++k)
          if (pattern.columns[k] == j)
            for (std::size_t r = 0; r < 3; ++r) from_table[3 * i + r] = values[9 * k + 3 * r + c];
      worst = std::max(worst, max_difference(column, from_table));
    }
  // The table's blocks in the rows and columns of pinned particles, which no product probes.
  for (std::size_t i = 0; i < n; ++i)
    for (uint32_t k = pattern.row_offsets[i]; k < pattern.row_offsets[i + 1]; ++k)
      if (cloth.inverse_mass(i) == 0.0 || cloth.inverse_mass(pattern.columns[k]) == 0.0)
        for (std::size_t e = 0; e < 9; ++e) worst = std::max(worst, std::abs(values[9 * k + e]));
  return worst;
}

TEST(DefiniteJacobian, TheBlockTableIsTheProductsMatrixOnTheGridAndTheSpringList) {
  for (const bool general : {false, true})
    for (const double scale : {0.85, 1.15}) {
      PipelineOptions options;
      options.force_general_path = general;
      Scaled cloth(scale, options);
      const auto& table = host_extension<clothlab_definite_jacobian_2_extension>(
          cloth.system, CLOTHLAB_EXT_DEFINITE_JACOBIAN_2);
      clothlab_block_pattern pattern{};
      pattern.struct_size = sizeof pattern;
      ASSERT_EQ(cloth.exact->pattern(cloth.system.context, &pattern), CLOTHLAB_OK);
      // NaN before the call: the table is written whole, whatever the buffer held.
      std::vector<double> values(9 * std::size_t{pattern.block_count},
                                 std::numeric_limits<double>::quiet_NaN());
      ASSERT_EQ(table.blocks(cloth.system.context, 0.0, cloth.system.x, cloth.system.v, 0.7, 0.2,
                             values.data()),
                CLOTHLAB_OK);
      const double size = max_abs(values);
      const std::string where =
          (general ? "spring list, scale " : "grid, scale ") + std::to_string(scale);
      EXPECT_LT(table_against_products(cloth, pattern, values, 0.7, 0.2), 1e-12 * size) << where;
      // Mutants the comparison must catch: an off-diagonal block halved, and two off-diagonal
      // blocks of a row swapped (a block in another's slot).
      // The first free row with two off-diagonal blocks of free particles.
      std::vector<uint32_t> off_diagonal;
      for (uint32_t row = 0; row < pattern.row_count && off_diagonal.size() < 2; ++row) {
        off_diagonal.clear();
        if (cloth.inverse_mass(row) == 0.0) continue;
        for (uint32_t k = pattern.row_offsets[row]; k < pattern.row_offsets[row + 1]; ++k)
          if (pattern.columns[k] != row && cloth.inverse_mass(pattern.columns[k]) > 0.0)
            off_diagonal.push_back(k);
      }
      ASSERT_GE(off_diagonal.size(), 2u);
      std::vector<double> halved = values, swapped = values;
      for (std::size_t e = 0; e < 9; ++e) {
        halved[9 * off_diagonal[0] + e] *= 0.5;
        std::swap(swapped[9 * off_diagonal[0] + e], swapped[9 * off_diagonal[1] + e]);
      }
      EXPECT_GT(table_against_products(cloth, pattern, halved, 0.7, 0.2), 1e-3 * size) << where;
      EXPECT_GT(table_against_products(cloth, pattern, swapped, 0.7, 0.2), 1e-3 * size) << where;
    }
}

TEST(DefiniteJacobian, SameBitsOnOneAndSeveralThreads) {
  std::vector<double> reference, reference_table;
  for (int threads : {1, 2, 3}) {
    PipelineOptions options;
    options.threads = threads;
    Scaled cloth(0.95, options, 80, 70);  // large enough to run threaded
    const std::vector<double> product = cloth.apply(true, 1.0, 0.1, true, cloth.u);
    clothlab_block_pattern pattern{};
    pattern.struct_size = sizeof pattern;
    ASSERT_EQ(cloth.exact->pattern(cloth.system.context, &pattern), CLOTHLAB_OK);
    std::vector<double> table(9 * std::size_t{pattern.block_count});
    ASSERT_EQ(host_extension<clothlab_definite_jacobian_2_extension>(
                  cloth.system, CLOTHLAB_EXT_DEFINITE_JACOBIAN_2)
                  .blocks(cloth.system.context, 0.0, cloth.system.x, cloth.system.v, 1.0, 0.1,
                          table.data()),
              CLOTHLAB_OK);
    if (reference.empty()) {
      reference = product;
      reference_table = table;
    } else {
      EXPECT_EQ(product, reference) << threads << " threads";
      EXPECT_EQ(table, reference_table) << threads << " threads, the block table";
    }
  }
}

}  // namespace
}  // namespace clothlab
