// The engine's host extensions against the reference system's (plain serial loops that
// scatter spring by spring, another algebraic form of the spring Jacobian): the same state in
// both, the same products, blocks, pattern, reductions and external forces.
#include <clothlab/ext/definite_jacobian.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "extension_support.hpp"
#include "reference_system.hpp"

namespace clothlab {
namespace {

using testing::host_extension;
using testing::max_abs;
using testing::values_of;
using testing::vector_from;

template <class Real>
struct Pair {
  explicit Pair(const Scene& scene)
      : cloth(scene, sizeof(Real) == 4 ? Precision::Float32 : Precision::Float64, {}),
        reference(scene, true) {
    testing::move_off_rest(cloth, 11, 0.05, x, v);
    direction.resize(x.size());
    for (std::size_t e = 0; e < x.size(); ++e) direction[e] = std::cos(0.23 * double(e));
    const clothlab_system& r = reference.system();
    r.copy(r.context, r.x, vector_from<Real>(r, x));
    r.copy(r.context, r.v, vector_from<Real>(r, v));
  }

  // J u (or, definite, D u of clothlab.definite-jacobian/1) on one of the two systems.
  std::vector<double> product(const clothlab_system& system, bool with_velocity,
                              bool definite = false) {
    const auto& jacobian =
        host_extension<clothlab_jacobian_extension>(system, CLOTHLAB_EXT_JACOBIAN);
    EXPECT_EQ(jacobian.reserve(system.context), CLOTHLAB_OK);
    const auto apply = definite ? host_extension<clothlab_definite_jacobian_extension>(
                                      system, CLOTHLAB_EXT_DEFINITE_JACOBIAN)
                                      .apply
                                : jacobian.apply;
    void* out = system.alloc_vector(system.context);
    EXPECT_EQ(apply(system.context, 0.0, system.x, with_velocity ? system.v : nullptr, 0.7, 0.3,
                    vector_from<Real>(system, direction), out),
              CLOTHLAB_OK);
    return values_of<Real>(system, out);
  }

