// Whole runs of clothlab-conformance: faulty plugins are caught by the right check and the
// run still completes; sound plugins pass. Results are read from the --json report.
#include <clothlab/plugin.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "../support/sanitizer.hpp"

namespace {

using clothlab::testing::address_sanitizer;

// A plugin that segfaults in a check's child: the child dies of SIGSEGV. In a sanitizer build
// the reason depends on whether the plugin is instrumented too (UBSan then reports the null
// store and the child exits with status 1) or not (CLOTHLAB_SANITIZE=host: signal 11).
constexpr const char* segfault_reason = address_sanitizer ? "crashed: " : "crashed: signal 11";

struct RunnerOutput {
  int exit_code = -1;
  std::string output;
  nlohmann::json report;  // null when no report was written
};

std::string plugin(const std::string& name) {
  return std::string(CONFORMANCE_PLUGIN_DIR) + "/" + name + ".so";
}

// `environment`: assignments put before the command, e.g. "LD_PRELOAD=...".
RunnerOutput run_conformance(const std::string& arguments, const std::string& environment = "") {
  const std::string report_path =
      ::testing::TempDir() + "conformance-" + std::to_string(getpid()) + ".json";
  std::remove(report_path.c_str());
  const std::string command = environment + " " + CONFORMANCE_RUNNER + " --seed 11 --json " +
                              report_path + " " + arguments + " 2>&1";
  RunnerOutput run;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  char buffer[4096];
  while (size_t n = fread(buffer, 1, sizeof buffer, pipe)) run.output.append(buffer, n);
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(report_path);
  if (in) run.report = nlohmann::json::parse(in);
  std::remove(report_path.c_str());
  return run;
}

const nlohmann::json* find_check(const RunnerOutput& run, const std::string& component,
                                 const std::string& check) {
  if (run.report.is_null()) return nullptr;
  for (const nlohmann::json& result : run.report["checks"])
    if (result["component"] == component && result["check"] == check) return &result;
  return nullptr;
}

struct FaultyCase {
  const char* plugin;
  const char* component;
  const char* check;
  const char* reason;               // expected inside the failure reason
  const char* arguments;            // filters keep the runs short
  const char* test_name = nullptr;  // when one plugin is caught by several checks; else plugin
};

class FaultyPlugin : public ::testing::TestWithParam<FaultyCase> {};

TEST_P(FaultyPlugin, IsCaughtByTheRightCheckAndTheRunCompletes) {
  const FaultyCase& c = GetParam();
  const RunnerOutput run = run_conformance(std::string(c.arguments) + " " + plugin(c.plugin));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  ASSERT_FALSE(run.report.is_null()) << "no report written:\n" << run.output;
  const nlohmann::json* result = find_check(run, c.component, c.check);
  ASSERT_NE(result, nullptr) << c.check << " did not run:\n" << run.output;
  EXPECT_EQ((*result)["passed"], false) << run.output;
  EXPECT_NE((*result)["reason"].get<std::string>().find(c.reason), std::string::npos)
      << (*result)["reason"];
  const std::string summary = std::to_string(run.report["passed"].get<int>()) + " passed, " +
                              std::to_string(run.report["failed"].get<int>()) + " failed\n";
  EXPECT_TRUE(run.output.ends_with(summary)) << run.output;
}

INSTANTIATE_TEST_SUITE_P(
    Conformance, FaultyPlugin,
    ::testing::Values(
        FaultyCase{"faulty_lies_about_order", "lies-about-order", "numerics.order-spring",
                   "measured order 1.", "--filter numerics.order"},
        FaultyCase{"faulty_produces_nan", "produces-nan", "lifecycle.grid-3x3-f64", "non-finite",
                   "--filter lifecycle.grid-3x3"},
        FaultyCase{"faulty_moves_pinned", "moves-pinned", "numerics.pinned-f64",
                   "pinned particle 0 moved", "--filter numerics.pinned"},
        FaultyCase{"faulty_moves_pins_off_the_grid", "moves-pins-off-the-grid",
                   "numerics.pinned-f64", "on the irregular mesh: pinned particle 0 moved",
                   "--filter numerics.pinned"},
        FaultyCase{"faulty_segfaults_in_step", "segfaults-in-step", "lifecycle.grid-3x3-f64",
                   segfault_reason, "--filter 'lifecycle|robustness'"},
        FaultyCase{"faulty_hangs_in_step", "hangs-in-step", "lifecycle.grid-3x3-f64",
                   "timed out after 1 s",
                   "--timeout 1 --filter 'lifecycle.grid-3x3-f64|params.defaults'"},
        FaultyCase{"faulty_abi_major_2", "library", "loading.abi-version", "built for ABI 2.0", ""},
        FaultyCase{"faulty_throws_through_boundary", "throws-through-boundary",
                   "robustness.no-throw", "exception escaped the C boundary from step",
                   "--filter robustness"},
        FaultyCase{"faulty_allocates_every_step", "allocates-every-step", "robustness.no-alloc",
                   "heap allocator calls during 10 steps", "--filter robustness"},
        FaultyCase{"faulty_allocates_where_its_contacts_act", "allocates-where-its-contacts-act",
                   "robustness.no-alloc", "heap allocator calls during 10 steps",
                   "--filter robustness.no-alloc"},
        FaultyCase{"faulty_misdeclares_scheme", "misdeclares-scheme", "descriptor.extensions",
                   "takes 2 evaluations per step, the descriptor says evals_per_step = 1",
                   "--filter descriptor"},
        FaultyCase{"faulty_claims_unconditional_stability", "claims-unconditional-stability",
                   "stability.unconditional-sheet", "declares unconditional stability, but",
                   "--filter stability.unconditional"},
        FaultyCase{"faulty_claims_to_resolve_contacts", "claims-to-resolve-contacts",
                   "contacts.no-tunnelling", "it went into or through a capsule of radius 0.012 m",
                   "--filter contacts"},
        FaultyCase{"faulty_resolves_at_the_step_start", "resolves-at-the-step-start",
                   "contacts.moving-collider",
                   "a box 2 mm thick rising at 95 m/s (its top at y = ", "--filter contacts"},
        FaultyCase{"faulty_keeps_its_velocity_through_contacts",
                   "keeps-its-velocity-through-contacts", "contacts.carried-by-a-moving-body",
                   "the strip's mean velocity along the box's motion is ", "--filter contacts"},
        FaultyCase{"faulty_restarts_bdf2_at_contacts", "restarts-bdf2-at-contacts",
                   "contacts.carried-by-a-moving-body", "m/s after 0.2 s on a box sliding",
                   "--filter contacts.carried"},
        FaultyCase{"faulty_answers_any_collider_revision", "answers-any-collider-revision",
                   "descriptor.extensions", "get_extension(\"clothlab.colliders/0\") is not NULL",
                   "--filter descriptor"},
        FaultyCase{"faulty_holds_its_target_between_keys", "holds-its-target-between-keys",
                   "scenario.attachments", "attachment 0 (particle 0): target jumps",
                   "--filter scenario.attachments"},
        FaultyCase{"faulty_jumps_its_collider", "jumps-its-collider", "scenario.colliders",
                   "collider 0: pose at t = 1 s: position moved 2", "--filter scenario.colliders"},
        FaultyCase{"faulty_gives_a_negative_radius", "gives-a-negative-radius",
                   "scenario.colliders", "collider 0: radius = -0.2",
                   "--filter scenario.colliders"},
        FaultyCase{"faulty_loses_its_collider", "loses-its-collider", "scenario.colliders",
                   "collider 0: pose at t = 0.5 s: position.y = nan, allowed finite",
                   "--filter scenario.colliders"},
        FaultyCase{"faulty_misstates_its_collider_velocity", "misstates-its-collider-velocity",
                   "scenario.colliders", "s: velocity 0 m/s, its poses move at 3 m/s",
                   "--filter scenario.colliders"},
        FaultyCase{"faulty_idle_in_float32", "idle-in-float32", "numerics.precisions-agree",
                   "float32 and float64 differ by", "--filter numerics"},
        FaultyCase{"faulty_rebinds_badly", "rebinds-badly", "lifecycle.prepare-twice",
                   "after a second prepare", "--filter lifecycle"},
        // One for every check (host/conformance/README.md, "Which faulty plugin each check
        // catches").
        FaultyCase{"faulty_lies_about_order", "lies-about-order", "numerics.order-free-fall",
                   "measured order 1.", "--filter numerics.order-free-fall",
                   "faulty_lies_about_order_free_fall"},
        FaultyCase{"faulty_lies_about_order", "lies-about-order", "numerics.order-damped-spring",
                   "measured order 1.", "--filter numerics.order-damped-spring",
                   "faulty_lies_about_order_damped_spring"},
        FaultyCase{"faulty_moves_pinned", "moves-pinned", "numerics.pinned-f32",
                   "pinned particle 0 moved", "--filter numerics.pinned-f32",
                   "faulty_moves_pinned_f32"},
        FaultyCase{"faulty_claims_unconditional_stability", "claims-unconditional-stability",
                   "stability.unconditional-flag", "declares unconditional stability, but",
                   "--filter stability.unconditional-flag",
                   "faulty_claims_unconditional_stability_flag"},
        FaultyCase{"faulty_damps_per_step", "damps-per-step", "lifecycle.dt-zero",
                   "a step with dt = 0 changed the state", "--filter lifecycle.dt-zero"},
        FaultyCase{"faulty_kicks_in_prepare", "kicks-in-prepare", "lifecycle.zero-steps",
                   "create/prepare/destroy without a step changed the state",
                   "--filter lifecycle.zero-steps"},
        FaultyCase{"faulty_starts_once_per_process", "starts-once-per-process", "lifecycle.repeat",
                   "round 2 of create/prepare/step/destroy differs from round 1",
                   "--filter lifecycle.repeat"},
        FaultyCase{"faulty_starts_once_per_process", "starts-once-per-process",
                   "numerics.deterministic", "two identical runs give different bits",
                   "--filter numerics.deterministic", "faulty_starts_once_per_process_numerics"},
        FaultyCase{"faulty_adds_own_gravity", "adds-own-gravity", "numerics.rest",
                   "a cloth at rest without external forces moved", "--filter numerics.rest"},
        FaultyCase{"faulty_chunks_by_process_threads", "chunks-by-process-threads",
                   "numerics.threads-f64", "1 and 2 threads give different bits",
                   "--filter numerics.threads-f64"},
        FaultyCase{"faulty_chunks_by_process_threads", "chunks-by-process-threads",
                   "numerics.threads-f32", "1 and 2 threads give different bits",
                   "--filter numerics.threads-f32", "faulty_chunks_by_process_threads_f32"},
        FaultyCase{"faulty_shares_state_between_instances", "shares-state-between-instances",
                   "robustness.concurrent",
                   "instance 1 stepped by turns with another differs from its run alone",
                   "--filter robustness.concurrent"},
        FaultyCase{"faulty_refuses_its_default", "refuses-its-default", "params.defaults",
                   "create failed: INVALID_ARGUMENT: substeps = 1", "--filter params.defaults"},
        FaultyCase{"faulty_clamps_out_of_range", "clamps-out-of-range", "params.out-of-range",
                   "was accepted", "--filter params.out-of-range"},
        FaultyCase{"faulty_truncates_non_integers", "truncates-non-integers", "params.wrong-type",
                   "substeps = 1.5 (not an integer) was accepted", "--filter params.wrong-type"},
        FaultyCase{"faulty_supports_fewer_substeps", "supports-fewer-substeps", "params.fuzz",
                   "at most 16 substeps supported with substeps=64", "--filter params.fuzz"},
        FaultyCase{"faulty_malformed_id", "SymplecticEuler", "descriptor.fields",
                   "id = \"SymplecticEuler\", allowed [a-z0-9_-]+", "--filter descriptor.fields"},
        FaultyCase{"faulty_duplicates_an_id", "library", "descriptor.ids-unique",
                   "id = \"duplicated-euler\", allowed an id no other component",
                   "--filter descriptor.ids-unique"},
        FaultyCase{"faulty_misweighs_bdf2", "misweighs-bdf2", "numerics.order-spring",
                   "measured order 1.1", "--filter numerics.order-spring"},
        FaultyCase{"faulty_misweighs_bdf2", "misweighs-bdf2", "numerics.order-damped-spring",
                   "measured order 0.9", "--filter numerics.order-damped-spring",
                   "faulty_misweighs_bdf2_damped_spring"},
        FaultyCase{"faulty_declares_order_zero", "declares-order-zero", "descriptor.order",
                   "declared order 0 < 1", "--filter descriptor.order"},
        FaultyCase{"faulty_default_outside_range", "default-outside-range", "descriptor.params",
                   "params.substeps.default_value = 0, allowed int in [1, 64]",
                   "--filter descriptor.params"},
        FaultyCase{"faulty_misdeclares_two_params", "misdeclares-two-params", "descriptor.params",
                   "params.verbose.range = [0, 2], allowed [0, 1] for a bool",
                   "--filter descriptor.params"},
        FaultyCase{"faulty_needs_a_missing_library", "library", "loading.dlopen",
                   "undefined symbol: clothlab_faulty_helper_never_linked",
                   "--filter loading.dlopen"},
        FaultyCase{"faulty_exports_its_helpers", "library", "loading.exports",
                   "clothlab_faulty_halve", "--filter loading.exports"},
        FaultyCase{"faulty_refuses_second_load", "library", "loading.reload",
                   "entry returned null on load 2", "--filter loading.reload"},
        FaultyCase{"faulty_pins_past_the_grid", "pins-past-the-grid", "scenario.valid",
                   "scene.pinned = 64: allowed indices < rows*cols = 64",
                   "--filter scenario.valid"},
        FaultyCase{"faulty_ruffles_at_random", "ruffles-at-random", "scenario.deterministic",
                   "two describe calls on one instance differ", "--filter scenario.deterministic"},
        FaultyCase{"faulty_ignores_wind", "ignores-wind", "scenario.params",
                   "setting wind = 1.250000 changes neither the scene, nor its colliders, nor its "
                   "air, nor "
                   "what moves",
                   "--filter scenario.params"},
        FaultyCase{"faulty_ignores_attachments", "ignores-attachments", "attachments.follow-f64",
                   "attached particle 0 off its target after step 1", "--filter attachments"},
        FaultyCase{"faulty_offers_only_float32", "offers-only-float32", "numerics.float64",
                   "numerics are measured in float64, which it lacks", "--filter numerics.float64"},
        FaultyCase{"faulty_undercounts_evals", "undercounts-evals", "lifecycle.evals-per-step",
                   "20 force evaluations in 10 steps; declared evals_per_step 1",
                   "--filter lifecycle"},
        FaultyCase{"faulty_lacks_step", "library", "loading.abi-policy",
                   "the host loader refuses it at its own version 1.3: integrator lacks-step: "
                   "step = null, allowed a function",
                   "--filter loading"},
        FaultyCase{"faulty_flips_the_stiffness_sign", "flips-the-stiffness-sign",
                   "stability.default-sheet",
                   "it diverged at dt = 0.001 s on the default sheet (float64): ",
                   "--filter stability.default-sheet"},
        FaultyCase{"faulty_flips_the_stiffness_sign", "flips-the-stiffness-sign",
                   "stability.default-flag",
                   "it diverged at dt = 0.001 s on the default flag (float64): ",
                   "--filter stability.default-flag", "faulty_flips_the_stiffness_sign_flag"},
        FaultyCase{"faulty_allocates_in_worker_thread", "allocates-in-worker-thread",
                   "robustness.no-alloc", "heap allocator calls during 10 steps",
                   "--filter robustness.no-alloc"},
        FaultyCase{"faulty_reserves_in_step", "reserves-in-step", "robustness.no-alloc",
                   "in step 1: clothlab.jacobian/1's reserve called after prepare",
                   "--filter robustness.no-alloc"}),
    [](const ::testing::TestParamInfo<FaultyCase>& info) {
      return std::string(info.param.test_name != nullptr ? info.param.test_name
                                                         : info.param.plugin);
    });

// The plugin author's recipe of lab/sanitizers.md: the installed (Release) runner with the
// AddressSanitizer runtime preloaded, so that an ASan-built plugin loads.
std::string asan_runtime_preloaded() {
  EXPECT_TRUE(std::ifstream(ASAN_RUNTIME).good())
      << "no AddressSanitizer runtime: " << ASAN_RUNTIME;
  return std::string("LD_PRELOAD=") + ASAN_RUNTIME;
}

// The allocation counter forwards to the preloaded runtime's allocator (the runtime's own
// interceptors allocate there): the stepping checks pass, and the counter still counts.
TEST(ConformanceRun, AsanRuntimePreloadedTheSteppingChecksRunAndAllocationsAreCounted) {
  const RunnerOutput sound = run_conformance(
      "--filter 'params.defaults|lifecycle.grid-3x3|robustness' " + plugin("c_euler"),
      asan_runtime_preloaded());
  EXPECT_EQ(sound.exit_code, 0) << sound.output;
  ASSERT_NE(find_check(sound, "c-euler", "robustness.no-alloc"), nullptr) << sound.output;
  EXPECT_EQ((*find_check(sound, "c-euler", "robustness.no-alloc"))["passed"], true);
  const RunnerOutput allocating =
      run_conformance("--filter robustness.no-alloc " + plugin("faulty_allocates_every_step"),
                      asan_runtime_preloaded());
  const nlohmann::json* no_alloc =
      find_check(allocating, "allocates-every-step", "robustness.no-alloc");
  ASSERT_NE(no_alloc, nullptr) << allocating.output;
  EXPECT_NE((*no_alloc)["reason"].get<std::string>().find("heap allocator calls during 10 steps"),
            std::string::npos)
      << (*no_alloc)["reason"];
}

// An ASan-built plugin with a heap overflow: the failed check's reason holds the report's first
// line (as the sanitizer printed it) and its summary line.
TEST(ConformanceRun, AsanReportOfAPluginReachesTheFailReason) {
  const RunnerOutput run =
      run_conformance("--filter lifecycle.grid-3x3-f64 " + plugin("faulty_overflows_heap_in_step"),
                      asan_runtime_preloaded());
  EXPECT_EQ(run.exit_code, 1) << run.output;
  const nlohmann::json* result =
      find_check(run, "overflows-heap-in-step", "lifecycle.grid-3x3-f64");
  ASSERT_NE(result, nullptr) << run.output;
  EXPECT_EQ((*result)["passed"], false);
  const std::string reason = (*result)["reason"];
  // The runner also passes the child's stderr through: the report's first line is there.
  const size_t error = run.output.find("==ERROR: AddressSanitizer: heap-buffer-overflow on ");
  ASSERT_NE(error, std::string::npos) << run.output;
  const size_t line_start = run.output.rfind('\n', error) + 1;
  const std::string first_line =
      run.output.substr(line_start, run.output.find('\n', error) - line_start);
  EXPECT_NE(reason.find(first_line + "; SUMMARY: AddressSanitizer: heap-buffer-overflow"),
            std::string::npos)
      << first_line << "\n"
      << reason;
  EXPECT_NE(reason.find("overflows_heap_in_step"), std::string::npos) << reason;
}

// The fault only a run at the defaults shows: an implicit Euler with its stiffness term's sign
// flipped, declaring no unconditional stability, passes every other check and fails the two
// default-scene runs, by the stability monitor's verdict.
// A flick over in 20 to 80 ms is between the 0.1 s samples scenario.params once took: its
// parameter changes what moves, and the path passes scenario.attachments at substep times.
TEST(ConformanceRun, AParameterThatActsForMillisecondsChangesTheMotion) {
  const RunnerOutput run = run_conformance("--filter scenario " + plugin("flicks_a_corner"));
  EXPECT_EQ(run.exit_code, 0) << run.output;
  for (const char* check : {"scenario.params", "scenario.attachments"}) {
    const nlohmann::json* result = find_check(run, "flicks-a-corner", check);
    ASSERT_NE(result, nullptr) << check << " did not run:\n" << run.output;
    EXPECT_EQ((*result)["passed"], true) << check << ": " << (*result)["reason"];
  }
}

TEST(ConformanceRun, OnlyTheDefaultSceneRunsCatchAFlippedStiffnessSign) {
  // As for a sound plugin below: the other checks must not fail on the clock of shared cores.
  const RunnerOutput run =
      run_conformance("--timeout 90 " + plugin("faulty_flips_the_stiffness_sign"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  ASSERT_FALSE(run.report.is_null()) << run.output;
  std::vector<std::string> failed;
  for (const nlohmann::json& result : run.report["checks"])
    if (result["passed"] == false) failed.push_back(result["check"].get<std::string>());
  EXPECT_EQ(failed, (std::vector<std::string>{"stability.default-sheet", "stability.default-flag"}))
      << run.output;
  EXPECT_GT(run.report["passed"].get<int>(), 30) << run.output;
}

// An undeclared drag that vanishes with the step keeps the order, rest and dt = 0: only the
// momentum check sees it.
TEST(ConformanceRun, OnlyTheMomentumCheckCatchesAnUndeclaredDrag) {
  const RunnerOutput run =
      run_conformance("--timeout 90 " + plugin("faulty_drags_without_declaring"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  ASSERT_FALSE(run.report.is_null()) << run.output;
  std::vector<std::string> failed;
  for (const nlohmann::json& result : run.report["checks"])
    if (result["passed"] == false) failed.push_back(result["check"].get<std::string>());
  EXPECT_EQ(failed, (std::vector<std::string>{"numerics.momentum"})) << run.output;
  const nlohmann::json* momentum = find_check(run, "drags-without-declaring", "numerics.momentum");
  ASSERT_NE(momentum, nullptr) << run.output;
  EXPECT_NE((*momentum)["reason"].get<std::string>().find("momentum not given by gravity"),
            std::string::npos)
      << run.output;
  EXPECT_GT(run.report["passed"].get<int>(), 40) << run.output;
}

TEST(ConformanceRun, ContinuesWithTheNextPluginAfterACrash) {
  const RunnerOutput run =
      run_conformance("--filter lifecycle.grid-3x3-f64 " + plugin("faulty_segfaults_in_step") +
                      " " + plugin("c_euler"));
  EXPECT_EQ(run.exit_code, 1);
  const nlohmann::json* after = find_check(run, "c-euler", "lifecycle.grid-3x3-f64");
  ASSERT_NE(after, nullptr) << run.output;
  EXPECT_EQ((*after)["passed"], true);
}

// The grid checks share one mechanism (step, then require a finite state): each of them, in
// each precision, fails on the plugin that writes NaN.
TEST(ConformanceRun, EveryGridCheckCatchesANonFiniteState) {
  const RunnerOutput run =
      run_conformance("--filter lifecycle.grid " + plugin("faulty_produces_nan"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  ASSERT_FALSE(run.report.is_null()) << run.output;
  int grids = 0;
  for (const nlohmann::json& result : run.report["checks"]) {
    EXPECT_EQ(result["passed"], false) << result["check"];
    EXPECT_NE(result["reason"].get<std::string>().find("non-finite"), std::string::npos)
        << result["reason"];
    ++grids;
  }
  EXPECT_EQ(grids, 10) << run.output;  // 5 shapes x 2 precisions
}

// The loader refuses on the first finding of the one descriptor validator; the runner reports
// every finding, and the loader's refusal too.
TEST(ConformanceRun, ReportsEveryFindingOfTheDescriptorValidator) {
  const RunnerOutput run = run_conformance("--filter 'descriptor.params|loading.host-loader' " +
                                           plugin("faulty_misdeclares_two_params"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  const nlohmann::json* params = find_check(run, "misdeclares-two-params", "descriptor.params");
  ASSERT_NE(params, nullptr) << run.output;
  EXPECT_EQ((*params)["reason"],
            "integrator misdeclares-two-params: params.substeps.default_value = 2.5, allowed int "
            "in [1, 64]; integrator misdeclares-two-params: params.verbose.range = [0, 2], "
            "allowed [0, 1] for a bool");
  const nlohmann::json* host = find_check(run, "library", "loading.host-loader");
  ASSERT_NE(host, nullptr) << run.output;
  EXPECT_EQ((*host)["passed"], false);
  const std::string refusal = (*host)["reason"];
  EXPECT_NE(refusal.find("params.substeps.default_value = 2.5"), std::string::npos) << refusal;
  EXPECT_EQ(refusal.find("params.verbose"), std::string::npos) << refusal;
}

TEST(ConformanceRun, AbiMajorTwoIsNotReadBeyondItsVersion) {
  const RunnerOutput run = run_conformance(plugin("faulty_abi_major_2"));
  ASSERT_FALSE(run.report.is_null()) << run.output;
  for (const nlohmann::json& result : run.report["checks"])
    EXPECT_EQ(result["check"].get<std::string>().rfind("loading.", 0), 0u) << result["check"];
}

TEST(ConformanceRun, ANewerMinorAbiIsAcceptedByTheRunnerAndTheHostLoader) {
  const RunnerOutput run = run_conformance("--filter loading " + plugin("abi_newer_minor"));
  EXPECT_EQ(run.exit_code, 0) << run.output;
  const nlohmann::json* host = find_check(run, "library", "loading.host-loader");
  ASSERT_NE(host, nullptr) << run.output;
  EXPECT_EQ((*host)["passed"], true) << (*host)["reason"];
  const nlohmann::json* version = find_check(run, "library", "loading.abi-version");
  ASSERT_NE(version, nullptr) << run.output;
  EXPECT_EQ((*version)["reason"], "ABI " + std::to_string(CLOTHLAB_ABI_VERSION_MAJOR) + "." +
                                      std::to_string(CLOTHLAB_ABI_VERSION_MINOR + 1));
}

TEST(ConformanceRun, TheHostLoaderRefusesAnotherMajor) {
  const RunnerOutput run = run_conformance("--filter loading " + plugin("faulty_abi_major_2"));
  const nlohmann::json* host = find_check(run, "library", "loading.host-loader");
  ASSERT_NE(host, nullptr) << run.output;
  EXPECT_EQ((*host)["passed"], false);
  EXPECT_EQ((*host)["reason"].get<std::string>().rfind("the host refuses it: ", 0), 0u)
      << (*host)["reason"];
}

class SoundPlugin : public ::testing::TestWithParam<std::string> {};

TEST_P(SoundPlugin, PassesEveryCheck) {
  // The per-check deadline detects hangs (tested above with 1 s); here the cores are shared
  // with ctest -j2 and maybe sanitizers, and a sound plugin must not fail on the clock.
  const RunnerOutput run = run_conformance("--timeout 90 " + GetParam());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  ASSERT_FALSE(run.report.is_null()) << run.output;
  EXPECT_EQ(run.report["failed"], 0) << run.output;
  EXPECT_GT(run.report["passed"].get<int>(), 10);
}

std::vector<std::string> sound_plugins() {
  std::vector<std::string> arguments = {plugin("c_euler"), plugin("example_velocity_verlet"),
                                        plugin("example_linearly_implicit_euler"),
                                        plugin("abi_legacy_1_0"), plugin("abi_legacy_1_1")};
  std::stringstream builtins(BUILTIN_PLUGINS);
  for (std::string name; std::getline(builtins, name, ',');) {
    arguments.push_back(BUILTIN_PLUGIN_DIR + std::string("/") + name + ".so");
  }
  return arguments;
}

INSTANTIATE_TEST_SUITE_P(Conformance, SoundPlugin, ::testing::ValuesIn(sound_plugins()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           const std::string& path = info.param;
                           const size_t slash = path.rfind('/');
                           std::string name = path.substr(slash + 1, path.size() - slash - 4);
                           return name;
                         });

// The mesh scenario reads its file through a text parameter (--text): with one it passes the
// loading, descriptor and scene checks and those parameter checks that hold for a file's data;
// without, its default (no file) is refused and params.defaults says so. Left out, because a
// mesh's valid values depend on its file: params.fuzz (an in-range max_vertices or max_file_mb
// below the file's refuses it, a fuzzed pin rule may select nothing, an error by design) and
// scenario.params (the limits and the settings of a pin rule not in use change nothing, and
// placement changes the mesh, which the check does not read).
TEST(ConformanceRun, TheMeshScenarioPassesWithAFileFromTextParameters) {
  const std::string mesh = BUILTIN_PLUGIN_DIR + std::string("/mesh.so");
  const RunnerOutput run = run_conformance(
      "--timeout 90 --filter 'loading|descriptor|params[.](defaults|out-of-range|wrong-type)|"
      "scenario[.](valid|deterministic|colliders)' --text mesh.file=" +
      std::string(MESH_ASSETS) + "/disc.obj " + mesh);
  EXPECT_EQ(run.exit_code, 0) << run.output;
  ASSERT_FALSE(run.report.is_null()) << run.output;
  EXPECT_EQ(run.report["failed"], 0) << run.output;
  EXPECT_GT(run.report["passed"].get<int>(), 5) << run.output;
  const RunnerOutput without = run_conformance("--timeout 90 --filter params.defaults " + mesh);
  const nlohmann::json* defaults = find_check(without, "mesh", "params.defaults");
  ASSERT_NE(defaults, nullptr) << without.output;
  EXPECT_FALSE((*defaults)["passed"].get<bool>()) << without.output;
  EXPECT_NE(without.output.find("scenario.file: empty"), std::string::npos) << without.output;
}

// The multigrid settings need clothlab.grid/1: robustness.no-alloc's plugin-only system must
// pass it on (without it prepare failed, "needs a cloth laid out as a grid"), and the solves
// must not allocate or depend on the thread count, also when the hierarchy is reused.
TEST(ConformanceRun, TheMultigridSettingsPassNoAllocAndThreads) {
  for (const std::string setting :
       {"implicit_euler.multigrid=1",
        "implicit_euler.multigrid=1 --param implicit_euler.multigrid_rebuild=4",
        "projective_dynamics.factorization=2"}) {
    const std::string id = setting.substr(0, setting.find('.'));
    const RunnerOutput run =
        run_conformance("--timeout 90 --filter 'no-alloc|threads-f' --param " + setting + " " +
                        BUILTIN_PLUGIN_DIR + std::string("/") + id + ".so");
    EXPECT_EQ(run.exit_code, 0) << run.output;
    ASSERT_FALSE(run.report.is_null()) << run.output;
    EXPECT_EQ(run.report["failed"], 0) << run.output;
    EXPECT_EQ(run.report["passed"], 3) << run.output;
  }
}

// The order checks measure the implicit methods' orders, not only a pass: backward Euler's 1 and
// BDF2's 2 on the same solver (the faulty misweighs_bdf2, bdf2's code with first-order weights,
// is caught above).
TEST(ConformanceRun, MeasuresFirstOrderForImplicitEulerAndSecondForBdf2) {
  for (const auto& [id, order] : {std::pair{"implicit_euler", 1.0}, std::pair{"bdf2", 2.0}}) {
    const RunnerOutput run =
        run_conformance("--timeout 90 --filter 'numerics.order-(spring|damped-spring)' " +
                        std::string(BUILTIN_PLUGIN_DIR) + "/" + id + ".so");
    EXPECT_EQ(run.exit_code, 0) << run.output;
    for (const char* check : {"numerics.order-spring", "numerics.order-damped-spring"}) {
      const nlohmann::json* result = find_check(run, id, check);
      ASSERT_NE(result, nullptr) << id << " " << check << ":\n" << run.output;
      const std::string reason = (*result)["reason"];
      const std::string prefix = "measured order ";
      ASSERT_TRUE(reason.starts_with(prefix)) << reason;
      EXPECT_NEAR(std::stod(reason.substr(prefix.size())), order, 0.1) << id << " " << reason;
    }
  }
}

TEST(ConformanceRun, WritesJunitAndPrintsTheSeed) {
  const std::string junit = ::testing::TempDir() + "conformance-junit.xml";
  const RunnerOutput run =
      run_conformance("--filter loading --junit " + junit + " " + plugin("c_euler"));
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("seed 11"), std::string::npos);
  std::ifstream in(junit);
  std::stringstream xml;
  xml << in.rdbuf();
  EXPECT_NE(xml.str().find("<testsuite name=\"c_euler\" tests=\"6\" failures=\"0\""),
            std::string::npos)
      << xml.str();
  std::remove(junit.c_str());
}

TEST(ConformanceRun, RejectsBadOptionsWithOneLine) {
  RunnerOutput run = run_conformance("--timeout -1 " + plugin("c_euler"));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.output,
            "clothlab-conformance: --timeout = -1.000000: allowed (0, 86400] seconds\n");
  run = run_conformance("/nonexistent/plugin.so");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.output, "clothlab-conformance: plugin \"/nonexistent/plugin.so\": no such file\n");
  run = run_conformance("--filter '(' " + plugin("c_euler"));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.output.rfind("clothlab-conformance: --filter = \"(\": not a valid", 0), 0u)
      << run.output;
  run = run_conformance("--param c-euler.substeps=99 " + plugin("c_euler"));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.output.find("--param c-euler.substeps = 99"), std::string::npos) << run.output;
}

// Item 7 of issue 12: a bad --param was found after 11 checks ran; --filter nomatch reported
// "0 passed, 0 failed" and exited 0; a plugin named without '/' went to dlopen's search.
TEST(ConformanceRun, BadParamIsFoundBeforeAnyCheckRuns) {
  const RunnerOutput run = run_conformance("--param c-euler.substeps=99 " + plugin("c_euler"));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.output.find("PASS"), std::string::npos) << run.output;
  EXPECT_EQ(run.output.find("FAIL"), std::string::npos) << run.output;
}

TEST(ConformanceRun, AFilterThatMatchesNothingIsAnError) {
  const RunnerOutput run = run_conformance("--filter no-such-check " + plugin("c_euler"));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.output.find("clothlab-conformance: --filter = \"no-such-check\" matched no check"),
            std::string::npos)
      << run.output;
}

TEST(ConformanceRun, APluginNamedInItsOwnFolderLoads) {
  const std::string command = std::string("cd '") + CONFORMANCE_PLUGIN_DIR + "' && " +
                              CONFORMANCE_RUNNER + " --seed 3 --filter loading c_euler.so 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buffer[4096];
  while (size_t n = fread(buffer, 1, sizeof buffer, pipe)) output.append(buffer, n);
  const int status = pclose(pipe);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << output;
  EXPECT_EQ(output.find("cannot open shared object file"), std::string::npos) << output;
  EXPECT_NE(output.find("PASS"), std::string::npos) << output;
}

}  // namespace
