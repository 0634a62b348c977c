// The material per unit area turned into springs and masses by the core: the grid's families
// (the Provot mapping), the same springs on the grid written as triangles, and a sheet that sags
// as the continuum says at any resolution, on an irregular mesh.
#include <gtest/gtest.h>

#include <clothlab/core/cloth.hpp>
#include <clothlab/core/cloth_material.hpp>
#include <clothlab/core/cloth_model.hpp>
#include <clothlab/core/triangle_mesh.hpp>
#include <cmath>
#include <numbers>
#include <numeric>
#include <utility>
#include <vector>

#include "cloth_test_support.hpp"
#include "mesh_test_support.hpp"

namespace clothlab {
namespace {

ClothMaterial cotton() {  // configs/materials/cotton.yaml
  ClothMaterial material;
  material.areal_density = 0.15;
  material.stretch_stiffness = 6129;
  material.shear_stiffness = 44.95;
  material.bending_stiffness = 7.845e-6;
  material.damping_time = 1.0e-5;
  return material;
}

double total(const std::vector<double>& values) {
  return std::accumulate(values.begin(), values.end(), 0.0);
}

TEST(ClothMaterial, GridFamiliesAreTheMembraneStiffnessAndBendingOverSpacingSquared) {
  ClothMaterial material;
  material.areal_density = 0.2;
  material.stretch_stiffness = 5000;
  material.shear_stiffness = 100;
  material.bending_stiffness = 1e-5;
  material.damping_time = 1e-4;
  Scene coarse = testing::bare_scene(21, 21), fine = testing::bare_scene(81, 81);
  coarse.width = coarse.height = fine.width = fine.height = 1.0;  // h = 0.05 m and 0.0125 m
  apply_material(coarse, material, nullptr);
  apply_material(fine, material, nullptr);
  for (const Scene& scene : {coarse, fine}) {
    EXPECT_DOUBLE_EQ(scene.total_mass, 0.2);
    EXPECT_DOUBLE_EQ(scene.structural.ks, 4900);  // E - G: the axes carry E with the diagonals
    EXPECT_DOUBLE_EQ(scene.shear.ks, 100);
    EXPECT_DOUBLE_EQ(scene.structural.kd, 0.49);
  }
  EXPECT_DOUBLE_EQ(coarse.flexion.ks, 1e-5 / (0.05 * 0.05));
  EXPECT_DOUBLE_EQ(fine.flexion.ks, 16 * coarse.flexion.ks);  // B / h^2
  EXPECT_DOUBLE_EQ(fine.flexion.kd, 1e-4 * fine.flexion.ks);
  Scene wide = testing::bare_scene(21, 21);
  wide.width = 2.0;
  wide.height = 3.0;
  apply_material(wide, material, nullptr);
  EXPECT_DOUBLE_EQ(wide.total_mass, 1.2);  // density x area
}

TEST(ClothMaterial, GridWrittenAsTrianglesGetsTheGridsSpringsAndMass) {
  const ClothMaterial material = cotton();
  for (const testing::Diagonals diagonals :
       {testing::Diagonals::Falling, testing::Diagonals::Rising, testing::Diagonals::Alternating}) {
    Scene grid_scene = testing::busy_scene(7, 9);
    grid_scene.width = 0.8;
    grid_scene.height = 0.6;  // square cells of 0.1 m
    const TriangleMesh mesh = testing::grid_mesh(grid_scene, diagonals);
    Scene mesh_scene = grid_scene;
    apply_material(grid_scene, material, nullptr);
    apply_material(mesh_scene, material, &mesh);
    const auto grid = build_grid_model(grid_scene);
    const auto general = build_mesh_model(mesh, mesh_scene, &material);
    EXPECT_NEAR(mesh_scene.total_mass, grid_scene.total_mass, 1e-12 * grid_scene.total_mass);
    EXPECT_NEAR(total(general->masses), total(grid->masses), 1e-12 * grid_scene.total_mass);
    // The mesh lists its springs by pair; look each grid spring up there.
    ASSERT_EQ(general->spring_count(), grid->spring_count());
    std::vector<std::size_t> by_pair(grid->particle_count * std::size_t{grid->particle_count},
                                     general->spring_count());
    for (std::size_t s = 0; s < general->spring_count(); ++s)
      by_pair[general->first[s] * std::size_t{grid->particle_count} + general->second[s]] = s;
    for (std::size_t s = 0; s < grid->spring_count(); ++s) {
      const std::size_t m =
          by_pair[grid->first[s] * std::size_t{grid->particle_count} + grid->second[s]];
      ASSERT_LT(m, general->spring_count()) << "grid spring " << s << " missing on the mesh";
      EXPECT_EQ(general->family[m], grid->family[s]);
      EXPECT_NEAR(general->rest_length[m], grid->rest_length[s], 1e-12);
      EXPECT_NEAR(general->ks[m], grid->ks[s], 1e-12 * grid->ks[s]) << "spring " << s;
      EXPECT_NEAR(general->kd[m], grid->kd[s], 1e-12 * grid->kd[s]) << "spring " << s;
    }
  }
}

// An irregular sheet (testing::irregular_mesh: jittered, randomly split cells) made flat, its
// outline straight, scaled to `width` x `height`.
TriangleMesh irregular_sheet(uint32_t rows, uint32_t cols, double width, double height) {
  TriangleMesh mesh = testing::irregular_mesh(rows, cols);
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t c = 0; c < cols; ++c) {
      double* p = mesh.positions.data() + 3 * (std::size_t{r} * cols + c);
      if (c == 0 || c + 1 == cols) p[0] = c;
      if (r == 0 || r + 1 == rows) p[1] = -static_cast<double>(r);
      p[0] *= width / (cols - 1);
      p[1] *= height / (rows - 1);
      p[2] = 0;
    }
  return mesh;
}

// How far the bottom edge of a sheet hung by its top edge sinks under its own weight, at rest:
// damped symplectic Euler from rest to equilibrium.
double bottom_sag(const TriangleMesh& mesh, uint32_t rows, uint32_t cols, double height,
                  const ClothMaterial& material) {
  Scene scene;
  scene.rows = scene.cols = 0;
  scene.gravity = {0, -9.81, 0};
  for (uint32_t c = 0; c < cols; ++c) scene.pinned.push_back(c);
  apply_material(scene, material, &mesh);
  PipelineOptions options;
  options.threads = 1;
  options.adaptive_threads = false;
  Cloth cloth(scene, build_mesh_model(mesh, scene, &material), Precision::Float64, options);
  const clothlab_system& system = cloth.system();
  void* acceleration = system.alloc_vector(system.context);
  const auto* a = static_cast<const double*>(acceleration);
  std::vector<double> x, v;
  cloth.positions(x);
  cloth.velocities(v);
  // The step from the fastest stretch wave (a row spacing long); a drag that damps the slowest
  // (a quarter wave along the strip) critically, and ten of its periods over 2 pi to settle.
  const double wave_speed = std::sqrt(material.stretch_stiffness / material.areal_density);
  const double dt = 0.1 * height / (rows - 1) / wave_speed;
  const double slowest = std::numbers::pi / 2 * wave_speed / height, drag = 2 * slowest;
  for (int step = 0; step < static_cast<int>(10 / slowest / dt); ++step) {
    EXPECT_EQ(system.eval_acceleration(system.context, 0.0, system.x, system.v, acceleration),
              CLOTHLAB_OK);
    for (std::size_t i = 0; i < system.particle_count; ++i)
      for (std::size_t k = 0; k < 3; ++k) {
        double& velocity = v[3 * i + k];
        velocity += dt * (a[k * system.stride + i] - drag * velocity);
        x[3 * i + k] += dt * velocity;
      }
    cloth.set_state(x, v);
  }
  double sag = 0;
  for (uint32_t c = 0; c < cols; ++c) {
    const std::size_t i = std::size_t{rows - 1} * cols + c;
    sag += mesh.positions[3 * i + 1] - x[3 * i + 1];
  }
  return sag / cols;
}

TEST(ClothMaterial, IrregularSheetSagsAsTheContinuumAtTwoResolutions) {
  // A 0.25 x 1 m strip hung by its top edge stretches under its weight by rho g H^2 / (2 E')
  // at the bottom, E' the strip's Young's modulus: E for the spring network on triangles
  // (Poisson ratio 1/3; up to 1 / (1 - 1/9) more where the pinned edge stops the strip
  // narrowing). Its side edges carry an inner edge's stiffness over half a cell, as the grid's
  // do: across `cols` vertices the strip is cols / (cols - 1) times stiffer, a bias that
  // vanishes with the spacing.
  ClothMaterial material = cotton();
  material.stretch_stiffness = 60;  // a sag of centimetres, not of rounding
  material.shear_stiffness = 0;
  material.bending_stiffness = 0;
  material.damping_time = 0;
  const double height = 1.0;
  const double continuum =
      material.areal_density * 9.81 * height * height / (2 * material.stretch_stiffness);
  for (const auto& [rows, cols] : {std::pair{13u, 4u}, std::pair{25u, 7u}}) {
    const double sag =
        bottom_sag(irregular_sheet(rows, cols, 0.25, height), rows, cols, height, material);
    const double expected = continuum * (cols - 1.0) / cols;
    EXPECT_NEAR(sag, expected, 0.06 * expected) << rows << " x " << cols;
  }
}

}  // namespace
}  // namespace clothlab