  Cloth cloth;
  reference::ReferenceSystem<Real> reference;
  std::vector<double> x, v, direction;
};

// On a sheet and on strips and tiny grids, where some stencils have no springs at all.
template <class Real>
void expect_same_jacobian(double tolerance, bool definite = false) {
  for (const auto& [rows, cols] : {std::pair{9u, 8u}, {1u, 7u}, {7u, 1u}, {2u, 3u}, {3u, 2u}}) {
    Pair<Real> pair(testing::busy_scene(rows, cols));
    for (const bool with_velocity : {true, false}) {
      const std::vector<double> engine = pair.product(pair.cloth.system(), with_velocity, definite);
      const std::vector<double> oracle =
          pair.product(pair.reference.system(), with_velocity, definite);
      const double scale = max_abs(oracle);
      ASSERT_GT(scale, 1.0) << rows << "x" << cols;
      for (std::size_t e = 0; e < engine.size(); ++e)
        ASSERT_NEAR(engine[e], oracle[e], tolerance * scale)
            << e << " velocity " << with_velocity << ", " << rows << "x" << cols;
    }
  }
}

TEST(ExtensionsVsReference, JacobianProductFloat64) { expect_same_jacobian<double>(1e-12); }
TEST(ExtensionsVsReference, JacobianProductFloat32) { expect_same_jacobian<float>(1e-5); }
TEST(ExtensionsVsReference, DefiniteJacobianProductFloat64) {
  expect_same_jacobian<double>(1e-12, true);
}
TEST(ExtensionsVsReference, DefiniteJacobianProductFloat32) {
  expect_same_jacobian<float>(1e-5, true);
}

TEST(ExtensionsVsReference, DefiniteJacobianDiagonalBlocks) {
  Pair<double> pair(testing::busy_scene(9, 8));
  std::vector<double> blocks[2];
  const clothlab_system* systems[2] = {&pair.cloth.system(), &pair.reference.system()};
  for (int s = 0; s < 2; ++s) {
    const clothlab_system& system = *systems[s];
    blocks[s].resize(9 * std::size_t{system.particle_count});
    ASSERT_EQ(
        host_extension<clothlab_definite_jacobian_extension>(system, CLOTHLAB_EXT_DEFINITE_JACOBIAN)
            .diagonal_blocks(system.context, 0.0, system.x, system.v, 0.4, 0.6, blocks[s].data()),
        CLOTHLAB_OK);
  }
  const double scale = max_abs(blocks[1]);
  ASSERT_GT(scale, 1.0);
  for (std::size_t e = 0; e < blocks[0].size(); ++e)
    ASSERT_NEAR(blocks[0][e], blocks[1][e], 1e-12 * scale) << e;
}

TEST(ExtensionsVsReference, BlockPatternBlocksAndDiagonal) {
  Pair<double> pair(testing::busy_scene(6, 7));
  const clothlab_system* systems[2] = {&pair.cloth.system(), &pair.reference.system()};
  clothlab_block_pattern patterns[2];
  std::vector<double> blocks[2], diagonals[2];
  for (int s = 0; s < 2; ++s) {
    const clothlab_system& system = *systems[s];
    const auto& jacobian =
        host_extension<clothlab_jacobian_extension>(system, CLOTHLAB_EXT_JACOBIAN);
    ASSERT_EQ(jacobian.reserve(system.context), CLOTHLAB_OK);
    patterns[s] = {};
    patterns[s].struct_size = sizeof patterns[s];
    ASSERT_EQ(jacobian.pattern(system.context, &patterns[s]), CLOTHLAB_OK);
    blocks[s].resize(9 * std::size_t{patterns[s].block_count});
    diagonals[s].resize(9 * std::size_t{system.particle_count});
    ASSERT_EQ(jacobian.blocks(system.context, 0.0, system.x, system.v, 0.4, 0.6, blocks[s].data()),
              CLOTHLAB_OK);
    ASSERT_EQ(jacobian.diagonal_blocks(system.context, 0.0, system.x, system.v, 0.4, 0.6,
                                       diagonals[s].data()),
              CLOTHLAB_OK);
  }
  ASSERT_EQ(patterns[0].row_count, patterns[1].row_count);
  ASSERT_EQ(patterns[0].block_count, patterns[1].block_count);
  EXPECT_TRUE(std::equal(patterns[0].row_offsets,
                         patterns[0].row_offsets + patterns[0].row_count + 1,
                         patterns[1].row_offsets));
  EXPECT_TRUE(std::equal(patterns[0].columns, patterns[0].columns + patterns[0].block_count,
                         patterns[1].columns));
  const double scale = max_abs(blocks[1]);
  for (std::size_t e = 0; e < blocks[0].size(); ++e)
    ASSERT_NEAR(blocks[0][e], blocks[1][e], 1e-12 * scale) << e;
  for (std::size_t e = 0; e < diagonals[0].size(); ++e)
    ASSERT_NEAR(diagonals[0][e], diagonals[1][e], 1e-12 * scale) << e;
}

TEST(ExtensionsVsReference, ReductionsAndExternalForces) {
  Pair<double> pair(testing::busy_scene(10, 9));
  std::vector<double> results[2][3], external[2];
  const clothlab_system* systems[2] = {&pair.cloth.system(), &pair.reference.system()};
  for (int s = 0; s < 2; ++s) {
    const clothlab_system& system = *systems[s];
    const auto& reductions =
        host_extension<clothlab_reductions_extension>(system, CLOTHLAB_EXT_REDUCTIONS);
    void* u = vector_from<double>(system, pair.direction);
    results[s][0] = {reductions.dot(system.context, u, system.v)};
    results[s][1] = {reductions.mass_dot(system.context, u, system.x)};
    results[s][2] = {reductions.max_abs(system.context, system.v)};
    const auto& forces =
        host_extension<clothlab_external_forces_extension>(system, CLOTHLAB_EXT_EXTERNAL_FORCES);
    EXPECT_EQ(forces.depends_on_position(system.context), 1);
    void* a = system.alloc_vector(system.context);
    ASSERT_EQ(forces.acceleration(system.context, 0.0, system.x, a), CLOTHLAB_OK);
    external[s] = values_of<double>(system, a);
  }
  for (int r = 0; r < 3; ++r)
    EXPECT_NEAR(results[0][r][0], results[1][r][0], 1e-12 * std::abs(results[1][r][0])) << r;
  const double scale = max_abs(external[1]);
  for (std::size_t e = 0; e < external[0].size(); ++e)
    ASSERT_NEAR(external[0][e], external[1][e], 1e-12 * scale) << e;
}

// The same springs (ends, laws, rest lengths, families) and triangles; the reference's own
// first-fit colourings are independent too (the engine's are checked in topology_test).
TEST(ExtensionsVsReference, Topology) {
  Scene scene = testing::busy_scene(7, 9);
  scene.flexion = {0.0, 0.0};  // left out by both
  Cloth cloth(scene, Precision::Float64, {});
  reference::ReferenceSystem<double> oracle(scene, true);
  const clothlab_topology engine = testing::topology_of(cloth.system());
  const clothlab_topology reference = testing::topology_of(oracle.system());
  using Row = std::tuple<uint32_t, uint32_t, double, double, double, uint8_t>;
  const auto rows = [](const clothlab_topology& t) {
    std::vector<Row> out;
    for (uint32_t s = 0; s < t.spring_count; ++s)
      out.emplace_back(t.first[s], t.second[s], t.rest_length[s], t.ks[s], t.kd[s], t.family[s]);
    std::sort(out.begin(), out.end());
    return out;
  };
  const std::vector<Row> a = rows(engine), b = rows(reference);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(std::get<0>(a[k]), std::get<0>(b[k]));
    EXPECT_EQ(std::get<1>(a[k]), std::get<1>(b[k]));
    EXPECT_NEAR(std::get<2>(a[k]), std::get<2>(b[k]), 1e-12);
    EXPECT_EQ(std::get<3>(a[k]), std::get<3>(b[k]));
    EXPECT_EQ(std::get<4>(a[k]), std::get<4>(b[k]));
    EXPECT_EQ(std::get<5>(a[k]), std::get<5>(b[k]));
  }
  ASSERT_EQ(engine.triangle_count, reference.triangle_count);
  EXPECT_TRUE(std::equal(engine.triangles, engine.triangles + 3 * engine.triangle_count,
                         reference.triangles));
  ASSERT_EQ(reference.adjacency_offsets[reference.particle_count], 2 * reference.spring_count);
  std::vector<uint32_t> color(reference.particle_count);
  for (uint32_t c = 0; c < reference.particle_color_count; ++c)
    for (uint32_t m = reference.particle_color_offsets[c];
         m < reference.particle_color_offsets[c + 1]; ++m)
      color[reference.particle_color_members[m]] = c;
  for (uint32_t s = 0; s < reference.spring_count; ++s)
    EXPECT_NE(color[reference.first[s]], color[reference.second[s]]) << s;
}

// The same grid (rows, cols, spacings); the reference's first-fit colours are no stencils.
TEST(ExtensionsVsReference, Grid) {
  const Scene scene = testing::busy_scene(7, 9);
  Cloth cloth(scene, Precision::Float64, {});
  reference::ReferenceSystem<double> oracle(scene, true);
  const clothlab_grid engine = testing::grid_of(cloth.system());
  const clothlab_grid reference = testing::grid_of(oracle.system());
  EXPECT_EQ(engine.rows, reference.rows);
  EXPECT_EQ(engine.cols, reference.cols);
  EXPECT_EQ(engine.column_spacing, reference.column_spacing);
  EXPECT_EQ(engine.row_spacing, reference.row_spacing);
  EXPECT_NE(engine.spring_colors, nullptr);
  EXPECT_EQ(reference.spring_colors, nullptr);
}

}  // namespace
}  // namespace clothlab
