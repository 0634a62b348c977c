// The jacobian, definite-jacobian and cg-step extensions on the spring list (any mesh; a grid
// with PipelineOptions::force_general_path): against central differences of the spring-list
// forces on an irregular mesh, against the grid's row products on a grid forced onto the general
// path, and the same bits on any thread count.
#include <clothlab/ext/cg_step.h>
#include <clothlab/ext/definite_jacobian.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include "extension_support.hpp"
#include "mesh_test_support.hpp"

namespace clothlab {
namespace {

using testing::host_extension;
using testing::max_abs;
using testing::max_difference;
using testing::values_of;
using testing::vector_from;

PipelineOptions options_with(bool general, int threads = 1) {
  PipelineOptions options;
  options.threads = threads;
  options.adaptive_threads = false;
  options.force_general_path = general;
  return options;
}

std::vector<double> wave(std::size_t size, double frequency, double phase) {
  std::vector<double> out(size);
  for (std::size_t e = 0; e < size; ++e) out[e] = std::sin(frequency * double(e) + phase);
  return out;
}

// The results of every product of the three extensions at the cloth's state, along one u.
struct Products {
  std::vector<double> exact, definite, diagonal, definite_diagonal, blocks, cg_q, cg_solution, cg_p,
      cg_r, cg_z;
  double p_dot_q = 0, r_dot_r = 0, r_dot_z = 0;
};

template <class Real>
Products products_of(Cloth& cloth) {
  const clothlab_system& system = cloth.system();
  const auto& jacobian = host_extension<clothlab_jacobian_extension>(system, CLOTHLAB_EXT_JACOBIAN);
  const auto& definite =
      host_extension<clothlab_definite_jacobian_extension>(system, CLOTHLAB_EXT_DEFINITE_JACOBIAN);
  const auto& cg = host_extension<clothlab_cg_step_extension>(system, CLOTHLAB_EXT_CG_STEP);
  EXPECT_EQ(jacobian.reserve(system.context), CLOTHLAB_OK);
  const std::size_t size = 3 * std::size_t{system.particle_count};
  void* u = vector_from<Real>(system, wave(size, 0.37, 0.1));
  void* out = system.alloc_vector(system.context);
  Products p;
  EXPECT_EQ(jacobian.apply(system.context, 0, system.x, system.v, -0.7, -0.3, u, out), CLOTHLAB_OK);
  p.exact = values_of<Real>(system, out);
  EXPECT_EQ(definite.apply(system.context, 0, system.x, system.v, -0.7, -0.3, u, out), CLOTHLAB_OK);
  p.definite = values_of<Real>(system, out);
  p.diagonal.resize(9 * std::size_t{system.particle_count});
  p.definite_diagonal.resize(p.diagonal.size());
  EXPECT_EQ(jacobian.diagonal_blocks(system.context, 0, system.x, system.v, -0.7, -0.3,
                                     p.diagonal.data()),
            CLOTHLAB_OK);
  EXPECT_EQ(definite.diagonal_blocks(system.context, 0, system.x, system.v, -0.7, -0.3,
                                     p.definite_diagonal.data()),
            CLOTHLAB_OK);
  clothlab_block_pattern pattern{};
  pattern.struct_size = sizeof pattern;
  EXPECT_EQ(jacobian.pattern(system.context, &pattern), CLOTHLAB_OK);
  p.blocks.resize(9 * std::size_t{pattern.block_count});
  EXPECT_EQ(jacobian.blocks(system.context, 0, system.x, system.v, -0.7, -0.3, p.blocks.data()),
            CLOTHLAB_OK);

  void* direction = vector_from<Real>(system, wave(size, 0.23, 0.0));
  void* solution = vector_from<Real>(system, wave(size, 0.41, 0.2));
  void* z_in = vector_from<Real>(system, wave(size, 0.83, 0.4));
  void* r = vector_from<Real>(system, wave(size, 0.57, 0.3));
  void* z = system.alloc_vector(system.context);
  std::vector<double> blocks[2] = {wave(size, 0.7, 0.0), wave(size, 0.3, 1.0)};
  for (double& value : blocks[0]) value = 1.0 + 0.5 * value;
  for (double& value : blocks[1]) value *= 0.2;
  void* diagonal = vector_from<Real>(system, blocks[0]);
  void* off_diagonal = vector_from<Real>(system, blocks[1]);
  EXPECT_EQ(cg.linearise(system.context, 0, system.x, system.v, -0.7, -0.3), CLOTHLAB_OK);
  EXPECT_EQ(cg.product(system.context, 0.29, 0.61, z_in, direction, solution, out, &p.p_dot_q),
            CLOTHLAB_OK);
  EXPECT_EQ(
      cg.update(system.context, 0.37, out, diagonal, off_diagonal, r, z, &p.r_dot_r, &p.r_dot_z),
      CLOTHLAB_OK);
  p.cg_q = values_of<Real>(system, out);
  p.cg_p = values_of<Real>(system, direction);
  p.cg_solution = values_of<Real>(system, solution);
  p.cg_r = values_of<Real>(system, r);
  p.cg_z = values_of<Real>(system, z);
  return p;
}

void expect_products_near(const Products& general, const Products& grid, double tolerance) {
  const auto near = [&](const std::vector<double>& a, const std::vector<double>& b,
                        const char* what) {
    EXPECT_LE(max_difference(a, b), tolerance * std::max(1.0, max_abs(b))) << what;
  };
  near(general.exact, grid.exact, "jacobian apply");
  near(general.definite, grid.definite, "definite apply");
  near(general.diagonal, grid.diagonal, "diagonal blocks");
  near(general.definite_diagonal, grid.definite_diagonal, "definite diagonal blocks");
  near(general.blocks, grid.blocks, "blocks");
  near(general.cg_q, grid.cg_q, "cg-step q");
  near(general.cg_p, grid.cg_p, "cg-step p");
  near(general.cg_solution, grid.cg_solution, "cg-step solution");
  near(general.cg_r, grid.cg_r, "cg-step r");
  near(general.cg_z, grid.cg_z, "cg-step z");
  EXPECT_NEAR(general.p_dot_q, grid.p_dot_q, tolerance * std::abs(grid.p_dot_q));
  EXPECT_NEAR(general.r_dot_r, grid.r_dot_r, tolerance * std::abs(grid.r_dot_r));
  EXPECT_NEAR(general.r_dot_z, grid.r_dot_z, tolerance * std::abs(grid.r_dot_z));
}

void expect_products_equal(const Products& a, const Products& b) {
  for (auto member : {&Products::exact, &Products::definite, &Products::diagonal,
                      &Products::definite_diagonal, &Products::blocks, &Products::cg_q,
                      &Products::cg_p, &Products::cg_solution, &Products::cg_r, &Products::cg_z})
    EXPECT_EQ(a.*member, b.*member);
  EXPECT_EQ(a.p_dot_q, b.p_dot_q);
  EXPECT_EQ(a.r_dot_r, b.r_dot_r);
  EXPECT_EQ(a.r_dot_z, b.r_dot_z);
}

// Grids of several shapes (strips with empty stencils among them), pinned, damped, off rest;
// 40 x 90 spans several of the cg-step sweep's tiles, so each band's ring of slots wraps.
TEST(SpringListJacobian, AgreesWithTheGridRowProducts) {
  for (const auto& [rows, cols] : {std::pair{9u, 8u}, {1u, 7u}, {7u, 2u}, {12u, 40u}, {40u, 90u}}) {
    Scene scene = testing::busy_scene(rows, cols);
    scene.wind_strength = 0.0;
    for (Precision precision : {Precision::Float64, Precision::Float32}) {
      SCOPED_TRACE(::testing::Message() << rows << "x" << cols << " " << to_string(precision));
      Products results[2];
      for (bool general : {false, true}) {
        Cloth cloth(scene, precision, options_with(general));
        std::vector<double> x, v;
        testing::move_off_rest(cloth, 11, 0.05, x, v);
        results[general] = precision == Precision::Float64 ? products_of<double>(cloth)
                                                           : products_of<float>(cloth);
      }
      expect_products_near(results[1], results[0], precision == Precision::Float64 ? 1e-12 : 2e-5);
    }
  }
}

// d a / dx u and d a / dv u on an irregular mesh, whose springs no grid stencil holds.
TEST(SpringListJacobian, MatchesCentralDifferencesOfTheSpringListForcesOnAMesh) {
  Scene scene = testing::busy_scene(9, 11);
  scene.wind_strength = 0.0;
  Cloth cloth(scene, build_mesh_model(testing::irregular_mesh(11, 9), scene), Precision::Float64,
              options_with(true));
  const clothlab_system& system = cloth.system();
  std::vector<double> x, v;
  testing::move_off_rest(cloth, 5, 0.02, x, v);
  std::vector<double> u = wave(x.size(), 0.37, 0.1);
  for (uint32_t pinned : scene.pinned)
    for (std::size_t k = 0; k < 3; ++k) u[3 * pinned + k] = 0;
  const auto acceleration = [&](const std::vector<double>& at_x, const std::vector<double>& at_v) {
    void* a = system.alloc_vector(system.context);
    EXPECT_EQ(system.eval_acceleration(system.context, 0.0, vector_from<double>(system, at_x),
                                       vector_from<double>(system, at_v), a),
              CLOTHLAB_OK);
    return values_of<double>(system, a);
  };
  const auto& jacobian = host_extension<clothlab_jacobian_extension>(system, CLOTHLAB_EXT_JACOBIAN);
  ASSERT_EQ(jacobian.reserve(system.context), CLOTHLAB_OK);
  void* out = system.alloc_vector(system.context);
  for (bool along_x : {true, false}) {
    SCOPED_TRACE(along_x ? "along x" : "along v");
    const double h = 1e-6;
    std::vector<double> plus = along_x ? x : v, minus = plus;
    for (std::size_t e = 0; e < u.size(); ++e) plus[e] += h * u[e], minus[e] -= h * u[e];
    const std::vector<double> a_plus = along_x ? acceleration(plus, v) : acceleration(x, plus);
    const std::vector<double> a_minus = along_x ? acceleration(minus, v) : acceleration(x, minus);
    std::vector<double> difference(u.size());
    for (std::size_t e = 0; e < u.size(); ++e) difference[e] = (a_plus[e] - a_minus[e]) / (2 * h);
    ASSERT_EQ(jacobian.apply(system.context, 0.0, vector_from<double>(system, x),
                             vector_from<double>(system, v), along_x ? 1.0 : 0.0,
                             along_x ? 0.0 : 1.0, vector_from<double>(system, u), out),
              CLOTHLAB_OK);
    const std::vector<double> product = values_of<double>(system, out);
    ASSERT_GT(max_abs(difference), 1.0);
    EXPECT_LT(max_difference(product, difference), 1e-6 * max_abs(difference));
  }
}

// cg-step's q = A p on a mesh numbered along rows (its springs in SpringLanes' bands, read in
// order, those across edges in chosen bands) and on the same mesh numbered otherwise: by a step
// (which keeps bands bands, with other offsets) and at random (gathered): the same q, particle
// for particle. The 60 x 90 mesh spans several of the sweep's tiles, so each band's ring wraps.
TEST(SpringListJacobian, CgProductDoesNotDependOnHowTheParticlesAreNumbered) {
  for (const auto& [rows, cols] : {std::pair{20u, 24u}, std::pair{60u, 90u}}) {
    Scene scene = testing::busy_scene(rows, cols);
    scene.wind_strength = 0.0;
    const uint32_t n = rows * cols;
    const TriangleMesh mesh = testing::irregular_mesh(rows, cols);
    using Numbering = std::pair<const char*, std::vector<uint32_t>>;
    for (const auto& [numbering, to] :
         {Numbering{" by step", testing::step_numbering(n, 97)},  // 97 coprime to n
          Numbering{" shuffled", testing::shuffled_numbering(n, 7)}}) {
      SCOPED_TRACE(std::to_string(rows) + " x " + std::to_string(cols) + numbering);
      Scene renumbered_scene = scene;
      for (uint32_t& pin : renumbered_scene.pinned) pin = to[pin];
      const auto renumber = [&](const std::vector<double>& values) {
        return testing::renumbered_values(values, to);
      };
      for (Precision precision : {Precision::Float64, Precision::Float32}) {
        SCOPED_TRACE(to_string(precision));
        std::vector<double> q[2], x, v;
        for (bool numbered_otherwise : {false, true}) {
          Cloth cloth(numbered_otherwise ? renumbered_scene : scene,
                      numbered_otherwise
                          ? build_mesh_model(testing::renumbered(mesh, to), renumbered_scene)
                          : build_mesh_model(mesh, scene),
                      precision, options_with(true));
          if (numbered_otherwise)
            cloth.set_state(renumber(x), renumber(v));
          else
            testing::move_off_rest(cloth, 5, 0.02, x, v);
          const clothlab_system& system = cloth.system();
          const auto& jacobian =
              host_extension<clothlab_jacobian_extension>(system, CLOTHLAB_EXT_JACOBIAN);
          const auto& cg = host_extension<clothlab_cg_step_extension>(system, CLOTHLAB_EXT_CG_STEP);
          ASSERT_EQ(jacobian.reserve(system.context), CLOTHLAB_OK);
          const std::vector<double> p = wave(3 * std::size_t{n}, 0.37, 0.1);
          const bool real = precision == Precision::Float64;
          void* p_vector = real ? vector_from<double>(system, numbered_otherwise ? renumber(p) : p)
                                : vector_from<float>(system, numbered_otherwise ? renumber(p) : p);
          void* out = system.alloc_vector(system.context);
          double dot = 0;
          ASSERT_EQ(cg.linearise(system.context, 0, system.x, system.v, -0.7, -0.3), CLOTHLAB_OK);
          ASSERT_EQ(cg.product(system.context, 0, 0, nullptr, p_vector, nullptr, out, &dot),
                    CLOTHLAB_OK);
          q[numbered_otherwise] =
              real ? values_of<double>(system, out) : values_of<float>(system, out);
        }
        const std::vector<double> expected = renumber(q[0]);
        const double tolerance = precision == Precision::Float64 ? 1e-12 : 2e-5;
        EXPECT_LE(max_difference(q[1], expected), tolerance * max_abs(expected));
      }
    }
  }
}

TEST(SpringListJacobian, SameBitsOnAnyThreadCount) {
  const Scene scene = testing::busy_scene(72, 70);  // past parallel_from_particles
  const auto mesh = build_mesh_model(testing::irregular_mesh(70, 72), scene);
  for (Precision precision : {Precision::Float32, Precision::Float64}) {
    SCOPED_TRACE(to_string(precision));
    Products results[2];
    for (int threads : {1, 3}) {
      Cloth cloth(scene, mesh, precision, options_with(true, threads));
      ASSERT_EQ(cloth.threads(), threads);
      std::vector<double> x, v;
      testing::move_off_rest(cloth, 3, 0.01, x, v);
      results[threads > 1] =
          precision == Precision::Float64 ? products_of<double>(cloth) : products_of<float>(cloth);
    }
    expect_products_equal(results[0], results[1]);
  }
}

}  // namespace
}  // namespace clothlab
