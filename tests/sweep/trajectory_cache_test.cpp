#include "clothlab/sweep/trajectory_cache.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "sweep_test_support.hpp"

namespace clothlab::sweep {
namespace {

using testing::ScratchFolder;

CaseSpec reference_case(const std::vector<Setting>& extra) {
  SweepSpec spec;
  spec.source = "test";
  spec.fixed = {{"integrator.plugin", "rk4", "test"},
                {"scenario.plugin", "flag", "test"},
                {"scenario.rows", "20", "test"}};
  for (const Setting& setting : extra) spec.fixed.push_back(setting);
  return expand_cases(spec).at(0);
}

struct CountingRuns {
  int calls = 0;
  bool stable = true;
  Trajectory operator()(const CaseSpec&) {
    ++calls;
    Trajectory run;
    run.positions = {0.1, 0.2, 1.0 / 3.0};
    run.diagonal = 1.5;
    run.summary.max_stretch.over_run = 1.02;
    run.summary.max_stretch_away_from_pins.over_run = 1.015;
    run.summary.p99_stretch.over_run = 1.01;
    run.summary.contacts.emplace().colliders = 2;
    run.summary.contacts->thickness = 0.01;
    if (!stable) run.verdict.status = CaseStatus::Unstable;
    return run;
  }
};

TEST(TrajectoryCache, ServesAnIdenticalCaseFromTheFolder) {
  ScratchFolder folder;
  std::string rk4_build = "rk4.so size 1 fnv1a 01";
  const PluginIdentity identity = [&](const std::string& id) {
    return id == "rk4" ? rk4_build : "flag.so";
  };
  CountingRuns runs;
  {
    TrajectoryCache cache(folder.path() / "references", identity, "clothlab 1");
    const Trajectory first = cache.run(std::ref(runs), reference_case({}));
    EXPECT_EQ(runs.calls, 1);
    EXPECT_EQ(cache.hits(), 0);
    EXPECT_TRUE(std::filesystem::exists(cache.path_of(reference_case({}))));
  }
  // A later session: the same effective settings (a repeated key's last value, another
  // timeout) are served, bit for bit.
  TrajectoryCache cache(folder.path() / "references", identity, "clothlab 1");
  const Trajectory again =
      cache.run(std::ref(runs), reference_case({{"scenario.rows", "30", "test"},
                                                {"scenario.rows", "20", "test"},
                                                {"timeout", "5", "test"}}));
  EXPECT_EQ(runs.calls, 1);
  EXPECT_EQ(cache.hits(), 1);
  EXPECT_EQ(again.positions, (std::vector<double>{0.1, 0.2, 1.0 / 3.0}));
  EXPECT_EQ(again.diagonal, 1.5);
  // Its whole summary too (--choose holds a method to the reference's robust stretch).
  EXPECT_EQ(again.summary, CountingRuns()(reference_case({})).summary);
  // Another setting or a rebuilt plugin is a miss.
  cache.run(std::ref(runs), reference_case({{"scenario.rows", "30", "test"}}));
  EXPECT_EQ(runs.calls, 2);
  rk4_build = "rk4.so size 2 fnv1a 02";
  cache.run(std::ref(runs), reference_case({}));
  EXPECT_EQ(runs.calls, 3);
  EXPECT_EQ(cache.hits(), 1);
}

// --choose's error run at a 200 x 200 and at a 300 x 300 scene is the same 100 x 100 run
// ("mesh" over the scene's rows and cols): one reference serves both, and the scene that is
// 100 x 100 itself.
TEST(TrajectoryCache, ServesTheSameMeshHoweverItIsSpelt) {
  ScratchFolder folder;
  TrajectoryCache cache(folder.path(), nullptr, "clothlab 1");
  CountingRuns runs;
  const auto scene = [](const std::string& side, const std::string& error_mesh) {
    std::vector<Setting> settings = {{"scenario.rows", side, "test"},
                                     {"scenario.cols", side, "test"}};
    if (!error_mesh.empty()) settings.push_back({"mesh", error_mesh, "test"});
    return reference_case(settings);
  };
  cache.run(std::ref(runs), scene("200", "100x100"));
  cache.run(std::ref(runs), scene("300", "100x100"));
  cache.run(std::ref(runs), scene("100", ""));
  EXPECT_EQ(runs.calls, 1);
  EXPECT_EQ(cache.hits(), 2);
  cache.run(std::ref(runs), scene("200", "100x50"));
  cache.run(std::ref(runs), scene("100", "100x50"));
  EXPECT_EQ(runs.calls, 2);
  // A later rows setting wins over the mesh, as in a run.
  cache.run(std::ref(runs),
            reference_case({{"mesh", "100x50", "test"}, {"scenario.rows", "40", "test"}}));
  EXPECT_EQ(runs.calls, 3);
}

// A reference that does not match the scene is computed again, never served: another material,
// mesh, precision, host build, or the same file name with other content.
TEST(TrajectoryCache, RecomputesAReferenceOfAnotherSceneOrHost) {
  ScratchFolder folder;
  CountingRuns runs;
  const std::filesystem::path mesh_file = folder.path() / "disc.obj";
  std::ofstream(mesh_file) << "v 0 0 0\n";
  const auto scene = [&](const std::string& stiffness, const std::string& rows,
                         const std::string& precision) {
    return reference_case({{"material.stretch_stiffness", stiffness, "test"},
                           {"scenario.rows", rows, "test"},
                           {"precision", precision, "test"},
                           {"scenario.file", mesh_file.string(), "test"}});
  };
  {
    TrajectoryCache cache(folder.path() / "references", nullptr, "clothlab 1");
    cache.run(std::ref(runs), scene("6100", "20", "float64"));
    cache.run(std::ref(runs), scene("6100", "20", "float64"));
    EXPECT_EQ(runs.calls, 1);
    cache.run(std::ref(runs), scene("3000", "20", "float64"));  // another material
    cache.run(std::ref(runs), scene("6100", "30", "float64"));  // another mesh
    cache.run(std::ref(runs), scene("6100", "20", "float32"));  // another precision
    EXPECT_EQ(runs.calls, 4);
    std::ofstream(mesh_file) << "v 0 0 1\n";  // the mesh file edited in place
    cache.run(std::ref(runs), scene("6100", "20", "float64"));
    EXPECT_EQ(runs.calls, 5);
    EXPECT_EQ(cache.hits(), 1);
  }
  // Another host build (version) misses what the first stored, then serves its own.
  TrajectoryCache rebuilt(folder.path() / "references", nullptr, "clothlab 2");
  rebuilt.run(std::ref(runs), scene("6100", "20", "float64"));
  EXPECT_EQ(runs.calls, 6);
  EXPECT_EQ(rebuilt.hits(), 0);
  rebuilt.run(std::ref(runs), scene("6100", "20", "float64"));
  EXPECT_EQ(runs.calls, 6);
  EXPECT_EQ(rebuilt.hits(), 1);
}

TEST(TrajectoryCache, KeepsNeitherUnstableRunsNorUnreadableFiles) {
  ScratchFolder folder;
  TrajectoryCache cache(folder.path(), nullptr, "clothlab 1");
  CountingRuns runs;
  runs.stable = false;
  cache.run(std::ref(runs), reference_case({}));
  cache.run(std::ref(runs), reference_case({}));
  EXPECT_EQ(runs.calls, 2);
  EXPECT_FALSE(std::filesystem::exists(cache.path_of(reference_case({}))));
  // A damaged file is a miss, and is replaced.
  std::ofstream(cache.path_of(reference_case({}))) << "{\"identity\": 3";
  runs.stable = true;
  cache.run(std::ref(runs), reference_case({}));
  EXPECT_EQ(runs.calls, 3);
  cache.run(std::ref(runs), reference_case({}));
  EXPECT_EQ(runs.calls, 3);
  EXPECT_EQ(cache.hits(), 1);
}

}  // namespace
}  // namespace clothlab::sweep
