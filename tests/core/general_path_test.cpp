// The spring-list path (any mesh) against the grid's row pipeline: the switch
// PipelineOptions::force_general_path runs a grid on it, so the two must agree to rounding, in
// forces, energy and stretch, and in whole runs of every explicit built-in; the same bits on any
// thread count; it offers every extension but the grid (integrators that need one refuse).
#include <clothlab/ext/attachment_targets.h>
#include <clothlab/ext/cg_step.h>
#include <clothlab/ext/contacts.h>
#include <clothlab/ext/definite_jacobian.h>
#include <clothlab/ext/external_forces.h>
#include <clothlab/ext/grid.h>
#include <clothlab/ext/jacobian.h>
#include <clothlab/ext/reductions.h>
#include <clothlab/ext/threads.h>
#include <clothlab/ext/topology.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <clothlab/core/cloth.hpp>
#include <clothlab/core/cloth_model.hpp>
#include <clothlab/core/collider.hpp>
#include <clothlab/core/coloring.hpp>
#include <clothlab/core/triangle_mesh.hpp>
#include <clothlab/host/plugin_library.hpp>
#include <cmath>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include "cloth_test_support.hpp"
#include "mesh_test_support.hpp"

namespace clothlab {
namespace {

using testing::max_abs;
using testing::max_difference;

PipelineOptions general_options(int threads = 1) {
  PipelineOptions options;
  options.threads = threads;
  options.adaptive_threads = false;
  options.force_general_path = true;
  return options;
}

PipelineOptions grid_options(int threads = 1) {
  PipelineOptions options = general_options(threads);
  options.force_general_path = false;
  return options;
}

// A state off rest: springs stretched and sheared, everything moving.
void perturb(Cloth& cloth) {
  std::vector<double> x, v;
  cloth.positions(x);
  cloth.velocities(v);
  for (std::size_t c = 0; c < x.size(); ++c) {
    x[c] += 0.01 * std::sin(1.7 * static_cast<double>(c) + 0.3);
    v[c] = 0.2 * std::cos(0.9 * static_cast<double>(c));
  }
  cloth.set_state(x, v);
}

// eval_acceleration at the cloth's state, particle-major.
std::vector<double> accelerations(Cloth& cloth, bool with_velocities = true) {
  const clothlab_system& system = cloth.system();
  void* a = system.alloc_vector(system.context);
  EXPECT_EQ(system.eval_acceleration(system.context, 0.0, system.x,
                                     with_velocities ? system.v : nullptr, a),
            CLOTHLAB_OK);
  std::vector<double> out(3 * std::size_t{system.particle_count});
  for (std::size_t i = 0; i < system.particle_count; ++i)
    for (std::size_t k = 0; k < 3; ++k) {
      const std::size_t at = k * system.stride + i;
      out[3 * i + k] = system.precision == CLOTHLAB_FLOAT64 ? static_cast<const double*>(a)[at]
                                                            : static_cast<const float*>(a)[at];
    }
  return out;
}

Scene airy_scene(uint32_t rows, uint32_t cols) {
  Scene scene = testing::busy_scene(rows, cols);
  scene.air = {{2.0, 0.5, 3.0}, 1.225, 1.2, 0.8};
  return scene;
}

TEST(GeneralPath, ForcesAgreeWithTheGridPipeline) {
  // 6 x 40: rows wide enough for whole blocks of triangles in order (the wind on lanes); 40 x 90:
  // several of the sweep's tiles, so each band's ring of slots wraps (LaneBands::sweep).
  for (const Scene& scene : {testing::busy_scene(9, 11), testing::busy_scene(6, 40),
                             airy_scene(7, 20), airy_scene(30, 6), testing::busy_scene(40, 90)}) {
    for (Precision precision : {Precision::Float64, Precision::Float32}) {
      SCOPED_TRACE(std::to_string(scene.rows) + "x" + std::to_string(scene.cols) + " " +
                   to_string(precision));
      Cloth grid(scene, precision, grid_options());
      Cloth general(scene, precision, general_options());
      perturb(grid);
      perturb(general);
      for (bool damped : {true, false}) {
        const std::vector<double> expected = accelerations(grid, damped);
        const double tolerance =
            (precision == Precision::Float64 ? 1e-12 : 2e-5) * max_abs(expected);
        EXPECT_LE(max_difference(accelerations(general, damped), expected), tolerance);
      }
    }
  }
}

TEST(GeneralPath, ExternalForcesAgreeWithTheGridPipeline) {
  const Scene scene = airy_scene(8, 9);
  Cloth grid(scene, Precision::Float64, grid_options());
  Cloth general(scene, Precision::Float64, general_options());
  perturb(grid);
  perturb(general);
  std::vector<double> results[2];
  for (Cloth* cloth : {&grid, &general}) {
    const clothlab_system& system = cloth->system();
    const auto* external = static_cast<const clothlab_external_forces_extension*>(
        system.get_extension(system.context, CLOTHLAB_EXT_EXTERNAL_FORCES));
    ASSERT_NE(external, nullptr);
    EXPECT_EQ(external->depends_on_position(system.context), 1);
    auto* a = static_cast<double*>(system.alloc_vector(system.context));
    ASSERT_EQ(external->acceleration(system.context, 0.0, system.x, a), CLOTHLAB_OK);
    results[cloth == &general].assign(a, a + 3 * system.stride);
  }
  EXPECT_LE(max_difference(results[0], results[1]), 1e-12 * max_abs(results[0]));
}

TEST(GeneralPath, MeshOfTheGridWithItsMassesMovesLikeTheGrid) {
  // The grid's own triangles (cells split as grid_triangles does) and its equal masses: the
  // mesh builder's model then exerts the grid's forces.
  const Scene scene = airy_scene(10, 12);
  TriangleMesh mesh = testing::grid_mesh(scene, testing::Diagonals::Rising);
  mesh.masses.assign(scene.rows * scene.cols, scene.total_mass / (scene.rows * scene.cols));
  Cloth grid(scene, Precision::Float64, grid_options());
  Cloth general(scene, build_mesh_model(mesh, scene), Precision::Float64, general_options());
  perturb(grid);
  perturb(general);
  const std::vector<double> expected = accelerations(grid);
  EXPECT_LE(max_difference(accelerations(general), expected), 1e-12 * max_abs(expected));
}

TEST(GeneralPath, EnergyAndStretchAgreeWithTheGridPath) {
  Scene scene = testing::busy_scene(12, 9);
  Cloth grid(scene, Precision::Float64, grid_options());
  Cloth general(scene, Precision::Float64, general_options());
  perturb(grid);
  perturb(general);
  const Cloth::Energy e_grid = grid.energy(), e_general = general.energy();
  EXPECT_NEAR(e_general.kinetic, e_grid.kinetic, 1e-12 * e_grid.kinetic);
  EXPECT_NEAR(e_general.spring, e_grid.spring, 1e-12 * e_grid.spring);
  EXPECT_NEAR(e_general.gravity, e_grid.gravity, 1e-12 * std::abs(e_grid.gravity));
  for (Cloth::Springs which : {Cloth::Springs::All, Cloth::Springs::Structural}) {
    const Cloth::Stretch s_grid = grid.stretch(which), s_general = general.stretch(which);
    EXPECT_DOUBLE_EQ(s_general.max, s_grid.max);
    EXPECT_NEAR(s_general.mean, s_grid.mean, 1e-12);
    EXPECT_DOUBLE_EQ(s_general.max_away_from_pins, s_grid.max_away_from_pins);
    EXPECT_DOUBLE_EQ(general.stretch_percentile(which, 0.9), grid.stretch_percentile(which, 0.9));
    const Cloth::LongestSpring l_grid = grid.longest_spring(which);
    const Cloth::LongestSpring l_general = general.longest_spring(which);
    EXPECT_DOUBLE_EQ(l_general.ratio, l_grid.ratio);
    EXPECT_EQ(l_general.first, l_grid.first);
    EXPECT_EQ(l_general.second, l_grid.second);
  }
}

// Runge-Kutta-Nystrom steps of the classic RK4 on `cloth` (steps of 10 us: stable on the stiff
// test scenes); its positions after.
std::vector<double> rk4_steps(Cloth& cloth, int steps) {
  const clothlab_rkn_scheme& scheme = testing::rk4_scheme();
  const clothlab_system& system = cloth.system();
  EXPECT_EQ(system.reserve_rkn(system.context, 4), CLOTHLAB_OK);
  for (int s = 0; s < steps; ++s)
    EXPECT_EQ(system.step_rkn(system.context, s * 1e-5, 1e-5, &scheme), CLOTHLAB_OK);
  std::vector<double> x;
  cloth.positions(x);
  return x;
}

TEST(GeneralPath, SameBitsOnAnyThreadCount) {
  // Past parallel_from_particles: the team runs. With the air, the triangles go one at a time;
  // with the wind alone, on lanes.
  for (const Scene& scene : {airy_scene(72, 70), testing::busy_scene(72, 70)}) {
    const auto mesh = build_mesh_model(testing::irregular_mesh(70, 72), scene);
    for (Precision precision : {Precision::Float32, Precision::Float64}) {
      Cloth one(scene, precision, general_options(1)), two(scene, precision, general_options(2));
      Cloth mesh_one(scene, mesh, precision, general_options(1));
      Cloth mesh_three(scene, mesh, precision, general_options(3));
      ASSERT_EQ(two.threads(), 2);
      ASSERT_EQ(mesh_three.threads(), 3);
      EXPECT_EQ(rk4_steps(one, 5), rk4_steps(two, 5));
      EXPECT_EQ(rk4_steps(mesh_one, 5), rk4_steps(mesh_three, 5));
    }
  }
}

// A pinned particle (inverse mass 0) stays where it is under rk4 on the general path, even when
// its state carries a velocity (the update's active mask, not a zero velocity, holds it).
TEST(GeneralPath, PinnedParticlesStayPutUnderRk4WithAVelocity) {
  const Scene scene = testing::busy_scene(20, 21);
  ASSERT_FALSE(scene.pinned.empty());
  for (Precision precision : {Precision::Float32, Precision::Float64}) {
    Cloth cloth(scene, precision, general_options(1));
    perturb(cloth);
    std::vector<double> before, velocities;
    cloth.positions(before);
    cloth.velocities(velocities);
    const std::vector<double> after = rk4_steps(cloth, 3);
    for (uint32_t pin : scene.pinned)
      for (std::size_t k = 0; k < 3; ++k) {
        ASSERT_NE(velocities[3 * pin + k], 0.0);
        EXPECT_EQ(after[3 * pin + k], before[3 * pin + k]) << "pin " << pin << " axis " << k;
      }
  }
}

// Numbered along rows, nearly every spring and triangle of a mesh lies in a band of LaneBands
// (read in order: the wind alone runs on lanes, dead slots masked; the springs across edges in
// chosen bands); numbered at random, nearly none does (gathered). Both give each particle its
// forces. The 40 x 90 mesh spans several of the sweep's tiles, so each band's ring wraps.
TEST(GeneralPath, ForcesDoNotDependOnHowTheParticlesAreNumbered) {
  for (const auto& [rows, cols] : {std::pair{20u, 40u}, std::pair{40u, 90u}})
    for (const Scene& scene : {airy_scene(rows, cols), testing::busy_scene(rows, cols)}) {
      const TriangleMesh mesh = testing::irregular_mesh(rows, cols);
      const uint32_t n = rows * cols;
      const auto in_rows = build_mesh_model(mesh, scene);
      // By a step coprime to n (bands stay bands), and at random (nothing in order).
      using Numbering = std::pair<const char*, std::vector<uint32_t>>;
      for (const auto& [numbering, to] :
           {Numbering{" by step", testing::step_numbering(n, 97)},
            Numbering{" shuffled", testing::shuffled_numbering(n, 7)}}) {
        Scene renumbered_scene = scene;
        for (uint32_t& pin : renumbered_scene.pinned) pin = to[pin];
        const auto renumbered_model =
            build_mesh_model(testing::renumbered(mesh, to), renumbered_scene);
        for (Precision precision : {Precision::Float64, Precision::Float32}) {
          SCOPED_TRACE(std::string(to_string(precision)) + (scene.has_air() ? " air " : " wind ") +
                       std::to_string(rows) + " x " + std::to_string(cols) + numbering);
          Cloth rows_cloth(scene, in_rows, precision, general_options());
          Cloth renumbered_cloth(renumbered_scene, renumbered_model, precision, general_options());
          perturb(rows_cloth);
          std::vector<double> x, v;
          rows_cloth.positions(x);
          rows_cloth.velocities(v);
          renumbered_cloth.set_state(testing::renumbered_values(x, to),
                                     testing::renumbered_values(v, to));
          const std::vector<double> expected = accelerations(rows_cloth);
          const std::vector<double> renumbered_a = accelerations(renumbered_cloth);
          std::vector<double> got(3 * n);
          for (uint32_t i = 0; i < n; ++i)
            for (std::size_t k = 0; k < 3; ++k) got[3 * i + k] = renumbered_a[3 * to[i] + k];
          const double tolerance =
              (precision == Precision::Float64 ? 1e-12 : 2e-5) * max_abs(expected);
          EXPECT_LE(max_difference(got, expected), tolerance);
        }
      }
    }
}

// The float32 lanes' accelerations on the model against the float64 path's (which reads each
// slot's own ends and law, one slot at a time) at the same float32 state, damped and undamped.
void expect_lanes_agree_with_float64(const Scene& scene,
                                     const std::shared_ptr<const ClothModel>& model) {
  Cloth lanes(scene, model, Precision::Float32, general_options());
  Cloth reference(scene, model, Precision::Float64, general_options());
  perturb(lanes);
  std::vector<double> x, v;
  lanes.positions(x);
  lanes.velocities(v);
  reference.set_state(x, v);  // the float32 state, exactly
  for (bool damped : {true, false}) {
    const std::vector<double> expected = accelerations(reference, damped);
    EXPECT_LE(max_difference(accelerations(lanes, damped), expected), 2e-5 * max_abs(expected));
  }
}

// The float32 lanes read a block's law as its kind says (one law, one ks and kd, two ks and kd
// picked per lane, or a law per lane); the float64 path reads each slot's own. On an irregular
// mesh, where a band of diagonals mixes shear and flexion springs, the two agree.
TEST(GeneralPath, LanesReadEachSpringsLawOnAnIrregularMesh) {
  const Scene scene = testing::busy_scene(20, 40);
  const auto model = build_mesh_model(testing::irregular_mesh(20, 40), scene);
  expect_lanes_agree_with_float64(scene, model);
}

// A run of blocks reads its first block's law while the blocks' laws stay the same
// (SpringLanes' kRunParity): on the grid read as a mesh, whose bands' blocks each take one law,
// the springs from stripes of 32 particles take other laws, so a band's blocks change law along
// it; the float32 lanes agree with the float64 path, which reads each slot's own.
TEST(GeneralPath, LanesReadEachBlocksLawWhereItChangesAlongABand) {
  const Scene scene = testing::busy_scene(20, 40);
  auto model = std::make_shared<ClothModel>(
      *build_mesh_model(testing::grid_mesh(scene, testing::Diagonals::Rising), scene));
  for (std::size_t k = 0; k < model->spring_count(); ++k)
    if (model->first[k] / 32 % 2 == 1)
      model->ks[k] *= 1.5, model->kd[k] *= 0.5, model->rest_length[k] *= 0.9;
  expect_lanes_agree_with_float64(scene, model);
}

// A run of blocks reads its first block's ends in order, the others following (kRunParity):
// where the grid read as a mesh keeps its springs along rows only from windows of 16 first ends
// 128 apart, they are too few for a band and are gathered, in blocks whose ends are in order but
// do not follow each other's; the float32 lanes agree with the float64 path.
TEST(GeneralPath, LanesReadEachBlocksEndsWhereTheyDoNotFollow) {
  const Scene scene = testing::busy_scene(20, 40);
  auto model = std::make_shared<ClothModel>(
      *build_mesh_model(testing::grid_mesh(scene, testing::Diagonals::Rising), scene));
  ClothModel& sparse = *model;
  std::size_t kept = 0;
  for (std::size_t k = 0; k < sparse.spring_count(); ++k) {
    if (sparse.second[k] - sparse.first[k] == 1 && sparse.first[k] % 128 >= 16) continue;
    sparse.first[kept] = sparse.first[k], sparse.second[kept] = sparse.second[k];
    sparse.rest_length[kept] = sparse.rest_length[k], sparse.ks[kept] = sparse.ks[k];
    sparse.kd[kept] = sparse.kd[k], sparse.family[kept] = sparse.family[k];
    ++kept;
  }
  for (auto* values : {&sparse.first, &sparse.second}) values->resize(kept);
  for (auto* values : {&sparse.rest_length, &sparse.ks, &sparse.kd}) values->resize(kept);
  sparse.family.resize(kept);
  detail::build_adjacency(sparse);
  expect_lanes_agree_with_float64(scene, model);
}

TEST(GeneralPath, OffersEveryExtensionButTheGrid) {
  const Scene scene = testing::busy_scene(6, 5);
  Cloth grid(scene, Precision::Float64, grid_options());
  Cloth general(scene, Precision::Float64, general_options());
  EXPECT_NE(grid.system().get_extension(grid.system().context, CLOTHLAB_EXT_GRID), nullptr);
  EXPECT_EQ(general.system().get_extension(general.system().context, CLOTHLAB_EXT_GRID), nullptr);
  for (const char* id :
       {CLOTHLAB_EXT_JACOBIAN, CLOTHLAB_EXT_DEFINITE_JACOBIAN, CLOTHLAB_EXT_CG_STEP,
        CLOTHLAB_EXT_REDUCTIONS, CLOTHLAB_EXT_EXTERNAL_FORCES, CLOTHLAB_EXT_CONTACTS,
        CLOTHLAB_EXT_ATTACHMENT_TARGETS, CLOTHLAB_EXT_THREADS}) {
    EXPECT_NE(grid.system().get_extension(grid.system().context, id), nullptr) << id;
    EXPECT_NE(general.system().get_extension(general.system().context, id), nullptr) << id;
  }
  const auto* topology = static_cast<const clothlab_topology_extension*>(
      general.system().get_extension(general.system().context, CLOTHLAB_EXT_TOPOLOGY));
  ASSERT_NE(topology, nullptr);
  clothlab_topology t{};
  t.struct_size = sizeof t;
  ASSERT_EQ(topology->get(general.system().context, &t), CLOTHLAB_OK);
  EXPECT_EQ(t.spring_count, general.model()->spring_count());
  EXPECT_EQ(t.spring_color_count, 12u);
  EXPECT_EQ(t.first, general.model()->first.data());
}

// ----------------------------------------------------------------------- the built-ins

std::string plugin_path(const std::string& id) {
  if (id == "euler") return CLOTHLAB_TEST_EULER_PLUGIN;
  if (id == "midpoint") return CLOTHLAB_TEST_MIDPOINT_PLUGIN;
  if (id == "rk4") return CLOTHLAB_TEST_RK4_PLUGIN;
  if (id == "verlet") return CLOTHLAB_TEST_VERLET_PLUGIN;
  if (id == "implicit_euler") return CLOTHLAB_TEST_IMPLICIT_EULER_PLUGIN;
  if (id == "projective_dynamics") return CLOTHLAB_TEST_PROJECTIVE_DYNAMICS_PLUGIN;
  if (id == "xpbd") return CLOTHLAB_TEST_XPBD_PLUGIN;
  if (id == "xpbd_tethers") return CLOTHLAB_TEST_XPBD_TETHERS_PLUGIN;
  return CLOTHLAB_TEST_VBD_PLUGIN;
}

// How a run holds the scene's grid: as the grid (its fast path), as the grid forced onto the
// spring list, or as the grid written as triangles (the mesh builder's model, equal masses).
enum class Path { Grid, ForcedGeneral, Mesh };

// The grid written as triangles, with the grid's equal masses and, where `grid_colours`, the
// grid model's colourings carried over to the mesh model's spring numbering (the mesh builder's
// own colouring has the grid's spring colours in another order, so it orders a Gauss-Seidel
// sweep differently).
std::shared_ptr<const ClothModel> grid_as_mesh(const Scene& scene, bool grid_colours) {
  TriangleMesh mesh = testing::grid_mesh(scene, testing::Diagonals::Rising);
  mesh.masses.assign(scene.rows * scene.cols, scene.total_mass / (scene.rows * scene.cols));
  auto model = std::make_shared<ClothModel>(*build_mesh_model(mesh, scene));
  if (!grid_colours) return model;
  const std::shared_ptr<const ClothModel> grid = build_grid_model(scene);
  std::vector<uint32_t> color_of(model->spring_count());
  for (uint32_t c = 0; c < grid->spring_colors.count(); ++c)
    for (uint32_t s : grid->spring_colors.color(c)) {
      const uint32_t i = grid->first[s], j = grid->second[s];
      for (uint32_t e = model->adjacency_offsets[i]; e < model->adjacency_offsets[i + 1]; ++e) {
        const uint32_t m = model->adjacent_springs[e];
        if (model->first[m] == i && model->second[m] == j) color_of[m] = c;
      }
    }
  model->spring_colors = group_by_color(color_of, grid->spring_colors.count());
  model->particle_colors = grid->particle_colors;
  return model;
}

// The positions after `seconds` of `id` at its defaults on `scene`, particle-major.
// The two pinned corners of the sheet's first row carried round a circle (the host's
// attachments, clothlab.attachment-targets/1).
class CirclingCorners final : public AttachmentSource {
 public:
  explicit CirclingCorners(const Scene& scene) {
    for (uint32_t pin : scene.pinned)
      for (int k = 0; k < 3; ++k)
        start_.push_back(scene.origin[k] +
                         (pin % scene.cols) * scene.column_spacing() * scene.col_axis[k]);
  }
  bool targets(double t, std::span<double> positions,
               std::span<double> velocities) noexcept override {
    const double turn = 2 * std::numbers::pi * t, radius = 0.05;
    for (std::size_t at = 0; at < start_.size(); at += 3) {
      const double offset[3] = {radius * std::sin(turn), 0, radius * (1 - std::cos(turn))};
      const double rate[3] = {radius * 2 * std::numbers::pi * std::cos(turn), 0,
                              radius * 2 * std::numbers::pi * std::sin(turn)};
      for (std::size_t k = 0; k < 3; ++k) {
        positions[at + k] = start_[at + k] + offset[k];
        velocities[at + k] = rate[k];
      }
    }
    return true;
  }

