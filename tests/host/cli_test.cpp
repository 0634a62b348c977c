// The clothlab program end to end, on small grids.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <clothlab/io/frame_formats.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "../support/read_text.hpp"

namespace {

namespace fs = std::filesystem;

const fs::path builtin_plugins = CLOTHLAB_BUILTIN_PLUGIN_DIR;
const fs::path test_plugins = CLOTHLAB_TEST_PLUGIN_DIR;
const fs::path source_dir = CLOTHLAB_SOURCE_DIR;

struct Outcome {
  int exit_code = -1;
  std::string out, err;
};

using clothlab::testing::read_text;

// A fresh folder per test for outputs, removed afterwards.
class Clothlab : public testing::Test {
 protected:
  void SetUp() override {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    folder_ = fs::temp_directory_path() /
              ("clothlab_cli_" + std::to_string(getpid()) + "_" + info->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  fs::path file(const std::string& name) const { return folder_ / name; }

  // Runs clothlab with the arguments (shell words) and an optional environment prefix; with a
  // time limit a hang is killed (exit code 137) instead of stopping the tests.
  Outcome run(const std::string& arguments, const std::string& environment = "",
              int time_limit_s = 0) const {
    const std::string limit =
        time_limit_s > 0 ? " timeout -s KILL " + std::to_string(time_limit_s) : "";
    const std::string command = "cd '" + folder_.string() + "' && env -u CLOTHLAB_PLUGIN_PATH " +
                                environment + limit + " '" CLOTHLAB_EXECUTABLE "' " + arguments +
                                " > stdout.txt 2> stderr.txt";
    const int status = std::system(command.c_str());
    Outcome outcome;
    outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    outcome.out = read_text(file("stdout.txt"));
    outcome.err = read_text(file("stderr.txt"));
    return outcome;
  }

  // Files in the folder besides the captured streams.
  std::vector<std::string> outputs() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(folder_)) {
      const std::string name = entry.path().filename().string();
      if (name != "stdout.txt" && name != "stderr.txt") names.push_back(name);
    }
    return names;
  }

