// clothlab.cg-step/1: the engine's fused CG sweeps against the reference system's (the same
// calls composed of definite-jacobian apply, axpy and mass_dot), the same bits on any thread
// count, and implicit_euler's CG (preconditioned_cg.hpp) fused and through separate calls.
#include <clothlab/ext/cg_step.h>
#include <clothlab/ext/reductions.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <optional>
#include <vector>

#include "extension_support.hpp"
#include "preconditioned_cg.hpp"
#include "reference_system.hpp"

namespace clothlab {
namespace {

using testing::host_extension;
using testing::max_abs;
using testing::values_of;
using testing::vector_from;

std::vector<double> wave(std::size_t size, double frequency) {
  std::vector<double> out(size);
  for (std::size_t e = 0; e < size; ++e) out[e] = std::cos(frequency * double(e));
  return out;
}

// A preconditioner's symmetric blocks (positive on the diagonal), as two vectors' values.
std::array<std::vector<double>, 2> some_blocks(std::size_t particles) {
  std::array<std::vector<double>, 2> blocks{std::vector<double>(3 * particles),
                                            std::vector<double>(3 * particles)};
  for (std::size_t e = 0; e < 3 * particles; ++e) {
    blocks[0][e] = 1.0 + 0.5 * std::sin(0.7 * double(e));
    blocks[1][e] = 0.2 * std::cos(0.3 * double(e));
  }
  return blocks;
}

struct Sweeps {
  std::vector<double> q, solution, r, z, p;
  double p_dot_q = 0, r_dot_r = 0, r_dot_z = 0;
};

// product (with a direction) and update on `system` at its state, from the same inputs on every
// system.
template <class Real>
Sweeps run_sweeps(const clothlab_system& system, bool with_velocity) {
  const auto& jacobian = host_extension<clothlab_jacobian_extension>(system, CLOTHLAB_EXT_JACOBIAN);
  EXPECT_EQ(jacobian.reserve(system.context), CLOTHLAB_OK);
  const auto& cg = host_extension<clothlab_cg_step_extension>(system, CLOTHLAB_EXT_CG_STEP);
  const std::size_t size = 3 * std::size_t{system.particle_count};
  void* p = vector_from<Real>(system, wave(size, 0.23));
  void* q = system.alloc_vector(system.context);
  void* solution = vector_from<Real>(system, wave(size, 0.41));
  void* r = vector_from<Real>(system, wave(size, 0.57));
  void* z = system.alloc_vector(system.context);
  void* z_in = vector_from<Real>(system, wave(size, 0.83));
  const auto blocks = some_blocks(system.particle_count);
  void* diagonal = vector_from<Real>(system, blocks[0]);
  void* off_diagonal = vector_from<Real>(system, blocks[1]);
  Sweeps out;
  EXPECT_EQ(
      cg.linearise(system.context, 0.0, system.x, with_velocity ? system.v : nullptr, -0.7, -0.3),
      CLOTHLAB_OK);
  EXPECT_EQ(cg.product(system.context, 0.29, 0.61, z_in, p, solution, q, &out.p_dot_q),
            CLOTHLAB_OK);
  EXPECT_EQ(
      cg.update(system.context, 0.37, q, diagonal, off_diagonal, r, z, &out.r_dot_r, &out.r_dot_z),
      CLOTHLAB_OK);
  out.p = values_of<Real>(system, p);
  out.q = values_of<Real>(system, q);
  out.solution = values_of<Real>(system, solution);
  out.r = values_of<Real>(system, r);
  out.z = values_of<Real>(system, z);
  return out;
}

void expect_near(const std::vector<double>& engine, const std::vector<double>& oracle,
                 double tolerance, const char* what) {
  ASSERT_EQ(engine.size(), oracle.size());
  const double scale = std::max(1.0, max_abs(oracle));
  for (std::size_t e = 0; e < engine.size(); ++e)
    ASSERT_NEAR(engine[e], oracle[e], tolerance * scale) << what << " " << e;
}

// Tiny grids and strips (some stencils empty: the per-stencil path) and grids wide enough for
// the row kernel's interior blocks (float32 with SIMD lanes, float_lanes.hpp).
template <class Real>
void expect_sweeps_match_reference(double tolerance) {
  for (const auto& [rows, cols] :
       {std::pair{9u, 8u}, {1u, 7u}, {7u, 1u}, {2u, 3u}, {3u, 2u}, {9u, 40u}, {12u, 53u}}) {
    const Scene scene = testing::busy_scene(rows, cols);
    Cloth cloth(scene, sizeof(Real) == 4 ? Precision::Float32 : Precision::Float64, {});
    reference::ReferenceSystem<Real> reference(scene, true);
    std::vector<double> x, v;
    testing::move_off_rest(cloth, 11, 0.05, x, v);
    const clothlab_system& r = reference.system();
    r.copy(r.context, r.x, vector_from<Real>(r, x));
    r.copy(r.context, r.v, vector_from<Real>(r, v));
    for (const bool with_velocity : {true, false}) {
      const Sweeps engine = run_sweeps<Real>(cloth.system(), with_velocity);
      const Sweeps oracle = run_sweeps<Real>(r, with_velocity);
      SCOPED_TRACE(::testing::Message() << rows << "x" << cols << " velocity " << with_velocity);
      ASSERT_GT(max_abs(oracle.q), 1.0);
      expect_near(engine.q, oracle.q, tolerance, "q");
      expect_near(engine.solution, oracle.solution, tolerance, "solution");
      expect_near(engine.r, oracle.r, tolerance, "r");
      expect_near(engine.z, oracle.z, tolerance, "z");
      expect_near(engine.p, oracle.p, tolerance, "p");
      for (const auto& [fused, composed] : {std::pair{engine.p_dot_q, oracle.p_dot_q},
                                            {engine.r_dot_r, oracle.r_dot_r},
                                            {engine.r_dot_z, oracle.r_dot_z}})
        EXPECT_NEAR(fused, composed, tolerance * std::abs(composed) + 1e-12);
    }
  }
}

TEST(CgStep, SweepsMatchTheReferenceFloat64) { expect_sweeps_match_reference<double>(1e-12); }
TEST(CgStep, SweepsMatchTheReferenceFloat32) { expect_sweeps_match_reference<float>(2e-5); }

TEST(CgStep, PinnedEntriesOfQAndZAreZero) {
  const Scene scene = testing::busy_scene(9, 40);
  Cloth cloth(scene, Precision::Float32, {});
  std::vector<double> x, v;
  testing::move_off_rest(cloth, 3, 0.05, x, v);
  const Sweeps sweeps = run_sweeps<float>(cloth.system(), true);
  for (const uint32_t pinned : scene.pinned)
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(sweeps.q[3 * pinned + k], 0.0);
      EXPECT_EQ(sweeps.z[3 * pinned + k], 0.0);
    }
}

template <class Real>
void expect_same_bits_on_any_thread_count() {
  Sweeps first;
  for (int threads : {1, 2, 3}) {
    PipelineOptions options;
    options.threads = threads;
    const Scene scene = testing::busy_scene(80, 70);  // large enough to run threaded
    Cloth cloth(scene, sizeof(Real) == 4 ? Precision::Float32 : Precision::Float64, options);
    std::vector<double> x, v;
    testing::move_off_rest(cloth, 5, 0.05, x, v);
    const Sweeps sweeps = run_sweeps<Real>(cloth.system(), true);
    if (threads == 1) {
      first = sweeps;
      continue;
    }
    EXPECT_EQ(sweeps.q, first.q) << threads << " threads";
    EXPECT_EQ(sweeps.z, first.z) << threads << " threads";
    EXPECT_EQ(sweeps.solution, first.solution) << threads << " threads";
    EXPECT_EQ(sweeps.p, first.p) << threads << " threads";
    EXPECT_EQ(sweeps.p_dot_q, first.p_dot_q) << threads << " threads";
    EXPECT_EQ(sweeps.r_dot_r, first.r_dot_r) << threads << " threads";
    EXPECT_EQ(sweeps.r_dot_z, first.r_dot_z) << threads << " threads";
  }
}

TEST(CgStep, SameBitsOnOneAndSeveralThreadsFloat32) {
  expect_same_bits_on_any_thread_count<float>();
}
TEST(CgStep, SameBitsOnOneAndSeveralThreadsFloat64) {
  expect_same_bits_on_any_thread_count<double>();
}

TEST(CgStep, BadCallsAreRefused) {
  Cloth cloth(testing::busy_scene(4, 5), Precision::Float64, {});
  const clothlab_system& system = cloth.system();
  const auto& cg = host_extension<clothlab_cg_step_extension>(system, CLOTHLAB_EXT_CG_STEP);
  void* p = system.alloc_vector(system.context);
  void* q = system.alloc_vector(system.context);
  void* z = system.alloc_vector(system.context);
  double dot = 0;
  EXPECT_EQ(cg.product(system.context, 0, 0, nullptr, p, nullptr, q, &dot),
            CLOTHLAB_ERROR_INVALID_ARGUMENT)
      << "a product before any linearise";
  EXPECT_EQ(cg.linearise(system.context, 0.0, nullptr, system.v, -1.0, -0.1),
            CLOTHLAB_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(cg.linearise(system.context, 0.0, system.x, system.v, -1.0, -0.1), CLOTHLAB_OK);
  EXPECT_EQ(cg.product(system.context, 0, 0, nullptr, p, nullptr, q, nullptr),
            CLOTHLAB_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(cg.product(system.context, 0, 0, nullptr, p, nullptr, p, &dot),
            CLOTHLAB_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(cg.product(system.context, 1, 1, z, p, nullptr, q, &dot),
            CLOTHLAB_ERROR_INVALID_ARGUMENT)
      << "a direction without a solution";
  EXPECT_EQ(cg.product(system.context, 0, 0, nullptr, p, nullptr, q, &dot), CLOTHLAB_OK);
  EXPECT_EQ(cg.update(system.context, 1.0, q, p, q, p, q, nullptr, &dot),
            CLOTHLAB_ERROR_INVALID_ARGUMENT);
}

// implicit_euler's solve of one stiff step (h = 1/60 s on a 40 x 37 sheet off rest) to a tight
// tolerance, fused and through separate calls: the same solution within rounding, a similar
// iteration count; the fused solve has the same bits on 1 and 2 threads. With the multigrid
// preconditioner (multigrid = 1), `fused` makes CG and the V-cycle's fine smoother take the
// host's linearised product instead of the definite Jacobian's product and an axpy.
template <class Real>
struct Solve {
  std::vector<double> solution;
  long iterations = 0;
  bool converged = false;
};

template <class Real>
Solve<Real> solve(bool fused, int threads, double tolerance, bool multigrid = false,
                  long cap = 2000) {
  PipelineOptions options;
  options.threads = threads;
  Cloth cloth(testing::busy_scene(40, 37),
              sizeof(Real) == 4 ? Precision::Float32 : Precision::Float64, options);
  std::vector<double> x, v;
  testing::move_off_rest(cloth, 7, 0.01, x, v);
  const sdk::System<Real> system(cloth.system());
  system.jacobian().reserve();
  std::array<Real*, builtin::PreconditionedCg<Real>::vector_count> vectors{};
  for (Real*& vector : vectors) vector = system.alloc_vector();
  Real* const rhs = system.alloc_vector();
  Real* const solution = system.alloc_vector();
  std::vector<double> inverse_blocks(9 * std::size_t{system.particle_count()});
  std::optional<builtin::MultigridPreconditioner> preconditioner;
  if (multigrid)
    preconditioner.emplace(system, builtin::kDefaultCoarsestNodes, builtin::kDefaultMultigridSweeps,
                           1, system.jacobian().pattern());
  builtin::PreconditionedCg<Real> cg(system, vectors, inverse_blocks, true, fused,
                                     preconditioner ? &*preconditioner : nullptr);
  EXPECT_EQ(cg.fused(), fused && !multigrid);
  const double h = 1.0 / 60.0;
  system.acceleration(0.0, system.x(), system.v(), rhs);
  cg.start(0.0, h, system.x(), system.v(), rhs, solution, false, tolerance);
  Solve<Real> out;
  auto outcome = builtin::PreconditionedCg<Real>::Outcome::kRunning;
  while (outcome == builtin::PreconditionedCg<Real>::Outcome::kRunning && out.iterations < cap) {
    outcome = cg.iterate();
    ++out.iterations;
  }
  cg.finish();
  out.converged = outcome == builtin::PreconditionedCg<Real>::Outcome::kConverged;
  out.solution = values_of<Real>(cloth.system(), solution);
  return out;
}

template <class Real>
void expect_fused_solve_as_separate(double tolerance, double agreement, bool multigrid = false) {
  const Solve<Real> separate = solve<Real>(false, 1, tolerance, multigrid);
  const Solve<Real> fused = solve<Real>(true, 1, tolerance, multigrid);
  ASSERT_TRUE(separate.converged);
  ASSERT_TRUE(fused.converged);
  EXPECT_GT(separate.iterations, multigrid ? 5 : 20);  // a real solve, not one step
  EXPECT_NEAR(double(fused.iterations), double(separate.iterations),
              0.1 * double(separate.iterations) + 2);
  const double largest = max_abs(separate.solution);
  ASSERT_GT(largest, 0.0);
  ASSERT_EQ(fused.solution.size(), separate.solution.size());
  for (std::size_t e = 0; e < fused.solution.size(); ++e)
    ASSERT_NEAR(fused.solution[e], separate.solution[e], agreement * largest) << e;
  EXPECT_EQ(solve<Real>(true, 2, tolerance, multigrid).solution, fused.solution);
}

TEST(CgStep, ImplicitEulersFusedSolveIsTheSeparateCallsFloat64) {
  expect_fused_solve_as_separate<double>(1e-10, 1e-8);
}
TEST(CgStep, ImplicitEulersFusedSolveIsTheSeparateCallsFloat32) {
  expect_fused_solve_as_separate<float>(1e-4, 2e-3);
}
// With the multigrid, also the iterate after a few iterations (far from converged, so each
// V-cycle's z shapes it): the same within rounding.
template <class Real>
void expect_multigrid_iterates_as_separate(double tolerance, double agreement,
                                           double iterate_agreement) {
  expect_fused_solve_as_separate<Real>(tolerance, agreement, true);
  constexpr long kIterations = 3;
  const Solve<Real> separate = solve<Real>(false, 1, 1e-30, true, kIterations);
  const Solve<Real> fused = solve<Real>(true, 1, 1e-30, true, kIterations);
  const double largest = max_abs(separate.solution);
  ASSERT_GT(largest, 0.0);
  double worst = 0.0;
  for (std::size_t e = 0; e < fused.solution.size(); ++e)
    worst = std::max(worst, std::abs(fused.solution[e] - separate.solution[e]));
  EXPECT_LT(worst, iterate_agreement * largest);
}

TEST(CgStep, TheMultigridSolveOnTheLinearisedProductIsTheSeparateCallsFloat64) {
  expect_multigrid_iterates_as_separate<double>(1e-10, 1e-8, 1e-10);
}
TEST(CgStep, TheMultigridSolveOnTheLinearisedProductIsTheSeparateCallsFloat32) {
  expect_multigrid_iterates_as_separate<float>(1e-4, 2e-3, 1e-4);
}

}  // namespace
}  // namespace clothlab