 private:
  std::vector<double> start_;  // 3 per pin
};

// What a run meets besides its forces: a collider (for integrators that resolve contacts) and
// the pins moved as attachments.
struct Surroundings {
  bool sphere = false;
  bool attachments = false;
};

// `substeps`: xpbd's inner substeps, 0 for its default. With surroundings: also the contact work it
// reports.
std::vector<double> run(const std::string& id, const Scene& scene, Path path, double seconds,
                        double dt, bool grid_colours = true, int substeps = 0,
                        Surroundings surroundings = {}, double* contact_work = nullptr) {
  const host::PluginLibrary library = host::PluginLibrary::load(plugin_path(id));
  const clothlab_integrator& integrator = library.integrator().descriptor();
  std::vector<clothlab_param_value> values(integrator.param_count);
  for (uint32_t p = 0; p < integrator.param_count; ++p) {
    for (int k = 0; k < 3; ++k) values[p].v[k] = integrator.params[p].default_value[k];
    if (substeps > 0 && std::string(integrator.params[p].name) == "inner_substeps")
      values[p].v[0] = substeps;
  }
  PipelineOptions options = path == Path::Grid ? grid_options() : general_options();
  options.velocity_forces = (integrator.flags & CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES) != 0;
  Cloth cloth = path == Path::Mesh
                    ? Cloth(scene, grid_as_mesh(scene, grid_colours), Precision::Float64, options)
                    : Cloth(scene, Precision::Float64, options);
  CirclingCorners corners(scene);
  if (surroundings.attachments) {
    cloth.set_attachments(scene.pinned, corners);
    EXPECT_TRUE(cloth.move_attachments(0.0));
  }
  Collider sphere;
  sphere.radius = 0.15;
  sphere.friction = 0.3;
  sphere.thickness = 0.005;
  sphere.pose.position = {0.0, 0.8, 0.5};
  if (surroundings.sphere) cloth.set_colliders({&sphere, 1}, 0.0);
  clothlab_message message{};
  void* instance = nullptr;
  EXPECT_EQ(integrator.create(values.data(), integrator.param_count, &instance, &message),
            CLOTHLAB_OK)
      << message.text;
  EXPECT_EQ(integrator.prepare(instance, &cloth.system(), &message), CLOTHLAB_OK) << message.text;
  const int steps = static_cast<int>(std::lround(seconds / dt));
  for (int s = 0; s < steps; ++s)
    EXPECT_EQ(integrator.step(instance, &cloth.system(), s * dt, dt, &message), CLOTHLAB_OK)
        << message.text;
  integrator.destroy(instance);
  if (contact_work != nullptr) *contact_work = cloth.contact_work();
  std::vector<double> x;
  cloth.positions(x);
  return x;
}

// The built-in sheet and flag (plugins/scenarios) at a test's size.
Scene sheet_scene() {
  Scene scene = testing::bare_scene(12, 12);
  scene.width = scene.height = 1.0;
  scene.origin = {-0.5, 1.0, 0.0};
  scene.total_mass = 0.3;
  scene.structural = {20.0, 0.014};
  scene.shear = {10.0, 0.007};
  scene.flexion = {1.0, 0.0007};
  scene.gravity = {0, -9.81, 0};
  scene.pinned = {0, 11};
  return scene;
}

Scene flag_scene() {
  Scene scene = sheet_scene();
  scene.origin = {0.0, 1.0, 0.0};
  scene.pinned.clear();
  for (uint32_t r = 0; r < scene.rows; ++r) scene.pinned.push_back(r * scene.cols);
  const double length = std::hypot(1.0, 0.5);
  scene.wind_direction = {1.0 / length, 0.0, 0.5 / length};
  scene.wind_strength = 5.0;
  return scene;
}

class BuiltIn : public ::testing::TestWithParam<const char*> {};

// xpbd projects the springs colour by colour (Gauss-Seidel): another colouring is another
// order of projections, which moves the result by a splitting error of the substep (tested
// below), so the grid written as triangles takes the grid's colours for it. The other built-ins
// keep the mesh's own colouring: vbd's vertex steps and the global solves do not depend
// on it beyond rounding.
bool order_depends_on_colours(const std::string& id) { return id.starts_with("xpbd"); }

// Float64, 1 ms steps: the sheet after 1 s and the windy flag (whose motion amplifies rounding)
// after 0.1 s agree within 1e-6 of the cloth's size on the three paths.
TEST_P(BuiltIn, GeneralPathAndGridWrittenAsTrianglesMoveLikeTheGrid) {
  const double size = 1.0;  // the cloth's width and height
  const double dt = 1e-3;
  const bool grid_colours = order_depends_on_colours(GetParam());
  for (const auto& [name, scene, seconds] :
       {std::tuple{"sheet", sheet_scene(), 1.0}, {"flag", flag_scene(), 0.1}}) {
    const std::vector<double> grid = run(GetParam(), scene, Path::Grid, seconds, dt);
    EXPECT_LE(max_difference(run(GetParam(), scene, Path::ForcedGeneral, seconds, dt), grid),
              1e-6 * size)
        << name << ": the grid forced onto the general path";
    EXPECT_LE(max_difference(run(GetParam(), scene, Path::Mesh, seconds, dt, grid_colours), grid),
              1e-6 * size)
        << name << ": the grid written as triangles";
  }
}

// With the mesh's own colouring xpbd's projections run in another order: a first-order
// splitting error, so the distance to the grid's run halves when the substeps double (both
// converge to the same motion).
TEST(GeneralPath, XpbdOnTheMeshsOwnColouringConvergesToTheGridsMotion) {
  const Scene sheet = sheet_scene();
  double previous = 0;
  for (int substeps : {10, 20, 40}) {
    const double distance =
        max_difference(run("xpbd", sheet, Path::Mesh, 0.25, 1e-3, false, substeps),
                       run("xpbd", sheet, Path::Grid, 0.25, 1e-3, true, substeps));
    EXPECT_GT(distance, 1e-8) << substeps << " substeps: the colourings order alike";
    if (previous > 0) {
      EXPECT_GT(distance, 0.4 * previous) << substeps << " substeps";
      EXPECT_LT(distance, 0.6 * previous) << substeps << " substeps";
    }
    previous = distance;
  }
}

// The sheet laid flat (its first row pinned at the corners), falling onto a sphere while its
// corners circle: contacts and attachments on the three paths, for every built-in that resolves
// contacts (attachments alone for the others).
TEST_P(BuiltIn, CollidersAndAttachmentsActAlikeOnEveryPath) {
  Scene scene = sheet_scene();
  scene.row_axis = {0, 0, 1};
  const std::string id = GetParam();
  const bool resolves_contacts = id != "verlet" && id != "vbd";
  const Surroundings surroundings{resolves_contacts, true};
  const double seconds = 0.3, dt = 1e-3;
  double work[3] = {0, 0, 0};
  const std::vector<double> grid =
      run(id, scene, Path::Grid, seconds, dt, true, 0, surroundings, &work[0]);
  const std::vector<double> general =
      run(id, scene, Path::ForcedGeneral, seconds, dt, true, 0, surroundings, &work[1]);
  const std::vector<double> mesh = run(id, scene, Path::Mesh, seconds, dt,
                                       order_depends_on_colours(id), 0, surroundings, &work[2]);
  EXPECT_LE(max_difference(general, grid), 1e-6) << "the grid forced onto the general path";
  EXPECT_LE(max_difference(mesh, grid), 1e-6) << "the grid written as triangles";
  if (resolves_contacts) {
    // Signed: stopping the sheet takes energy away, pushing it out of the sphere adds some.
    EXPECT_NE(work[0], 0.0) << "the sheet did not reach the sphere";
    EXPECT_NEAR(work[1], work[0], 1e-6 * std::abs(work[0]));
    EXPECT_NEAR(work[2], work[0], 1e-6 * std::abs(work[0]));
  }
  for (uint32_t pin : scene.pinned)  // the corners where the targets put them at the end
    for (const std::vector<double>* x : {&grid, &general, &mesh})
      EXPECT_NEAR((*x)[3 * pin + 2], 0.05 * (1 - std::cos(2 * std::numbers::pi * seconds)), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Integrators, BuiltIn,
                         ::testing::Values("euler", "midpoint", "rk4", "verlet", "implicit_euler",
                                           "projective_dynamics", "xpbd", "xpbd_tethers", "vbd"),
                         [](const auto& info) { return std::string(info.param); });

}  // namespace
}  // namespace clothlab