 private:
  fs::path folder_;
};

const char* small_sheet = "--scenario=sheet --set scenario.rows=4 --set scenario.cols=5 ";

TEST_F(Clothlab, JsonSummaryHasEveryKey) {
  const Outcome outcome = run(std::string("--integrator=rk4 ") + small_sheet +
                              "--dt 0.001 --steps 20 --quiet --json summary.json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  EXPECT_EQ(outcome.out, "");  // --quiet
  const auto json = nlohmann::json::parse(read_text(file("summary.json")));
  for (const char* key : {"integrator",
                          "scenario",
                          "precision",
                          "rows",
                          "cols",
                          "dt",
                          "steps",
                          "sim_time_s",
                          "wall_time_s",
                          "loop_time_s",
                          "ms_per_step",
                          "phase_ms",
                          "springs",
                          "force_evals",
                          "springs_per_second",
                          "real_time_factor",
                          "stable",
                          "verdict",
                          "threads",
                          "simd",
                          "counters",
                          "contacts",
                          "integrator_params",
                          "scenario_params"})
    EXPECT_TRUE(json.contains(key)) << key;
  for (const char* key : {"median", "p10", "p90"}) EXPECT_TRUE(json["ms_per_step"].contains(key));
  for (const char* key : {"internal_forces", "external_forces", "integrate"})
    EXPECT_TRUE(json["phase_ms"].contains(key));
  for (const char* key : {"springs_evaluated", "springs_damped", "normals_computed",
                          "particles_integrated", "steps_on_one_thread"})
    EXPECT_TRUE(json["counters"].contains(key)) << key;
  EXPECT_EQ(json["integrator"], "rk4");
  EXPECT_EQ(json["scenario"], "sheet");
  EXPECT_EQ(json["precision"], "float32");
  EXPECT_EQ(json["rows"], 4);
  EXPECT_EQ(json["cols"], 5);
  EXPECT_EQ(json["steps"], 20);
  EXPECT_DOUBLE_EQ(json["sim_time_s"].get<double>(), 0.02);
  // The loop holds the steps and more (the checks between them).
  EXPECT_GE(json["loop_time_s"].get<double>(), json["wall_time_s"].get<double>());
  EXPECT_GT(json["wall_time_s"].get<double>(), 0.0);
  // Seed eq. 2.2 for 4 x 5: structural 4*4 + 3*5 = 31, shear 2*3*4 = 24, flexion 4*3 + 2*5 = 22.
  EXPECT_EQ(json["springs"], 77);
  EXPECT_EQ(json["force_evals"], 80);  // 4 per RK4 step
  EXPECT_EQ(json["stable"], true);
  EXPECT_EQ(json["scenario_params"]["rows"], 4);
}

TEST_F(Clothlab, PrintsAHumanSummary) {
  const Outcome outcome = run(std::string("--integrator=euler ") + small_sheet + "--steps 3");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  EXPECT_NE(outcome.out.find("euler on sheet, 4x5"), std::string::npos) << outcome.out;
  EXPECT_NE(outcome.out.find("ms/step"), std::string::npos) << outcome.out;
}

// The position-based integrator runs from the command line on the windy scene, in frames of
// 1 ms and of 50 ms (40 frame substeps of one Gauss-Seidel sweep keep it stable there); its
// own inner substeps stay at 1, so the frame substeps are the one knob.
TEST_F(Clothlab, XpbdRunsTheFlagInFramesOf1MsAnd50Ms) {
  for (const char* frame_rate : {"1000", "20"}) {
    const Outcome outcome =
        run(std::string("--integrator=xpbd --scenario=flag --frame-rate ") + frame_rate +
            " --substeps 40 --duration 0.5 --json xpbd.json --quiet");
    ASSERT_EQ(outcome.exit_code, 0) << frame_rate << " Hz: " << outcome.err;
    const auto json = nlohmann::json::parse(read_text(file("xpbd.json")));
    EXPECT_EQ(json["stable"], true) << frame_rate;
    EXPECT_EQ(json["integrator_params"]["inner_substeps"], 1);
  }
}

// xpbd's substeps parameter is gone (they multiplied the frame substeps): a config that sets it
// is refused with the replacement, wherever it sets it.
TEST_F(Clothlab, XpbdsOldSubstepsKeyIsRefusedWithWhatToUseInstead) {
  std::ofstream(file("old.yaml")) << "integrator:\n  plugin: xpbd\n  substeps: 8\n";
  const Outcome from_file = run("--config old.yaml --steps 1");
  EXPECT_EQ(from_file.exit_code, 1);
  EXPECT_EQ(from_file.err.rfind("clothlab: error: old.yaml:3:13: integrator.substeps = 8: xpbd has "
                                "no substeps parameter any more; use the frame substeps",
                                0),
            0u)
      << from_file.err;
  EXPECT_NE(from_file.err.find("integrator.inner_substeps"), std::string::npos) << from_file.err;
  const Outcome by_id = run("--integrator=xpbd --set plugin_params.xpbd.substeps=8 --steps 1");
  EXPECT_EQ(by_id.exit_code, 1);
  EXPECT_EQ(by_id.err.rfind("clothlab: error: --set: plugin_params.xpbd.substeps = 8: xpbd has "
                            "no substeps parameter any more",
                            0),
            0u)
      << by_id.err;
  EXPECT_EQ(std::count(by_id.err.begin(), by_id.err.end(), '\n'), 1) << by_id.err;
}

TEST_F(Clothlab, DivergingRunExitsThreeAndStillWritesItsJson) {
  const Outcome outcome =
      run(std::string("--integrator=euler ") + small_sheet +
          "--set scenario.structural.ks=1e9 --dt 0.05 --steps 500 --json diverged.json");
  EXPECT_EQ(outcome.exit_code, 3) << outcome.err;
  EXPECT_EQ(outcome.err.rfind("clothlab: error: run diverged: non-finite", 0), 0u) << outcome.err;
  const auto json = nlohmann::json::parse(read_text(file("diverged.json")));
  EXPECT_EQ(json["stable"], false);
  const int failed = json["failed_step"].get<int>();
  EXPECT_GT(failed, 0);
  EXPECT_LT(failed, 500);
  EXPECT_EQ(json["steps"], failed);
  EXPECT_NE(json["verdict"].get<std::string>().find("at step " + std::to_string(failed)),
            std::string::npos);
}

TEST_F(Clothlab, BadSetExitsOneAndLeavesNoOutputFile) {
  const Outcome outcome =
      run("--integrator=rk4 --scenario=sheet --set scenario.rows=0 --steps 2 --json out.json "
          "--state-out state.csv");
  EXPECT_EQ(outcome.exit_code, 1);
  EXPECT_EQ(outcome.err,
            "clothlab: error: --set: scenario.rows = 0: out of range; allowed: int in [1, 4096]\n");
  EXPECT_TRUE(outputs().empty());
}

TEST_F(Clothlab, ValuesThePluginRejectsAreBadInput) {
  // In range for the host, but the flag refuses a zero wind direction with wind on.
  const Outcome outcome =
      run("--scenario=flag --set scenario.wind.direction=[0,0,0] --set scenario.wind.strength=5");
  EXPECT_EQ(outcome.exit_code, 1);
  EXPECT_NE(outcome.err.find("wind.direction"), std::string::npos) << outcome.err;
}

// The mesh scenario's file is a text parameter: a bad one is one line of bad input naming the
// file (resolved against the working directory on the command line).
TEST_F(Clothlab, AMeshFileThatIsNotThereIsOneLineOfBadInput) {
  const Outcome outcome =
      run("--integrator=verlet --scenario=mesh --set scenario.file=missing.obj --steps 2");
  EXPECT_EQ(outcome.exit_code, 1);
  EXPECT_NE(outcome.err.find((file("missing.obj").string() + ": no such file")), std::string::npos)
      << outcome.err;
  EXPECT_EQ(std::count(outcome.err.begin(), outcome.err.end(), '\n'), 1) << outcome.err;
}

// In a config file the path is relative to the file's folder; the report records it resolved.
TEST_F(Clothlab, AMeshPathInAConfigIsRelativeToItsFolder) {
  fs::create_directories(file("configs"));
  fs::copy_file(source_dir / "assets/meshes/cape.obj", file("configs/cape.obj"));
  std::ofstream(file("configs/run.yaml"))
      << "integrator: verlet\nscenario:\n  plugin: mesh\n  file: cape.obj\n"
         "  pin: {by_box: true, box: {min: [-1, 1.419, -1], max: [1, 1.421, 1]}}\n";
  // Not bad input; whether the two steps stay within the stability limits is not the point
  // (a host without clothlab.mesh/1 runs the scene's stand-in grid), and the JSON comes either
  // way.
  const Outcome outcome = run("--config configs/run.yaml --steps 2 --json out.json");
  ASSERT_NE(outcome.exit_code, 1) << outcome.err;
  const nlohmann::json json = nlohmann::json::parse(read_text(file("out.json")));
  EXPECT_EQ(json["scenario_params"]["file"], file("configs/cape.obj").string());
  const Outcome typo = run("--config configs/run.yaml --set scenario.fil=x.obj --steps 2");
  EXPECT_NE(typo.err.find("did you mean scenario.file?"), std::string::npos) << typo.err;
}

TEST_F(Clothlab, ListsTextParameters) {
  const Outcome outcome = run("--list-plugins");
  EXPECT_NE(outcome.out.find("scenario.file = \"\"  (text of at most 4096 bytes, a file path)"),
            std::string::npos)
      << outcome.out;
}

TEST_F(Clothlab, SolverStatisticsOfAnImplicitIntegratorReachTheJson) {
  for (const std::string integrator :
       {"implicit_euler", "bdf2", "projective_dynamics", "vbd", "rk4"}) {
    const Outcome outcome = run("--integrator=" + integrator + " " + small_sheet +
                                "--dt 0.01 --steps 20 --quiet --json s.json");
    ASSERT_EQ(outcome.exit_code, 0) << integrator << ": " << outcome.err;
    const auto json = nlohmann::json::parse(read_text(file("s.json")));
    if (integrator == "rk4") {
      EXPECT_TRUE(json["solver"].is_null());  // an explicit method has no solver
      continue;
    }
    const auto& solver = json["solver"];
    EXPECT_EQ(solver["steps"], 20) << integrator;
    EXPECT_EQ(solver["non_converged_steps"], 0) << integrator;
    EXPECT_TRUE(solver["first_non_converged_step"].is_null()) << integrator;
    EXPECT_GE(solver["iterations_per_step"]["mean"].get<double>(), 1.0) << integrator;
    // Matrix-free CG and block descent factor nothing; projective dynamics factors once for its
    // one dt.
    EXPECT_EQ(solver["factorizations"], integrator == "projective_dynamics" ? 1 : 0);
    EXPECT_EQ(json["verdict"].get<std::string>().find("missed"), std::string::npos);
  }
}

// 20 implicit_euler steps of the small sheet (JSON in s.json), and the settings that make
// every solve of that run miss its tolerance.
const std::string implicit_euler_run_of_20 = std::string("--integrator=implicit_euler ") +
                                             small_sheet +
                                             "--dt 0.01 --steps 20 --quiet --json s.json ";
const char* one_iteration_solves =
    "--set integrator.max_iterations=1 --set integrator.tolerance=1e-14 ";

// A missed tolerance is a failed check (exit 3, verdict "unconverged"), counted over the whole
// run rather than stopping it; the same run with a tolerance CG meets is stable (exit 0).
TEST_F(Clothlab, ASolveThatMissesItsToleranceFailsTheRunCountedWithItsStep) {
  const Outcome outcome = run(implicit_euler_run_of_20 + one_iteration_solves);
  ASSERT_EQ(outcome.exit_code, 3) << outcome.err;
  EXPECT_EQ(outcome.err.rfind("clothlab: error: run unconverged: the solver missed "
                              "its tolerance in 20 of 20 steps (first at step 1); stable: 20 steps",
                              0),
            0u)
      << outcome.err;
  const auto json = nlohmann::json::parse(read_text(file("s.json")));
  EXPECT_EQ(json["steps"], 20);  // not stopped at the first miss
  EXPECT_FALSE(json["stable"]);
  EXPECT_EQ(json["failed_check"], "unconverged");
  EXPECT_EQ(json["failed_step"], 1);
  EXPECT_EQ(json["solver"]["non_converged_steps"], 20);
  EXPECT_EQ(json["solver"]["first_non_converged_step"], 1);
  EXPECT_EQ(json["solver"]["iterations_per_step"]["max"], 1);
  EXPECT_GT(json["solver"]["max_residual"].get<double>(), 1e-14);
  EXPECT_EQ(json["verdict"].get<std::string>().rfind("unconverged: ", 0), 0u) << json["verdict"];

  const Outcome met = run(implicit_euler_run_of_20 + "--set integrator.max_iterations=1000");
  ASSERT_EQ(met.exit_code, 0) << met.err;
  const auto met_json = nlohmann::json::parse(read_text(file("s.json")));
  EXPECT_TRUE(met_json["stable"]);
  EXPECT_TRUE(met_json["failed_check"].is_null());
  EXPECT_EQ(met_json["solver"]["non_converged_steps"], 0);
  EXPECT_EQ(met_json["verdict"].get<std::string>().rfind("stable: 20 steps", 0), 0u);
}

// stability.unconverged = count takes the iteration limit as a fixed budget: the same run of
// one-iteration solves passes on its other checks, with every miss still counted in the
// verdict and the JSON. A value other than fail or count is one line of bad input.
TEST_F(Clothlab, AFixedIterationBudgetCountsTheMissedTolerancesWithoutFailingTheRun) {
  const std::string budget = implicit_euler_run_of_20 + one_iteration_solves;
  const Outcome counted = run(budget + "--set stability.unconverged=count");
  ASSERT_EQ(counted.exit_code, 0) << counted.err;
  const auto json = nlohmann::json::parse(read_text(file("s.json")));
  EXPECT_TRUE(json["stable"]);
  EXPECT_TRUE(json["failed_check"].is_null());
  EXPECT_EQ(json["solver"]["non_converged_steps"], 20);
  EXPECT_EQ(json["solver"]["first_non_converged_step"], 1);
  EXPECT_EQ(json["verdict"],
            "stable: 20 steps, 2 checks passed (finite, stretch, energy); the solver missed its "
            "tolerance in 20 of 20 steps (first at step 1)");

  const Outcome bad = run(budget + "--set stability.unconverged=maybe");
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
  EXPECT_NE(bad.err.find("stability.unconverged"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("allowed: fail or count"), std::string::npos) << bad.err;
}

TEST_F(Clothlab, SolverParameterOutOfRangeIsOneLineOfBadInput) {
  for (const char* setting :
       {"integrator.max_iterations=0", "integrator.tolerance=2", "integrator.newton_steps=51"}) {
    const Outcome outcome = run(std::string("--integrator=implicit_euler ") + small_sheet +
                                "--steps 1 --set " + setting);
    EXPECT_EQ(outcome.exit_code, 1) << setting;
    EXPECT_EQ(std::count(outcome.err.begin(), outcome.err.end(), '\n'), 1) << outcome.err;
    EXPECT_NE(outcome.err.find(std::string(setting).substr(0, std::string(setting).find('='))),
              std::string::npos)
        << outcome.err;
  }
  const Outcome outcome = run(std::string("--integrator=projective_dynamics ") + small_sheet +
                              "--steps 1 --set integrator.iterations=0");
  EXPECT_EQ(outcome.exit_code, 1);
  EXPECT_NE(outcome.err.find("integrator.iterations = 0"), std::string::npos) << outcome.err;
}

TEST_F(Clothlab, MissingOutputFolderIsReportedBeforeTheRun) {
  const Outcome outcome = run(std::string(small_sheet) + "--steps 1 --json no/such/folder/s.json");
  EXPECT_EQ(outcome.exit_code, 1);
  EXPECT_EQ(outcome.out, "");  // nothing ran
  EXPECT_NE(outcome.err.find("no/such/folder/s.json"), std::string::npos) << outcome.err;
}

TEST_F(Clothlab, UnknownPluginParameterListsTheValidKeys) {
  const Outcome outcome = run("--integrator=rk4 --scenario=sheet --set scenario.rowz=3");
  EXPECT_EQ(outcome.exit_code, 1);
  EXPECT_NE(
      outcome.err.find(
          "unknown parameter scenario.rowz (did you mean scenario.rows?); valid: scenario.rows"),
      std::string::npos)
      << outcome.err;
}

TEST_F(Clothlab, IntegratorByNameFileNameAndAbsolutePath) {
  const std::string absolute = (builtin_plugins / "rk4.so").string();
  for (const std::string& integrator : {std::string("rk4"), std::string("rk4.so"), absolute}) {
    const Outcome outcome =
        run("--integrator=" + integrator + " " + small_sheet + "--steps 2 --json s.json --quiet");
    ASSERT_EQ(outcome.exit_code, 0) << integrator << ": " << outcome.err;
    EXPECT_EQ(nlohmann::json::parse(read_text(file("s.json")))["integrator"], "rk4");
  }
}

TEST_F(Clothlab, MissingPluginExitsTwoListingTheSearchPath) {
  const Outcome outcome = run("--integrator=nothing --scenario=sheet --steps 1");
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_NE(outcome.err.find("nothing.so"), std::string::npos) << outcome.err;
  EXPECT_NE(outcome.err.find(fs::path(builtin_plugins).lexically_normal().string()),
            std::string::npos)
      << outcome.err;
}

TEST_F(Clothlab, LibraryOfAnotherAbiExitsTwo) {
  const Outcome outcome =
      run("--integrator=" + (test_plugins / "bad/clothlab_test_abi999.so").string() +
          " --scenario=sheet --steps 1");
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_NE(outcome.err.find("abi_version = 999.0"), std::string::npos) << outcome.err;
}

TEST_F(Clothlab, PluginPathFromEnvironmentAndCommandLine) {
  const std::string arguments =
      "--integrator=clothlab_test_good --scenario=clothlab_test_good --steps 3 --quiet";
  EXPECT_EQ(run(arguments).exit_code, 2);
  const Outcome from_environment =
      run(arguments, "CLOTHLAB_PLUGIN_PATH=/nonexistent:" + (test_plugins / "good").string());
  EXPECT_EQ(from_environment.exit_code, 0) << from_environment.err;
  const Outcome from_command_line =
      run(arguments + " --plugin-path " + (test_plugins / "good").string());
  EXPECT_EQ(from_command_line.exit_code, 0) << from_command_line.err;
}

TEST_F(Clothlab, StateOutIsFullPrecisionCsv) {
  const Outcome outcome =
      run("--integrator=verlet --scenario=sheet --set scenario.rows=2 --set scenario.cols=3 "
          "--steps 1 --precision float64 --state-out state.csv --quiet");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  std::ifstream csv(file("state.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "row,col,x,y,z,vx,vy,vz");
  int rows = 0;
  while (std::getline(csv, line)) {
    ++rows;
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 7) << line;
  }
  EXPECT_EQ(rows, 6);
  EXPECT_EQ(outputs(), std::vector<std::string>{"state.csv"});  // no temporary left
}

// The test scenario's cloth dropped on its plane: every built-in that declares
// CLOTHLAB_TRAIT_RESOLVES_CONTACTS leaves it resting at the plane's thickness (0.01 m).
const std::string collider_scene =
    "--scenario=" + (test_plugins / "colliders" / "clothlab_test_collider.so").string() + " ";

TEST_F(Clothlab, EveryContactResolvingBuiltInRestsTheClothOnThePlaneAtItsThickness) {
  for (const char* integrator :
       {"euler", "midpoint", "rk4", "implicit_euler", "bdf2", "projective_dynamics", "xpbd"}) {
    const Outcome outcome = run(std::string("--integrator=") + integrator + " " + collider_scene +
                                "--dt 0.001 --duration 1.5 --state-out state.csv --quiet");
    ASSERT_EQ(outcome.exit_code, 0) << integrator << ": " << outcome.err;
    std::ifstream csv(file("state.csv"));
    std::string line;
    std::getline(csv, line);
    int particles = 0;
    while (std::getline(csv, line)) {
      std::stringstream fields(line);
      std::string field;
      for (int column = 0; column < 4; ++column) std::getline(fields, field, ',');
      EXPECT_NEAR(std::stod(field), 0.01, 1e-4) << integrator << ": " << line;
      ++particles;
    }
    EXPECT_EQ(particles, 9) << integrator;
  }
}

TEST_F(Clothlab, AnIntegratorThatDoesNotResolveContactsIsRefusedOnAColliderScene) {
  const Outcome outcome = run("--integrator=verlet " + collider_scene + "--steps 10 --json o.json");
  EXPECT_EQ(outcome.exit_code, 1);
  EXPECT_EQ(outcome.err,
            "clothlab: error: integrator verlet does not resolve contacts (no "
            "CLOTHLAB_TRAIT_RESOLVES_CONTACTS in clothlab.integrator-traits/1), which scenario "
            "test-collider's 1 collider(s) need\n");
  EXPECT_TRUE(outputs().empty());
}

// The test scenario's disc, offered as a triangle mesh (clothlab.mesh/1), hanging from rim
// vertices 19 and 28: the host builds the core's model from the mesh.
const std::string mesh_scene =
    "--scenario=" + (test_plugins / "mesh" / "clothlab_test_mesh.so").string() + " ";

TEST_F(Clothlab, EveryBuiltInRunsAMeshAndKeepsItsPins) {
  for (const char* integrator : {"euler", "midpoint", "rk4", "verlet", "implicit_euler",
                                 "projective_dynamics", "xpbd", "xpbd_tethers", "vbd"}) {
    const Outcome outcome = run(std::string("--integrator=") + integrator + " " + mesh_scene +
                                "--dt 0.001 --duration 0.2 --state-out state.csv --quiet");
    ASSERT_EQ(outcome.exit_code, 0) << integrator << ": " << outcome.err;
    std::ifstream csv(file("state.csv"));
    std::string line;
    std::getline(csv, line);
    EXPECT_EQ(line, "particle,x,y,z,vx,vy,vz") << integrator;  // not a grid: by index
    int particles = 0;
    double lowest = 0;
    while (std::getline(csv, line)) {
      std::stringstream fields(line);
      std::string field;
      std::vector<double> values;
      while (std::getline(fields, field, ',')) values.push_back(std::stod(field));
      ASSERT_EQ(values.size(), 7u) << integrator << ": " << line;
      if (particles == 19) {
        EXPECT_NEAR(values[1], 0.3, 1e-7) << integrator;  // a pin, where it started (float32)
      }
      if (particles == 28) {
        EXPECT_NEAR(values[1], -0.3, 1e-7) << integrator;
      }
      lowest = std::min(lowest, values[2]);
      ++particles;
    }
    EXPECT_EQ(particles, 37) << integrator;
    EXPECT_LT(lowest, -0.01) << integrator << ": the disc did not sag";
  }
}

// The geometric multigrid coarsens a grid: on a mesh it is refused in one line naming the option.
TEST_F(Clothlab, ImplicitEulersMultigridRefusesAMeshInOneLine) {
  const Outcome outcome =
      run("--integrator=implicit_euler --set integrator.multigrid=1 " + mesh_scene + "--steps 10");
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_EQ(outcome.err,
            "clothlab: error: integrator implicit_euler prepare failed (unsupported): "
            "multigrid = 1 needs a cloth laid out as a grid (clothlab.grid/1); this scene is not "
            "one\n");
}

// A mesh's frames hold its 37 vertices and 54 triangles in every format, and `clothlab view`
// bundles them.
TEST_F(Clothlab, FramesOfAMeshHoldItsVerticesAndTriangles) {
  const Outcome outcome = run("--integrator=euler " + mesh_scene +
                              "--dt 0.001 --steps 10 --frames frames --set frames.every=5 "
                              "--set 'frames.format=[vtp, obj, pc2]' --quiet");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const nlohmann::json run_json = nlohmann::json::parse(read_text(file("frames/run.json")));
  EXPECT_EQ(run_json["vertices"], 37);
  EXPECT_FALSE(run_json.contains("rows"));

  std::vector<uint32_t> triangles;
  const clothlab::io::Frame last =
      clothlab::io::read_vtp(file("frames/frame_000002.vtp"), &triangles);
  EXPECT_EQ(last.positions.size(), 3u * 37);
  EXPECT_EQ(last.stretch.size(), 37u);
  EXPECT_GT(*std::max_element(last.stretch.begin(), last.stretch.end()), 0.0f);
  ASSERT_EQ(triangles.size(), 3u * 54);

  // The OBJ's faces are the same triangles, 1-based; its vertices the .vtp's points.
  std::ifstream obj(file("frames/frame_000002.obj"));
  std::vector<uint32_t> faces;
  int vertices = 0;
  for (std::string line; std::getline(obj, line);) {
    std::istringstream words(line);
    std::string kind;
    words >> kind;
    if (kind == "v") ++vertices;
    for (uint32_t index = 0; kind == "f" && words >> index;) faces.push_back(index - 1);
  }
  EXPECT_EQ(vertices, 37);
  const auto sorted_triangles = [](std::vector<uint32_t> list) {
    std::vector<std::array<uint32_t, 3>> sorted;
    for (std::size_t t = 0; t + 2 < list.size(); t += 3) {
      std::array<uint32_t, 3> triangle{list[t], list[t + 1], list[t + 2]};
      std::rotate(triangle.begin(), std::min_element(triangle.begin(), triangle.end()),
                  triangle.end());
      sorted.push_back(triangle);
    }
    std::sort(sorted.begin(), sorted.end());
    return sorted;
  };
  EXPECT_EQ(sorted_triangles(faces), sorted_triangles(triangles));

  // PC2: 37 points, 3 samples (steps 0, 5, 10), the last one the last frame's positions.
  std::ifstream pc2(file("frames/frames.pc2"), std::ios::binary);
  std::array<char, 32> header{};
  pc2.read(header.data(), header.size());
  int32_t points = 0, samples = 0;
  std::memcpy(&points, header.data() + 16, 4);
  std::memcpy(&samples, header.data() + 28, 4);
  EXPECT_EQ(points, 37);
  EXPECT_EQ(samples, 3);
  std::vector<float> last_sample(3 * 37);
  pc2.seekg(32 + 2 * 3 * 37 * sizeof(float));
  pc2.read(reinterpret_cast<char*>(last_sample.data()),
           static_cast<std::streamsize>(last_sample.size() * sizeof(float)));
  EXPECT_EQ(last_sample, last.positions);

  const Outcome view = run("view frames --out bundle");
  ASSERT_EQ(view.exit_code, 0) << view.err;
  EXPECT_NE(read_text(file("bundle/runs.js")).find("\"vertices\":37"), std::string::npos);
}

// The viewer checks the frames against run.json's vertex count.
TEST_F(Clothlab, ViewRefusesFramesThatDoNotMatchRunJsonsVertexCount) {
  ASSERT_EQ(run("--integrator=euler " + mesh_scene + "--steps 2 --frames frames --quiet").exit_code,
            0);
  nlohmann::json run_json = nlohmann::json::parse(read_text(file("frames/run.json")));
  run_json["vertices"] = 36;
  std::ofstream(file("frames/run.json")) << run_json.dump();
  const Outcome view = run("view frames --out bundle");
  EXPECT_EQ(view.exit_code, 1);
  EXPECT_NE(view.err.find("frame_000000.vtp: 37 points, run.json's mesh 36"), std::string::npos)
      << view.err;
}

TEST_F(Clothlab, ABadMeshIsOneLineBeforeTheRun) {
  const std::pair<std::string, std::string> cases[] = {
      {"--set scenario.fault=1",
       "scenario test-mesh described an invalid scene: mesh: triangle 1: vertex index 37 out of "
       "range (37 vertices)"},
      {"--set scenario.fault=2",
       "scenario test-mesh described an invalid scene: scene.pinned = 37: allowed indices < the "
       "mesh's vertex count = 37"},
  };
  for (const auto& [settings, message] : cases) {
    const Outcome outcome = run("--integrator=euler " + mesh_scene + settings + " --steps 10");
    EXPECT_EQ(outcome.exit_code, 2) << settings;
    EXPECT_EQ(outcome.err, "clothlab: error: " + message + "\n") << settings;
  }
}

TEST_F(Clothlab, MalformedCollidersAndPosesAreOneLineOfBadInputBeforeTheRun) {
  const std::pair<std::string, std::string> cases[] = {
      {"--set scenario.shape=1 --set scenario.radius=-0.5",
       "scenario test-collider: collider 0: radius = -0.5, allowed finite > 0"},
      {"--set scenario.shape=2 --set scenario.half_length=0",
       "scenario test-collider: collider 0: half_length = 0, allowed finite > 0"},
      {"--set scenario.friction=-0.1",
       "scenario test-collider: collider 0: friction = -0.10000000000000001, allowed finite >= 0"},
      {"--set scenario.broken_pose_after=0.5",
       "scenario test-collider: collider 0 (plane): pose at t = 0.5 s: position.x = nan, allowed "
       "finite"},
      {"--set scenario.jump_after=0.5",
       "scenario test-collider: collider 0 (plane): pose from t = 0.499 s to 0.5 s: position "
       "moved 2 m in 0.001 s (2000 m/s), allowed <= 100 m/s"},
  };
  for (const auto& [settings, message] : cases) {
    const Outcome outcome = run("--integrator=euler " + collider_scene + settings +
                                " --dt 0.001 --steps 1000 --json o.json");
    EXPECT_EQ(outcome.exit_code, 1) << settings;
    EXPECT_EQ(outcome.err, "clothlab: error: " + message + "\n") << settings;
    EXPECT_TRUE(outputs().empty()) << settings;
  }
}

// A 24 x 24 cloth dropped on the sphere and on the table settles over it: nothing ends inside
// the support or sank deeper than the thickness over the run, and its shadow is less than the
// flat cloth's but more than the support's own (the sphere's pi 0.3^2, the table's 0.6^2).
TEST_F(Clothlab, DrapeSettlesOverASphereAndATableAndReportsItsDrapeCoefficient) {
  const std::pair<const char*, double> supports[] = {{"0", 0.283}, {"1", 0.36}};
  for (const auto& [support, support_shadow] : supports) {
    const Outcome outcome =
        run(std::string("--integrator=xpbd --scenario=drape --set scenario.rows=24 "
                        "--set scenario.cols=24 --set scenario.support=") +
            support + " --dt 0.01 --duration 3 --json drape.json --quiet");
    ASSERT_EQ(outcome.exit_code, 0) << support << ": " << outcome.err;
    const auto json = nlohmann::json::parse(read_text(file("drape.json")));
    EXPECT_EQ(json["stable"], true) << support;
    const auto& contacts = json["contacts"];
    EXPECT_EQ(contacts["colliders"], 1) << support;
    EXPECT_EQ(contacts["particles_inside_at_end"], 0) << support;
    EXPECT_LT(contacts["max_penetration_over_run"].get<double>(), 0.005) << support;
    EXPECT_LE(contacts["max_depth_past_thickness_over_run"].get<double>(), 1e-6) << support;
    EXPECT_EQ(contacts["crossings_over_run"], 0) << support;
    const double coefficient = contacts["drape_coefficient"].get<double>();
    EXPECT_LT(coefficient, 0.95) << support;
    EXPECT_GT(coefficient, support_shadow) << support;
  }
}

// The drape's blade, 2 mm thick, rising at 95 m/s (given through clothlab.colliders/2) into the
// resting cotton 2 cm above it, 9.5 cm per 1 ms step: it carries the cloth, none of which crosses
// it or ends inside it, and the contacts' work is the energy the cloth gained (a balance: summing
// only what each contact added gave 888 J for 678). bdf2 restarts the particles a contact moved;
// with its history from before the push it overshot, and the run was called diverged.
TEST_F(Clothlab, ABladeRisingAt95MetresPerSecondCarriesTheClothWithNoneCrossingIt) {
  for (const char* integrator : {"xpbd", "implicit_euler", "bdf2"}) {
    const Outcome outcome =
        run("--config " + (source_dir / "configs/materials/cotton.yaml").string() +
            " --integrator=" + integrator +
            " --scenario=drape --set scenario.rows=24 --set scenario.cols=24 "
            "--set scenario.anchored=false --set scenario.support=2 --set scenario.support.size=1 "
            "--set scenario.thickness=0.002 --set scenario.drop=0.02 "
            "--set scenario.support.velocity=0,95,0 --dt 0.001 --duration 0.01 --json blade.json "
            "--energy-out blade.csv --quiet");
    ASSERT_EQ(outcome.exit_code, 0) << integrator << ": " << outcome.err;
    const auto json = nlohmann::json::parse(read_text(file("blade.json")));
    EXPECT_EQ(json["stable"], true) << integrator;
    const auto& contacts = json["contacts"];
    EXPECT_EQ(contacts["crossings_over_run"], 0) << integrator;
    EXPECT_EQ(contacts["particles_inside_at_end"], 0) << integrator;
    EXPECT_LE(contacts["max_depth_past_thickness_over_run"].get<double>(), 1e-6) << integrator;
    // The energy file's last column is the total: the run's last row less its first.
    std::stringstream rows(read_text(file("blade.csv")));
    std::vector<double> totals;
    std::string line;
    std::getline(rows, line);  // the header
    while (std::getline(rows, line)) totals.push_back(std::stod(line.substr(line.rfind(',') + 1)));
    ASSERT_GE(totals.size(), 2u) << integrator;
    const double gained = totals.back() - totals.front();
    EXPECT_NEAR(contacts["work"].get<double>(), gained, 0.005 * gained) << integrator;
  }
}

// The test scenario's particle 0 goes round a circle of radius 0.1 m at 3 rad/s from the origin:
// every built-in leaves it exactly on the circle (up to the float32 rounding of the target) after
// each of the first steps, while the cloth hangs from it.
const std::string attachment_scene =
    "--scenario=" + (test_plugins / "attachments" / "clothlab_test_attachment.so").string() + " ";

TEST_F(Clothlab, EveryBuiltInLeavesAnAttachedParticleOnItsPathAfterEachStep) {
  const double dt = 0.004;
  for (const char* integrator : {"euler", "midpoint", "rk4", "verlet", "implicit_euler", "bdf2",
                                 "projective_dynamics", "xpbd", "vbd"}) {
    for (const int steps : {1, 2, 3, 10, 25}) {
      const Outcome outcome = run(std::string("--integrator=") + integrator + " " +
                                  attachment_scene + "--dt " + std::to_string(dt) + " --steps " +
                                  std::to_string(steps) + " --state-out state.csv --quiet");
      ASSERT_EQ(outcome.exit_code, 0) << integrator << ": " << outcome.err;
      std::ifstream csv(file("state.csv"));
      std::string line;
      std::getline(csv, line);
      std::getline(csv, line);  // row 0, col 0: particle 0
      std::stringstream fields(line);
      std::string field;
      std::array<double, 8> values{};
      for (double& value : values) {
        std::getline(fields, field, ',');
        value = std::stod(field);
      }
      const double angle = 3.0 * steps * dt;
      const std::array<double, 6> expected = {
          0.1 * (std::cos(angle) - 1.0), 0.1 * std::sin(angle), 0.0,
          -0.3 * std::sin(angle),        0.3 * std::cos(angle), 0.0};
      for (int k = 0; k < 6; ++k)
        EXPECT_NEAR(values[2 + k], expected[k], 1e-7)
            << integrator << " after " << steps << " steps, coordinate " << k;
    }
  }
}

// The test scenario's particle driven round its circle at 5 m/s (50 rad/s) for 0.2 s at a step
// where the methods agree on the motion: the work the attachment did is the same for an
// explicit, a constraint and an implicit method (the sampled springs gave xpbd 9 % more than
// rk4), and xpbd_tethers, whose tethers pull on the attached particle inside the plugin, runs
// stable (it was called diverged after one step).
TEST_F(Clothlab, AnOrbitingAttachmentDoesTheSameWorkWithEveryKindOfMethod) {
  const auto orbit = [&](const std::string& integrator) {
    const Outcome outcome =
        run("--integrator=" + integrator + " " + attachment_scene +
            "--set scenario.omega=50 --dt 0.0001 --duration 0.2 --json orbit.json --quiet");
    EXPECT_EQ(outcome.exit_code, 0) << integrator << ": " << outcome.err;
    return nlohmann::json::parse(read_text(file("orbit.json")));
  };
  const double explicit_work = orbit("rk4")["attachments"]["work"].get<double>();
  EXPECT_GT(explicit_work, 0.1);  // the cloth starts at rest and ends swinging round
  for (const char* integrator : {"xpbd", "implicit_euler"}) {
    const auto json = orbit(integrator);
    EXPECT_EQ(json["stable"], true) << integrator << ": " << json["verdict"];
    EXPECT_NEAR(json["attachments"]["work"].get<double>(), explicit_work, 0.03 * explicit_work)
        << integrator;
  }
  const auto tethers = orbit("xpbd_tethers");
  EXPECT_EQ(tethers["stable"], true) << tethers["verdict"];
}

// On cotton at 1 ms the orbit's first step carries the attached corner 5 mm. The implicit methods
// solve with the attachments where the step ends (their Jacobian products ignore pinned entries,
// so a pin moved after the solve jumps against springs the solve never loaded): both run stable,
// and the attachment's work stays within the energy the cloth gained plus what the methods damp.
// With the pins moved after the solve, implicit_euler was called diverged at t = 0.01 s.
TEST_F(Clothlab, TheImplicitMethodsSolveWithTheAttachmentsWhereTheStepEnds) {
  for (const char* integrator : {"implicit_euler", "bdf2"}) {
    const Outcome outcome =
        run("--config " + (source_dir / "configs/materials/cotton.yaml").string() +
            " --integrator=" + integrator + " " + attachment_scene +
            "--set scenario.omega=50 --dt 0.001 --duration 0.2 --json stiff.json --quiet");
    EXPECT_EQ(outcome.exit_code, 0) << integrator << ": " << outcome.err;
    const auto json = nlohmann::json::parse(read_text(file("stiff.json")));
    EXPECT_EQ(json["stable"], true) << integrator << ": " << json["verdict"];
  }
}

// Verlet's drag towards world rest takes momentum no pin gave: it declares
// CLOTHLAB_TRAIT_DRAGS_TOWARDS_REST, and the monitor samples the pull from the springs instead
// of taking the drag's impulse for the attachment's (which called this run diverged).
TEST_F(Clothlab, VerletsDragTowardsRestIsNotTakenForAnAttachmentsPull) {
  const Outcome outcome =
      run("--integrator=verlet --set integrator.damping=100 " + attachment_scene +
          "--set scenario.omega=50 --dt 0.001 --duration 2 --json drag.json --quiet");
  EXPECT_EQ(outcome.exit_code, 0) << outcome.err;
  const auto json = nlohmann::json::parse(read_text(file("drag.json")));
  EXPECT_EQ(json["stable"], true) << json["verdict"];
}

// The pump scales the free particles' velocity relative to the attached one: the momentum it
// makes looks like the attachment's pull, the energy it adds is more than that pull's work.
TEST_F(Clothlab, AnIntegratorPumpingEnergyAtAnAttachmentIsCalledDiverged) {
  const Outcome outcome =
      run("--integrator=" + (test_plugins / "pump" / "clothlab_test_pumps_energy.so").string() +
          " --set integrator.relative=true --set integrator.gain=0.001 " + attachment_scene +
          "--set scenario.omega=50 --dt 0.0001 --duration 0.2 --json pump.json --quiet");
  EXPECT_EQ(outcome.exit_code, 3) << outcome.err;
  const auto json = nlohmann::json::parse(read_text(file("pump.json")));
  EXPECT_EQ(json["stable"], false);
  EXPECT_EQ(json["failed_check"], "energy") << json["verdict"];
  EXPECT_NE(json["verdict"].get<std::string>().find("attachment work"), std::string::npos)
      << json["verdict"];
}

TEST_F(Clothlab, AnAttachmentOutOfRangeNonFiniteOrJumpingIsOneLineOfBadInputBeforeTheRun) {
  const std::pair<std::string, std::string> cases[] = {
      {"--set scenario.particle=9",
       "scenario test-attachment: attachment 0: particle = 9, allowed 0 .. 8 (the cloth's "
       "particles)"},
      {"--set scenario.broken_after=0.5",
       "scenario test-attachment: attachment 0 (particle 0): target at t = 0.5 s: position.y = "
       "nan, allowed finite"},
  };
  for (const auto& [settings, message] : cases) {
    const Outcome outcome = run("--integrator=euler " + attachment_scene + settings +
                                " --dt 0.002 --steps 1000 --json o.json");
    EXPECT_EQ(outcome.exit_code, 1) << settings;
    EXPECT_EQ(outcome.err, "clothlab: error: " + message + "\n") << settings;
    EXPECT_TRUE(outputs().empty()) << settings;
  }

  // The jump and its bound are computed in floating point; their last digits depend on how the
  // compiler contracts the arithmetic, so they are compared as numbers.
  const Outcome jump = run("--integrator=euler " + attachment_scene +
                           "--set scenario.jump_at=0.25 --dt 0.002 --steps 1000 --json o.json");
  EXPECT_EQ(jump.exit_code, 1);
  const std::regex jump_message(
      "clothlab: error: scenario test-attachment: attachment 0 \\(particle 0\\): target jumps "
      "([0-9.e-]+) m between t = 0\\.248 and 0\\.25 s, allowed a continuous path \\(at most "
      "([0-9.e-]+) m: twice the step times its velocity there\\)\n");
  std::smatch numbers;
  ASSERT_TRUE(std::regex_match(jump.err, numbers, jump_message)) << jump.err;
  EXPECT_NEAR(std::stod(numbers[1]), 0.9995924331779968, 1e-12);
  EXPECT_NEAR(std::stod(numbers[2]), 0.001200001, 1e-12);
  EXPECT_TRUE(outputs().empty());
}

TEST_F(Clothlab, AnIntegratorThatDoesNotMoveAttachmentsIsRefusedOnAnAttachmentScene) {
  const Outcome outcome =
      run("--integrator=" + (test_plugins / "good" / "clothlab_test_good.so").string() + " " +
          attachment_scene + "--steps 10 --json o.json");
  EXPECT_EQ(outcome.exit_code, 1);
  EXPECT_EQ(outcome.err,
            "clothlab: error: integrator test-drift does not move attachments (no "
            "CLOTHLAB_TRAIT_MOVES_ATTACHMENTS in clothlab.integrator-traits/1), which scenario "
            "test-attachment's 1 attached particle(s) need\n");
  EXPECT_TRUE(outputs().empty());
}

// A small cape over the script's whole loop (walk, turn, run at 5 m/s, stop, rest: 8 s): every
// built-in that moves attachments and resolves contacts keeps it stable, with no particle left
// inside the body; the work its shoulders did is reported.
const std::string small_cape = "--scenario=cape --set scenario.rows=12 --set scenario.cols=8 ";

TEST_F(Clothlab, TheCapeRunsStableOverItsLoopForEveryBuiltInThatSupportsIt) {
  for (const char* integrator :
       {"euler", "midpoint", "rk4", "implicit_euler", "projective_dynamics", "xpbd"}) {
    const std::string dt = std::string(integrator) == "xpbd" ? "0.01" : "0.002";
    const Outcome outcome = run(std::string("--integrator=") + integrator + " " + small_cape +
                                "--dt " + dt + " --duration 8 --json cape.json --quiet");
    ASSERT_EQ(outcome.exit_code, 0) << integrator << ": " << outcome.err;
    const auto json = nlohmann::json::parse(read_text(file("cape.json")));
    EXPECT_EQ(json["stable"], true) << integrator << ": " << json["verdict"];
    EXPECT_EQ(json["contacts"]["colliders"], 4) << integrator;
    EXPECT_EQ(json["contacts"]["particles_inside_at_end"], 0) << integrator;
    EXPECT_EQ(json["attachments"]["particles"], 8) << integrator;
    EXPECT_TRUE(json["attachments"]["work"].is_number()) << integrator;
  }
}

// Without air: the air's drag grows with the square of the speed and caps what a pump injects
// (the cloth reaches a terminal speed), which no energy criterion can tell from a breeze.
TEST_F(Clothlab, AnEnergyInjectingIntegratorOnTheCapeIsStillCalledDiverged) {
  const Outcome outcome = run(
      "--integrator=" + (test_plugins / "pump" / "clothlab_test_pumps_energy.so").string() + " " +
      small_cape + "--set scenario.air.density=0 --dt 0.002 --duration 8 --json cape.json --quiet");
  EXPECT_EQ(outcome.exit_code, 3) << outcome.err;
  const auto json = nlohmann::json::parse(read_text(file("cape.json")));
  EXPECT_EQ(json["stable"], false);
  EXPECT_EQ(json["failed_check"], "energy") << json["verdict"];
}

TEST_F(Clothlab, TheCapesBodyAndScriptRefuseValuesOutOfRangeBeforeTheRun) {
  const std::pair<std::string, std::string> cases[] = {
      {"torso.radius=0", "scenario.torso.radius = 0: out of range; allowed: real in [0.01, 1] m"},
      {"arms.length=0", "scenario.arms.length = 0: out of range; allowed: real in [0.01, 2] m"},
      {"friction=-0.1", "scenario.friction = -0.1: out of range; allowed: real in [0, 10]"},
      {"turn.duration=0",
       "scenario.turn.duration = 0: out of range; allowed: real in [0.01, 100] s"},
  };
  for (const auto& [setting, message] : cases) {
    const Outcome outcome =
        run("--integrator=xpbd --scenario=cape --set scenario." + setting + " --steps 3");
    EXPECT_EQ(outcome.exit_code, 1) << setting;
    EXPECT_EQ(outcome.err, "clothlab: error: --set: " + message + "\n") << setting;
  }
}

TEST_F(Clothlab, ScenesWithoutCollidersReportNoContacts) {
  const Outcome outcome =
      run(std::string("--integrator=rk4 ") + small_sheet + "--steps 5 --quiet --json sheet.json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  EXPECT_TRUE(nlohmann::json::parse(read_text(file("sheet.json")))["contacts"].is_null());
}

TEST_F(Clothlab, ConfigErrorExitsOneWithItsPosition) {
  std::ofstream(file("bad.yaml")) << "integrator: rk4\nscenario:\n  plugin: sheet\n  rows: many\n";
  const Outcome outcome = run("--config bad.yaml");
  EXPECT_EQ(outcome.exit_code, 1);
  EXPECT_EQ(outcome.err,
            "clothlab: error: bad.yaml:4:9: scenario.rows = many: not a whole number; allowed: int "
            "in [1, 4096]\n");
}

// Errors found after parsing (loading a plugin, a name the file system cannot hold) are reported
// at the file:line:col of the key that caused them, in one line.
TEST_F(Clothlab, ErrorsFoundAfterParsingNameTheKeyThatCausedThem) {
  const std::string long_name(300, 'x');
  const struct {
    const char* name;
    std::string yaml, arguments;
    int exit_code;
    std::string starts;
  } cases[] = {
      {"missing plugin", "integrator: nosuch\n", "--steps 1", 2,
       "bad.yaml:1:13: integrator = nosuch: plugin nosuch: no nosuch.so in the plugin search path"},
      {"no scenario in it", "integrator: euler\nscenario: euler\n", "--steps 1", 2,
       "bad.yaml:2:11: scenario = euler: plugin "},
      {"a device", "integrator: /dev/null\n", "--steps 1", 2,
       "bad.yaml:1:13: integrator = /dev/null: plugin file /dev/null is a device or special file, "
       "not a shared library"},
      {"a folder", "scenario: /tmp\n", "--steps 1", 2,
       "bad.yaml:1:11: scenario = /tmp: plugin file /tmp is a folder, not a shared library"},
      {"a long frames name", "frames:\n  dir: out/" + long_name + "\n", "--steps 1", 1,
       "bad.yaml:2:8: frames.dir: the name xxxxxxxxxxxxxxxxxxxxxxxx... is 300 bytes long; "
       "allowed: names of at most 255 bytes"},
      {"a long choose output", "choose:\n  output: results/" + long_name.substr(0, 250) + "\n",
       "--choose --frame-rate 60", 1,
       "bad.yaml:2:11: choose.output: the name xxxxxxxxxxxxxxxxxxxxxxxx... is 250 bytes long; "
       "allowed: names of at most 255 bytes, the last at most 239"},
      {"choose's reference is a scenario", "choose:\n  reference_integrator: sheet\n",
       "--choose --frame-rate 60 --set choose.integrators=[euler]", 2,
       "bad.yaml:2:25: choose.reference_integrator: integrator = sheet: plugin "},
      {"choose names no integrator", "choose:\n  integrators: [euler, sheet]\n",
       "--choose --frame-rate 60", 1,
       "bad.yaml:2:16: choose.integrators: sheet is not an integrator on the plugin path"},
      {"work-precision's reference is a scenario",
       "duration: 0.1\nwork_precision:\n  reference_integrator: sheet\nsweep:\n  name: wp\n"
       "  mode: work-precision\n  matrix:\n    integrator: [euler]\n",
       "", 2, "bad.yaml:3:25: work_precision.reference_integrator: integrator = sheet: plugin "},
  };
  for (const auto& c : cases) {
    std::ofstream(file("bad.yaml")) << c.yaml;
    const Outcome outcome = run("--config bad.yaml " + c.arguments);
    EXPECT_EQ(outcome.exit_code, c.exit_code) << c.name << ": " << outcome.err;
    EXPECT_EQ(outcome.err.rfind("clothlab: error: " + c.starts, 0), 0u)
        << c.name << ": " << outcome.err;
    EXPECT_EQ(std::count(outcome.err.begin(), outcome.err.end(), '\n'), 1) << c.name;
  }
}

TEST_F(Clothlab, ShippedConfigsAreAccepted) {
  // Real cloth needs small steps: the frame-rate configs get 200 substeps, the bare material
  // files 0.1 ms steps (6 x 6 cotton's explicit limit is ~1 ms).
  const std::pair<const char*, const char*> configs[] = {
      {"default.yaml", ""},
      {"seed-2016.yaml", ""},
      {"bench-300-soft.yaml", ""},
      {"bench-300.yaml", "--substeps 200"},
      {"choose-cotton-flag-200.yaml", "--substeps 200"},
      {"materials/cotton.yaml", "--dt 0.0001"},
      {"materials/silk.yaml", "--dt 0.0001"},
      {"materials/denim.yaml", "--dt 0.0001"},
      {"materials/seed-2016.yaml", "--dt 0.0001"}};
  for (const auto& [config, extra] : configs) {
    const Outcome outcome =
        run("--config " + (source_dir / "configs" / config).string() +
            " --set scenario.rows=6 --set scenario.cols=6 --steps 2 --quiet " + extra);
    EXPECT_EQ(outcome.exit_code, 0) << config << ": " << outcome.err;
  }
}

// yaml-cpp reads a ',' outside a [list] or {map} as an empty document without consuming it,
// so reading a file's documents to the end never ended. These one- and two-character
// documents (and a ',' after a document) are each one line of bad input naming the file.
TEST_F(Clothlab, ShortMalformedConfigsAreOneLineOfBadInputNamingTheFile) {
  for (const char* text :
       {",",  ",\n", ",,", ",\n,", "[1],", "{a: 1},", "a: 1\n...\n,", "---\n,", "[",
        "{",  "]",   "}",  ":",    "?",    "-",       "&a",           "*a",     "!",
        "!!", "&",   "*",  "|",    ">",    "~",       "---",          "@"}) {
    std::ofstream(file("bad.yaml")) << text;
    const Outcome outcome = run("--config bad.yaml --steps 1 --quiet", "", 5);
    EXPECT_EQ(outcome.exit_code, 1) << "'" << text << "': " << outcome.err;
    EXPECT_EQ(outcome.err.rfind("clothlab: error: bad.yaml:", 0), 0u)
        << "'" << text << "': " << outcome.err;
    EXPECT_EQ(std::count(outcome.err.begin(), outcome.err.end(), '\n'), 1)
        << "'" << text << "': " << outcome.err;
  }
}

TEST_F(Clothlab, PluginParamsApplyOnlyToTheirPlugin) {
  const std::string seed = "--config " + (source_dir / "configs/seed-2016.yaml").string() +
                           " --set scenario.rows=6 --set scenario.cols=6 --steps 2 --quiet ";
  const Outcome verlet = run(seed + "--json verlet.json");
  ASSERT_EQ(verlet.exit_code, 0) << verlet.err;
  const auto json = nlohmann::json::parse(read_text(file("verlet.json")));
  EXPECT_EQ(json["integrator"], "verlet");
  EXPECT_EQ(json["integrator_params"]["damping_per_step"], 0.005);
  // rk4 has no damping_per_step: the verlet block is not applied to it.
  const Outcome rk4 = run(seed + "--integrator=rk4 --json rk4.json");
  EXPECT_NE(rk4.exit_code, 1) << rk4.err;
  EXPECT_EQ(nlohmann::json::parse(read_text(file("rk4.json")))["integrator_params"],
            nlohmann::json::object());
}

TEST_F(Clothlab, ListPluginsShowsComponentsAndParameters) {
  const Outcome outcome = run("--list-plugins");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  for (const char* text : {"integrator rk4", "order 4", "integrator bdf2", "order 2",
                           "scenario flag", "scenario.structural.ks", "scenario.wind.strength"})
    EXPECT_NE(outcome.out.find(text), std::string::npos) << text;
}

TEST_F(Clothlab, ListPluginsShowsTraitsAndExtensions) {
  const Outcome outcome = run("--list-plugins");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const std::size_t implicit = outcome.out.find("integrator implicit_euler");
  ASSERT_NE(implicit, std::string::npos) << outcome.out;
  const std::string block =
      outcome.out.substr(implicit, outcome.out.find("parameters", implicit) - implicit);
  for (const char* text : {"traits: ", "resolves-contacts", "moves-attachments",
                           "extensions: clothlab.integrator-traits/1"})
    EXPECT_NE(block.find(text), std::string::npos) << text << " in\n" << block;
}

// The JSON form is the same listing (plugin_listing builds it once), schema in
// docs/reference/plugin-listing.md.
TEST_F(Clothlab, ListPluginsAsJsonForTools) {
  const Outcome outcome = run("--list-plugins --json -");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const nlohmann::json listing = nlohmann::json::parse(outcome.out);
  EXPECT_EQ(listing["schema_version"], 1);
  EXPECT_TRUE(listing["errors"].empty());
  const nlohmann::json* implicit = nullptr;
  const nlohmann::json* flag = nullptr;
  for (const nlohmann::json& library : listing["libraries"]) {
    for (const nlohmann::json& integrator : library["integrators"])
      if (integrator["id"] == "implicit_euler") implicit = &integrator;
    for (const nlohmann::json& scenario : library["scenarios"])
      if (scenario["id"] == "flag") flag = &scenario;
  }
  ASSERT_NE(implicit, nullptr) << outcome.out;
  ASSERT_NE(flag, nullptr) << outcome.out;
  const auto& traits = (*implicit)["traits"];
  EXPECT_NE(std::find(traits.begin(), traits.end(), "resolves-contacts"), traits.end()) << traits;
  EXPECT_EQ((*implicit)["order"], 1);
  bool wind = false;
  for (const nlohmann::json& parameter : (*flag)["parameters"])
    wind = wind || parameter["key"] == "scenario.wind.strength";
  EXPECT_TRUE(wind) << (*flag)["parameters"];

  const Outcome to_file = run("--list-plugins --json listing.json");
  ASSERT_EQ(to_file.exit_code, 0) << to_file.err;
  EXPECT_EQ(nlohmann::json::parse(read_text(file("listing.json"))), listing);
}

TEST_F(Clothlab, ListPluginsReportsIdsInTwoLibraries) {
  const Outcome outcome = run("--list-plugins --plugin-path " + (test_plugins / "good").string() +
                              ":" + (test_plugins / "copy").string());
  EXPECT_EQ(outcome.exit_code, 2);
  EXPECT_NE(outcome.err.find("clothlab: error: duplicate plugin id test-drift"), std::string::npos)
      << outcome.err;
}

TEST_F(Clothlab, UnknownOptionExitsOne) {
  const Outcome outcome = run("--integrater=rk4");
  EXPECT_EQ(outcome.exit_code, 1);
  EXPECT_EQ(outcome.err.rfind("clothlab: error: command line: ", 0), 0u) << outcome.err;
}

// --dry-run: everything a run checks before its first step, then no step and no output.
TEST_F(Clothlab, DryRunChecksASingleRunAndWritesNothing) {
  const Outcome outcome =
      run("--integrator=rk4 --scenario=flag --set scenario.rows=8 --set scenario.cols=8 "
          "--json out.json --state-out state.csv --frames frames --dry-run");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  EXPECT_NE(outcome.out.find("dry run: rk4 on flag, 8x8 particles"), std::string::npos)
      << outcome.out;
  EXPECT_TRUE(outputs().empty());
}

// What only creating the scene and the integrator finds is found: the drape's collider needs an
// integrator that resolves contacts, which verlet does not.
TEST_F(Clothlab, DryRunRefusesWhatTheRunWouldRefuse) {
  const Outcome unknown =
      run("--integrator=rk4 --scenario=flag --set integrator.bogus=1 --dry-run");
  EXPECT_EQ(unknown.exit_code, 1) << unknown.err;
  const Outcome contacts = run("--integrator=verlet --scenario=drape --dry-run");
  EXPECT_EQ(contacts.exit_code, 1) << contacts.err;
  EXPECT_NE(contacts.err.find("does not resolve contacts"), std::string::npos) << contacts.err;
  const Outcome frames = run("--integrator=rk4 --scenario=flag --frames stdout.txt/f --dry-run");
  EXPECT_EQ(frames.exit_code, 1) << frames.err;
  EXPECT_NE(frames.err.find("--frames stdout.txt/f"), std::string::npos) << frames.err;
}

TEST_F(Clothlab, DryRunOfASweepChecksEveryCaseAndRunsNone) {
  std::ofstream(file("sweep.yaml")) << "steps: 5\n"
                                       "scenario: {plugin: sheet, rows: 4, cols: 4}\n"
                                       "sweep:\n"
                                       "  name: dry\n"
                                       "  output: out/dry\n"
                                       "  matrix: {integrator: [euler, rk4], dt: [0.001, 0.002]}\n";
  const Outcome outcome = run("--config sweep.yaml --dry-run");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  EXPECT_NE(outcome.out.find("dry run: sweep dry (run): 4 cases checked"), std::string::npos)
      << outcome.out;
  EXPECT_EQ(outputs(), std::vector<std::string>{"sweep.yaml"});
  const Outcome bad = run("--config sweep.yaml --set integrator.bogus=1 --dry-run");
  EXPECT_EQ(bad.exit_code, 1) << bad.err;
}

TEST_F(Clothlab, DryRunOfChooseChecksTheSceneAndRunsNoProbe) {
  const std::string scene =
      "--choose --scenario=flag --set scenario.rows=6 --set scenario.cols=6 "
      "--set 'choose.integrators=[euler,verlet]' --set choose.output=out/c ";
  const Outcome outcome = run(scene + "--frame-rate 60 --dry-run");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  EXPECT_NE(outcome.out.find("2 candidate(s)"), std::string::npos) << outcome.out;
  EXPECT_TRUE(outputs().empty());
  EXPECT_EQ(run(scene + "--dry-run").exit_code, 1);  // --choose needs a frame rate
}

// The duration was found not to be whole ladder steps only after the results store was opened,
// which left <out>.lock and <out>.sqlite behind (and replaced a store that was there).
TEST_F(Clothlab, WorkPrecisionDurationIsCheckedBeforeTheResultsStoreIsOpened) {
  std::ofstream(file("wp.yaml")) << "integrator: euler\n"
                                    "scenario: {plugin: sheet, rows: 4, cols: 4}\n"
                                    "duration: 0.04\n"
                                    "work_precision: {dt_start: 0.003, levels: 2}\n"
                                    "sweep:\n"
                                    "  name: wp\n"
                                    "  mode: work-precision\n"
                                    "  output: out/wp\n"
                                    "  matrix: {integrator: [euler]}\n";
  const std::string error =
      "clothlab: error: wp.yaml:3:11: duration = 0.04 s is not a whole number of steps of the "
      "work-precision ladder dt (dt_start / 2^0) = 0.003 s; allowed: a duration that every ladder "
      "and reference dt divides (a multiple of work_precision.dt_start = 0.003 s when refinement "
      "is whole)\n";
  const Outcome fresh = run("--config wp.yaml");
  EXPECT_EQ(fresh.exit_code, 1);
  EXPECT_EQ(fresh.err, error);
  EXPECT_FALSE(fs::exists(file("out")));

  fs::create_directories(file("earlier"));
  std::ofstream(file("earlier/wp.sqlite")) << "earlier results";
  const Outcome over_earlier = run("--config wp.yaml --out earlier");
  EXPECT_EQ(over_earlier.exit_code, 1);
  EXPECT_EQ(over_earlier.err, error);
  EXPECT_TRUE(read_text(file("earlier/wp.sqlite")) == "earlier results") << "store replaced";
  EXPECT_FALSE(fs::exists(file("earlier/wp.lock")));
}

// A search or a choice ran its cases with the bad plugin name: --find-max-dt counted every
// probe unstable and exited 0, --choose reported a failed reference without the file.
TEST_F(Clothlab, PluginNamedInAConfigIsCheckedWithItsPositionBeforeASearchOrAChoice) {
  std::ofstream(file("scenario.yaml")) << "scenario:\n  plugin: \"..\"\n";
  std::ofstream(file("integrator.yaml")) << "integrator:\n  plugin: \"..\"\n";
  for (const auto& [config, mode] :
       {std::pair{"scenario", "--find-max-dt"}, std::pair{"integrator", "--find-max-dt"},
        std::pair{"scenario", "--choose --frame-rate 60"}}) {
    const Outcome outcome = run(std::string("--config ") + config + ".yaml " + mode);
    EXPECT_EQ(outcome.exit_code, 2) << mode << ": " << outcome.err;
    const std::string expected =
        std::string("clothlab: error: ") + config + ".yaml:2:11: " + config + " = ..: plugin ..: ";
    EXPECT_EQ(outcome.err.rfind(expected, 0), 0u) << mode << ": " << outcome.err;
    EXPECT_EQ(std::count(outcome.err.begin(), outcome.err.end(), '\n'), 1) << outcome.err;
  }
  EXPECT_FALSE(fs::exists(file("results")));  // choose.output's folder
}

// --choose built its cases from the settings given, so without a scenario setting they had
// none ("empty plugin name") instead of the default scenario.
TEST_F(Clothlab, ChooseRunsTheDefaultScenario) {
  const Outcome outcome =
      run("--choose --frame-rate 60 --set scenario.rows=4 --set scenario.cols=4 --set "
          "choose.output=choose/choose --set choose.duration=0.1 --set choose.integrators=[euler]");
  EXPECT_EQ(outcome.exit_code, 0) << outcome.err;
  EXPECT_NE(outcome.out.find("1    euler"), std::string::npos) << outcome.out;
}

// The ranked file names the scene's mesh, so that tools/plot.py scaling can place a search
// among other meshes' from the file alone; null where the scenario's default size stands.
TEST_F(Clothlab, ChooseRankedFileNamesTheSceneMesh) {
  const std::string common =
      "--choose --frame-rate 60 --set choose.output=choose/choose --set choose.duration=0.05 "
      "--set choose.integrators=[euler] ";
  ASSERT_EQ(run(common + "--set mesh=5x4").exit_code, 0);
  EXPECT_EQ(nlohmann::json::parse(read_text(file("choose/choose-ranked.json")))["settings"]["mesh"],
            "5x4");
  ASSERT_EQ(run(common + "--set scenario.rows=6 --set scenario.cols=3").exit_code, 0);
  EXPECT_EQ(nlohmann::json::parse(read_text(file("choose/choose-ranked.json")))["settings"]["mesh"],
            "6x3");
}

// The ranked file says how a probe whose solver missed its tolerance was judged
// (stability.unconverged), since a fixed CG budget's pass reads the same in the ranking.
TEST_F(Clothlab, ChooseRankedFileNamesHowMissedTolerancesAreJudged) {
  const std::string common =
      "--choose --frame-rate 60 --set choose.output=choose/choose --set choose.duration=0.05 "
      "--set choose.integrators=[euler] --set mesh=4x4 ";
  ASSERT_EQ(run(common).exit_code, 0);
  EXPECT_EQ(nlohmann::json::parse(
                read_text(file("choose/choose-ranked.json")))["settings"]["unconverged"],
            "fail");
  ASSERT_EQ(run(common + "--set stability.unconverged=count").exit_code, 0);
  EXPECT_EQ(nlohmann::json::parse(
                read_text(file("choose/choose-ranked.json")))["settings"]["unconverged"],
            "count");
}

// A local solver (xpbd declares CLOTHLAB_TRAIT_LOCAL_SOLVES) gets the substeps the m / h^2
// bound predicts in its verdict and row; an explicit method does not.
TEST_F(Clothlab, ChoosePredictsALocalSolversSubsteps) {
  const Outcome outcome =
      run("--choose --frame-rate 60 --scenario sheet --set scenario.rows=4 --set scenario.cols=4 "
          "--set choose.output=choose/choose --set choose.duration=0.1 --set "
          "choose.integrators=[xpbd,euler]");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const auto ranked = nlohmann::json::parse(read_text(file("choose/choose-ranked.json")));
  std::map<std::string, nlohmann::json> rows;
  for (const auto& row : ranked["ranking"]) rows[row["integrator"]] = row;
  EXPECT_TRUE(rows.at("euler")["predicted_substeps"].is_null());
  const std::string verdict = rows.at("xpbd")["verdict"];
  EXPECT_NE(verdict.find("the m / h^2 bound predicts"), std::string::npos) << verdict;
  EXPECT_EQ(rows.at("euler")["verdict"].get<std::string>().find("m / h^2"), std::string::npos);
  EXPECT_NE(outcome.err.find("xpbd: the m / h^2 bound predicts"), std::string::npos) << outcome.err;
}

// On the cape (moving attachments and colliders), the integrators that cannot handle them are
// listed as refused with what they lack instead of ending the search (vbd's m / h^2 bound is a
// Simulation of the scene, which refuses it too), and the rows carry the penetration and the
// thickness it is judged against.
TEST_F(Clothlab, ChooseOnTheCapeRefusesWhatCannotHandleItAndJudgesThePenetration) {
  const Outcome outcome =
      run("--choose --frame-rate 60 --scenario cape --set scenario.rows=8 --set scenario.cols=6 "
          "--set choose.output=choose/choose --set choose.duration=0.1 --set "
          "choose.integrators=[verlet,vbd,euler]");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const auto ranked = nlohmann::json::parse(read_text(file("choose/choose-ranked.json")));
  std::map<std::string, nlohmann::json> rows;
  for (const auto& row : ranked["ranking"]) rows[row["integrator"]] = row;
  for (const char* refused : {"verlet", "vbd"}) {
    const std::string verdict = rows.at(refused)["verdict"];
    EXPECT_EQ(verdict.rfind("refused: does not resolve contacts", 0), 0u) << verdict;
    EXPECT_NE(verdict.find("which the scene's 4 collider(s) need"), std::string::npos) << verdict;
  }
  ASSERT_EQ(rows.at("euler")["rank"], 1) << outcome.out;
  EXPECT_EQ(rows.at("euler")["collider_thickness"], 0.01);
  EXPECT_LE(rows.at("euler")["max_penetration"].get<double>(), 0.01);
  EXPECT_NE(outcome.out.find("refused: does not resolve contacts"), std::string::npos)
      << outcome.out;
}

// merge's words after "merge" were all taken for output names, so --help was one.
TEST_F(Clothlab, MergeHelpPrintsItsUsageAndAnUnknownOptionIsOneLine) {
  const Outcome help = run("merge --help");
  EXPECT_EQ(help.exit_code, 0) << help.err;
  EXPECT_EQ(help.out.rfind("Usage: clothlab merge OUTPUT...\n", 0), 0u) << help.out;
  EXPECT_EQ(help.err, "");
  const Outcome unknown = run("merge --foo results/stress");
  EXPECT_EQ(unknown.exit_code, 1);
  EXPECT_EQ(unknown.err,
            "clothlab: error: merge: unrecognised option '--foo'; allowed: --help and OUTPUT "
            "names (see clothlab merge --help)\n");
  const Outcome nothing = run("merge");
  EXPECT_EQ(nothing.exit_code, 1);
  EXPECT_EQ(nothing.err,
            "clothlab: error: merge: no OUTPUT given; allowed: OUTPUT..., e.g. results/stress\n");
  EXPECT_EQ(outputs(), std::vector<std::string>{});
}

}  // namespace

namespace {

// Mean drop below the rest layout (rows at y = 1 - row / (rows - 1)) of a final-state CSV.
double mean_drop(const std::string& csv, int rows) {
  std::istringstream lines(csv);
  std::string line;
  std::getline(lines, line);  // header
  double sum = 0;
  int count = 0;
  while (std::getline(lines, line)) {
    int row = 0, col = 0;
    double x = 0, y = 0;
    std::sscanf(line.c_str(), "%d,%d,%lf,%lf", &row, &col, &x, &y);
    sum += (1.0 - static_cast<double>(row) / (rows - 1)) - y;
    ++count;
  }
  return sum / count;
}

// The cotton preset hanging from the flag's pole (an edge support: the two-corner sheet's point
// pins concentrate its weight in a singular stress whose drop keeps growing ~log N with the mesh),
// no wind, settled by Verlet with strong drag. Only the per-spring values' dependence on the
// spacing changes between the meshes; the material's sag must not.
TEST_F(Clothlab, MaterialSagAgreesAcrossResolutions) {
  double drop[2];
  const int meshes[2] = {20, 40};
  for (int k = 0; k < 2; ++k) {
    const std::string mesh = std::to_string(meshes[k]);
    const Outcome outcome = run(
        "--config '" + (source_dir / "configs/materials/cotton.yaml").string() +
        "' --scenario flag --set scenario.wind.strength=0 --integrator verlet "
        "--set integrator.damping=30 --frame-rate 60 --substeps 400 --duration 0.6 "
        "--set scenario.rows=" +
        mesh + " --set scenario.cols=" + mesh + " --quiet --state-out state.csv --json run.json");
    ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
    drop[k] = mean_drop(read_text(file("state.csv")), meshes[k]);
    const auto json = nlohmann::json::parse(read_text(file("run.json")));
    EXPECT_EQ(json["material"], "cotton");
    EXPECT_LT(json["max_stretch"]["over_run"].get<double>(), 1.05);  // cloth, not rubber
  }
  EXPECT_GT(drop[0], 1e-3);  // it does sag (about 1 cm)
  EXPECT_NEAR(drop[1] / drop[0], 1.0, 0.03) << drop[0] << " m vs " << drop[1] << " m";
}

TEST_F(Clothlab, FramesAndStretchAreReported) {
  const Outcome outcome =
      run(std::string("--integrator=verlet ") + small_sheet +
          "--frame-rate 50 --substeps 10 --duration 0.2 --quiet --json summary.json");
  ASSERT_EQ(outcome.exit_code, 0) << outcome.err;
  const auto json = nlohmann::json::parse(read_text(file("summary.json")));
  EXPECT_DOUBLE_EQ(json["dt"].get<double>(), 0.002);
  EXPECT_EQ(json["steps"], 100);
  EXPECT_EQ(json["substeps"], 10);
  EXPECT_DOUBLE_EQ(json["frame_rate"].get<double>(), 50.0);
  // A frame is ten steps: its median cost is at least five times a step's median.
  EXPECT_GT(json["ms_per_frame"]["median"].get<double>(),
            5 * json["ms_per_step"]["median"].get<double>());
  EXPECT_NEAR(
      json["frames_per_second"].get<double>() * json["ms_per_frame"]["median"].get<double>(),
      1000.0, 1e-6);
  // The soft default cloth hanging from two corners stretches (its corners beyond 1.1x rest).
  EXPECT_GT(json["max_stretch"]["over_run"].get<double>(), 1.1);
  EXPECT_GE(json["max_stretch"]["over_run"].get<double>(),
            json["max_stretch"]["final"].get<double>());
  EXPECT_GT(json["mean_stretch"].get<double>(), 1.0);
  EXPECT_LT(json["mean_stretch"].get<double>(), json["max_stretch"]["final"].get<double>());
  // When and where the largest was seen: a warp or weft spring at a pinned top corner (row 0,
  // column 0 or 4 of the 4x5 sheet), at a check within the run.
  const auto& at = json["max_stretch"]["over_run_at"];
  ASSERT_TRUE(at.is_object()) << json["max_stretch"];
  EXPECT_GT(at["t"].get<double>(), 0.0);
  EXPECT_LE(at["t"].get<double>(), 0.2 + 1e-12);
  EXPECT_EQ(at["row"], 0);
  const int row_step = at["to_row"].get<int>() - at["row"].get<int>();
  const int col_step = at["to_col"].get<int>() - at["col"].get<int>();
  EXPECT_EQ(row_step + std::abs(col_step), 1) << at;
  EXPECT_TRUE(at["col"] == 0 || at["to_col"] == 4 || (at["col"] == 4 && row_step == 1)) << at;
}

TEST_F(Clothlab, MaterialAndPerSpringValuesConflict) {
  const Outcome outcome =
      run("--config '" + (source_dir / "configs/materials/denim.yaml").string() +
          "' --set scenario.structural.ks=50 --steps 1");
  EXPECT_EQ(outcome.exit_code, 1);
  EXPECT_NE(outcome.err.find("--set: scenario.structural.ks = 50 conflicts with the material set "
                             "at "),
            std::string::npos)
      << outcome.err;
}

}  // namespace
