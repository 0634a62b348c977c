#include "clothlab/sweep/integrator_choice.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <clothlab/config/mesh_sides.hpp>
#include <clothlab/host/param_text.hpp>
#include <cmath>
#include <sstream>

#include "clothlab/sweep/sweep_error.hpp"
#include "sweep_test_support.hpp"

namespace clothlab::sweep {
namespace {

using testing::ScratchFolder;

// Fake integrators with known limits, on one particle of a cloth whose diagonal is 1 (so the
// error is the particle's x). Costs: 1 ms per substep plus 0.1 ms per iteration, times
// `time_scale`; a run takes its frames' time (T x the frame rate) and times out past the
// case's `timeout` setting like a child process would.
//   explicit:  unstable below 37 substeps; error 0.5 / substeps (1 % from 50 substeps)
//   stretchy:  always stable, stretch 1 + 0.5 / substeps (10 % from 5 substeps)
//   iterative: passes when substeps x iterations >= 8; cheapest is 1 substep x 8 iterations
//   plateau:   has iterations, error 0.5 / substeps + 0.001 / iterations: iterations barely
//              help, 1 % from 64 substeps x 1 iteration
//   steady:    passes at 1 substep, 25 ms/frame whatever the substeps
//   stiff:     error 0.001, unstable below 37 substeps at the 40 x 40 scene mesh only
//   damped:    error 0.03 + 0.001 / substeps: never within 1 %, whatever the step
//   saturated: error 0.2 up to 2 substeps, then 0.5 / substeps^2 (1 % from 8 substeps)
//   never:     always unstable
//   dear:      unstable below 11 substeps, 2.5 ms per substep
//   solver:    has iterations, unstable below 12 of them, 3 ms per substep and iteration
//   walker:    has iterations, unstable below 4 substeps, 10 x the usual cost
//   cornered:  the spring at a pin stretches 30 %, the rest of the cloth 2 %
//   soft:      stretch (everywhere) 1 + 0.2 / substeps: 10 % at 2 substeps, a strain 1.5 x
//              the reference's 2 % from 7 substeps
//   tunneller: on a scene with colliders, lies 0.04 / substeps m deep in one (thickness 0.01 m,
//              every other method 0.002 m deep): the thickness is kept from 4 substeps
// Every run's robust stretch (away from the pins) is its maximum but for cornered's; its 99th
// percentile half way to 1.
// The reference (rk4, float64) sits at x = 0 with a difference `reference_gap` between its two
// steps, and its robust stretch is `reference_stretch` (0: the reference has no such figure).
// `runs` lists every run as "integrator rows substeps". The grid's rows as the run would get them:
// the later of scenario.rows and mesh; "0" unset.
std::string rows_of(const CaseSpec& c) {
  for (auto setting = c.settings.rbegin(); setting != c.settings.rend(); ++setting) {
    if (setting->key == "scenario.rows") return setting->value;
    if (setting->key == "mesh") return config::mesh_sides(setting->value).rows;
  }
  return "0";
}

struct FakeRuns {
  double reference_gap = 0.0;
  double reference_stretch = 0.0;
  double precision_floor = 0.0;
  std::vector<std::string> precision_floor_runs;  // "precision dt" per run
  // The scene's attached particles and colliders, as every run reports them.
  uint32_t attached_particles = 0;
  uint32_t colliders = 0;
  double time_scale = 1.0;
  // "integrator substeps" whose first `bursts` short runs (the first frames) other jobs slow
  // 10-fold.
  std::string burst_on;
  int bursts = 1;
  // From this call on (0: never), other jobs make every run take twice as long.
  int loaded_from_call = 0;
  int calls = 0;
  std::vector<std::string> runs;
  std::vector<std::string> settings;       // "integrator substeps x iterations" per probe run
  std::vector<std::string> stretch_stops;  // "rows stability.stretch_stop" per probe run
  Trajectory operator()(const CaseSpec& c) {
    Trajectory run;
    host::RunSummary& figures = run.summary;
    run.diagonal = 1.0;
    // The reference integrator in the scene's (lower) precision at the reference's step: it
    // lies `precision_floor` from the float64 run. Not counted in `calls`, which schedule the
    // probes' load from the reference on.
    if (c.integrator == "rk4" && c.precision != "float64") {
      precision_floor_runs.push_back(c.precision + " " + host::format_number(c.dt));
      run.positions = {precision_floor, 0, 0};
      return run;
    }
    ++calls;
    if (attached_particles > 0)
      figures.attachments = host::RunSummary::Attachments{attached_particles, 0.0};
    if (colliders > 0) {
      host::RunSummary::Contacts& contacts = figures.contacts.emplace();
      contacts.colliders = colliders;
      contacts.max_penetration_over_run = contacts.max_depth_past_thickness_over_run =
          contacts.thickness = NAN;
    }
    if (c.precision == "float64") {
      run.positions = {c.dt > 3e-5 ? reference_gap : 0.0, 0, 0};  // the coarser of the two
      figures.max_stretch.over_run = figures.max_stretch_away_from_pins.over_run =
          reference_stretch;
      return run;
    }
    const double substeps = std::stod(c.setting("substeps"));
    runs.push_back(c.integrator + " " + rows_of(c) + " " + c.setting("substeps"));
    stretch_stops.push_back(rows_of(c) + " " + c.setting("stability.stretch_stop"));
    const std::string text = c.setting("integrator.iterations").empty()
                                 ? c.setting("integrator.cap")
                                 : c.setting("integrator.iterations");
    const double iterations = text.empty() ? 0.0 : std::stod(text);
    settings.push_back(c.integrator + " " + c.setting("substeps") + " x " +
                       (text.empty() ? "0" : text));
    double& ms_per_frame = figures.ms_per_frame.median;
    ms_per_frame =
        time_scale * (c.integrator == "steady" ? 25.0 : substeps) * (1.0 + 0.1 * iterations);
    if (c.integrator == "dear") ms_per_frame = 2.5 * substeps;
    if (c.integrator == "solver") ms_per_frame = 3 * substeps * iterations;
    if (c.integrator == "walker") ms_per_frame *= 10;
    if (loaded_from_call > 0 && calls >= loaded_from_call) ms_per_frame *= 2;
    if (c.duration < 1 && c.integrator + " " + c.setting("substeps") == burst_on) {
      if (--bursts == 0) burst_on.clear();
      ms_per_frame *= 10;
    }
    figures.ms_per_frame.p10 = 0.9 * ms_per_frame;
    figures.wall_time_s = ms_per_frame * c.duration * std::stod(c.setting("frame_rate")) / 1e3;
    const std::string timeout = c.setting("timeout");
    if (!timeout.empty() && figures.wall_time_s > std::stod(timeout)) {
      run.verdict.status = CaseStatus::Failed;
      run.verdict.reason = "timed out after " + timeout + " s";
      return run;
    }
    double& max_stretch = figures.max_stretch.over_run;
    double& away_from_pins = figures.max_stretch_away_from_pins.over_run;
    max_stretch = 1.01;
    double error = 0.001;
    const bool unstable = (c.integrator == "explicit" && substeps < 37) ||
                          (c.integrator == "iterative" && substeps * iterations < 8) ||
                          (c.integrator == "stiff" && rows_of(c) == "40" && substeps < 37) ||
                          (c.integrator == "dear" && substeps < 11) ||
                          (c.integrator == "solver" && iterations < 12) ||
                          (c.integrator == "walker" && substeps < 4) || c.integrator == "never";
    if (c.integrator == "explicit") error = 0.5 / substeps;
    if (c.integrator == "plateau") error = 0.5 / substeps + 0.001 / iterations;
    if (c.integrator == "damped") error = 0.03 + 0.001 / substeps;
    if (c.integrator == "saturated") error = substeps <= 2 ? 0.2 : 0.5 / (substeps * substeps);
    if (c.integrator == "stretchy") max_stretch = 1.0 + 0.5 / substeps;
    if (c.integrator == "soft") max_stretch = 1.0 + 0.2 / substeps;
    away_from_pins = max_stretch;
    if (c.integrator == "cornered") {
      max_stretch = 1.3;
      away_from_pins = 1.02;
    }
    figures.p99_stretch.over_run = (1.0 + away_from_pins) / 2;
    if (figures.contacts) {
      // The thinnest collider is 0.01 m thick; "cushioned" lies 0.015 m inside one 0.02 m
      // thick, "rounded" a float32 rounding past a thickness of 0.
      host::RunSummary::Contacts& contacts = *figures.contacts;
      contacts.thickness = 0.01;
      contacts.max_penetration_over_run = c.integrator == "tunneller" ? 0.04 / substeps : 0.002;
      contacts.max_depth_past_thickness_over_run =
          std::max(0.0, contacts.max_penetration_over_run - 0.01);
      if (c.integrator == "cushioned") contacts.max_penetration_over_run = 0.015;
      if (c.integrator == "rounded") contacts.max_depth_past_thickness_over_run = 5e-7;
    }
    if (unstable) {
      run.verdict.status = CaseStatus::Unstable;
      run.verdict.reason = "energy";
    }
    run.positions = {error, 0, 0};
    return run;
  }
};

std::string choose_rows_parameter(const std::vector<Choice>& choices,
                                  const ChoiceSettings& settings) {
  return choice_rows(choices, settings).at(0)["iterations_parameter"].get<std::string>();
}

struct Fixture {
  SweepSpec spec;
  CaseSpec base;
  ChoiceSettings settings;
  ScratchFolder folder;
  ResultsStore store{folder.path() / "choose", false};
  FakeRuns runs;
  std::ostringstream progress;
  Fixture() {
    spec.source = "test";
    spec.fixed = {{"scenario.plugin", "flag", "test"}, {"duration", "1", "test"}};
    base = expand_cases(spec).at(0);
    settings.frame_rate = 50;  // reference dt 1 / (50 x 512) = 39 us, its check 78 us
    settings.max_substeps = 256;
  }
  // The search over `candidates` with this fixture's settings, fake runs, store and progress.
  std::vector<Choice> choose(const std::vector<ChoiceCandidate>& candidates) {
    return choose_integrators(spec, base, candidates, settings, std::ref(runs), std::ref(runs),
                              store, progress);
  }
};

TEST(IntegratorChoice, FindsEachCheapestPassingSettingAndRanksByCost) {
  Fixture fixture;
  const std::vector<Choice> choices = fixture.choose(
      {{"never", false}, {"explicit", false}, {"stretchy", false}, {"iterative", true}});
  ASSERT_EQ(choices.size(), 4u);
  // Ranked by ms per frame: iterative (1 x 8: 1.8 ms), stretchy (5 substeps), explicit (>= 50).
  EXPECT_EQ(choices[0].integrator, "iterative");
  EXPECT_EQ(choices[0].substeps, 1u);
  EXPECT_EQ(choices[0].iterations, 8u);
  EXPECT_NEAR(choices[0].ms_per_frame, 1.8, 1e-12);
  EXPECT_EQ(choices[1].integrator, "stretchy");
  EXPECT_EQ(choices[1].substeps, 5u);
  EXPECT_EQ(choices[2].integrator, "explicit");
  // Stable from 37 but accurate enough only from 50; bisection stops within 10 %.
  EXPECT_GE(choices[2].substeps, 50u);
  EXPECT_LE(choices[2].substeps, 55u);
  EXPECT_LE(choices[2].error, 0.01);
  EXPECT_EQ(choices[2].verdict, "slower than real time");  // > 20 ms per frame at 50 Hz
  EXPECT_EQ(choices[0].verdict, "real time");
  EXPECT_FALSE(choices[3].passed);
  EXPECT_EQ(choices[3].integrator, "never");
  EXPECT_NE(choices[3].verdict.find("no setting passed up to 256 substeps"), std::string::npos);
  EXPECT_NE(fixture.progress.str().find("choose [2/4] explicit 64 substeps: passes"),
            std::string::npos);
  // One reference row, with its estimated error; rows for every probe.
  int references = 0, probes = 0;
  for (const Row& row : fixture.store.rows()) {
    references += row["kind"] == "reference";
    probes += row["kind"] == "probe";
  }
  EXPECT_EQ(references, 1);
  EXPECT_GT(probes, 20);
  const std::vector<Row> ranked = choice_rows(choices, fixture.settings);
  EXPECT_EQ(ranked[0]["rank"], 1);
  EXPECT_TRUE(ranked[3]["rank"].is_null());
  EXPECT_NE(choice_table(choices, fixture.settings).find("iterative"), std::string::npos);
}

// The report's reference line reads every figure from the reference row, each stretch figure
// of the run summary included; a row without one is an error naming it, not a 0.
TEST(IntegratorChoice, StatesTheReferenceFromItsRowAndRefusesAMissingFigure) {
  Fixture fixture;
  fixture.runs.reference_gap = 3e-4;
  fixture.runs.reference_stretch = 1.002;
  fixture.choose({{"explicit", false}});
  Row reference;
  for (const Row& row : fixture.store.rows())
    if (row["kind"] == "reference") reference = row;
  const std::string line = reference_line(reference);
  EXPECT_NE(line.find("rk4 float64"), std::string::npos) << line;
  // The reference's own error is estimated as its two runs' difference / 15.
  EXPECT_NE(line.find("estimated own error 0.002 %"), std::string::npos) << line;
  EXPECT_NE(line.find("max_stretch_away_from_pins 1.002"), std::string::npos) << line;
  EXPECT_NE(line.find("p99_stretch 1"), std::string::npos) << line;
  reference.erase("p99_stretch");
  try {
    reference_line(reference);
    ADD_FAILURE() << "a reference row without p99_stretch was printed";
  } catch (const SweepError& error) {
    EXPECT_STREQ(error.what(), "choose: the reference row has no p99_stretch");
  }
  EXPECT_THROW(reference_line(Row()), SweepError);
}

// Once a setting passed, a probe that takes stop_factor x its time is stopped, and the table
// says so; a cheaper integrator searched later is still found.
TEST(IntegratorChoice, StopsProbesSlowerThanTheBestSoFarAndSaysSo) {
  Fixture fixture;
  fixture.settings.stop_factor = 3;
  fixture.runs.time_scale = 10;  // iterative 1 x 8: 18 ms/frame, 0.9 s for T = 1 s at 50 Hz
  const std::vector<Choice> choices =
      fixture.choose({{"stretchy", false}, {"iterative", true}, {"explicit", false}});
  ASSERT_EQ(choices.size(), 3u);
  // stretchy has no yardstick yet (first searched): found in full, 5 substeps, 2.5 s a run.
  EXPECT_EQ(choices[1].integrator, "stretchy");
  EXPECT_EQ(choices[1].substeps, 5u);
  // iterative's probes (at most 1 x 8: 18 ms/frame) stay within 3 x 50: found in full.
  EXPECT_EQ(choices[0].integrator, "iterative");
  EXPECT_EQ(choices[0].iterations, 8u);
  // explicit: 8 substeps cost 80 ms/frame (72 the fastest frames), over 3 x 18: stopped after
  // its first frames, not searched to 50.
  EXPECT_FALSE(choices[2].passed);
  EXPECT_EQ(choices[2].verdict.rfind("slower than iterative at 1 substep x 8 iterations (18 "
                                     "ms/frame)",
                                     0),
            0u)
      << choices[2].verdict;
  EXPECT_NE(
      choices[2].verdict.find("its fastest of 5 first frames took 72 ms (twice), so 5 to 8 "
                              "substeps cost at least 45 ms/frame, over 1.5 x (stop_factor / 2); "
                              "stopped at 8 substeps"),
      std::string::npos)
      << choices[2].verdict;
  EXPECT_EQ(std::count(fixture.runs.runs.begin(), fixture.runs.runs.end(), "explicit 0 16"), 0);
  int stopped = 0;
  for (const Row& row : fixture.store.rows())
    stopped += row["kind"] == "probe" && row["stopped"] == true;
  EXPECT_EQ(stopped, 1);
  EXPECT_NE(fixture.progress.str().find("choose [3/3] explicit 8 substeps: slower than iterative"),
            std::string::npos);
  EXPECT_NE(choice_table(choices, fixture.settings).find("slower than iterative"),
            std::string::npos);

  // stop_factor 0: no budget, explicit is searched to its answer.
  ScratchFolder unbounded_folder;
  ResultsStore unbounded(unbounded_folder.path() / "choose", false);
  fixture.settings.stop_factor = 0;
  fixture.runs.time_scale = 1;  // explicit's 50 substeps within the probe timeout
  const std::vector<Choice> all = choose_integrators(
      fixture.spec, fixture.base, {{"iterative", true}, {"explicit", false}}, fixture.settings,
      std::ref(fixture.runs), std::ref(fixture.runs), unbounded, fixture.progress);
  EXPECT_TRUE(all[1].passed);
  EXPECT_GE(all[1].substeps, 50u);
}

// The error (on the smaller error mesh) is measured first: a setting that fails it is never run
// at the scene's mesh.
TEST(IntegratorChoice, RunsTheSceneMeshOnlyWhereTheErrorPasses) {
  Fixture fixture;
  fixture.spec.fixed.push_back({"scenario.rows", "40", "test"});
  fixture.spec.fixed.push_back({"scenario.cols", "40", "test"});
  fixture.base = expand_cases(fixture.spec).at(0);
  fixture.settings.error_mesh = "10x10";
  fixture.settings.error_duration = 0.5;
  const std::vector<Choice> choices = fixture.choose({{"explicit", false}});
  ASSERT_TRUE(choices[0].passed);
  EXPECT_GE(choices[0].substeps, 50u);
  // Doubling 1 .. 32 fails on the error mesh (unstable there): no 40 x 40 run for them.
  for (const char* substeps : {"1", "2", "4", "8", "16", "32"}) {
    EXPECT_EQ(std::count(fixture.runs.runs.begin(), fixture.runs.runs.end(),
                         std::string("explicit 10 ") + substeps),
              1);
    EXPECT_EQ(std::count(fixture.runs.runs.begin(), fixture.runs.runs.end(),
                         std::string("explicit 40 ") + substeps),
              0);
  }
  EXPECT_EQ(std::count(fixture.runs.runs.begin(), fixture.runs.runs.end(), "explicit 40 64"), 1)
      << ::testing::PrintToString(fixture.runs.runs);
  EXPECT_NE(fixture.progress.str().find("on the error mesh 10x10: unstable"), std::string::npos);
}

// Where doubling the iterations changes the error by under 10 %, the substep count is left
// after two probes; the answer is the same.
// The stretch over a run only grows: the fixture.runs at the scene's mesh ask to end at the first
// check past the limit (stability.stretch_stop), the error fixture.runs, whose stretch is not
// judged, do not.
TEST(IntegratorChoice, EndsSceneMeshRunsAtTheStretchLimit) {
  Fixture fixture;
  fixture.spec.fixed.push_back({"scenario.rows", "40", "test"});
  fixture.spec.fixed.push_back({"scenario.cols", "40", "test"});
  fixture.base = expand_cases(fixture.spec).at(0);
  fixture.settings.error_mesh = "10x10";
  fixture.settings.error_duration = 0.5;
  fixture.settings.stretch_limit = 1.2;
  const std::vector<Choice> choices = fixture.choose({{"stretchy", false}});
  ASSERT_TRUE(choices[0].passed);
  EXPECT_EQ(choices[0].substeps, 3u);  // 1 + 0.5 / 3 <= 1.2
  ASSERT_FALSE(fixture.runs.stretch_stops.empty());
  for (const std::string& stop : fixture.runs.stretch_stops)
    EXPECT_TRUE(stop == "40 1.2" || stop == "10 0") << stop;
  EXPECT_NE(
      std::find(fixture.runs.stretch_stops.begin(), fixture.runs.stretch_stops.end(), "40 1.2"),
      fixture.runs.stretch_stops.end());
  EXPECT_NE(
      fixture.progress.str().find("stretchy 2 substeps: stretch 1.25 away from the pins above 1.2"),
      std::string::npos)
      << fixture.progress.str();
}

// The stretch judged is the robust one: a cloth whose only long spring is the one at a pin
// (a stress concentration that grows as the mesh refines) passes at its cheapest setting, and
// the rows report both figures.
TEST(IntegratorChoice, JudgesTheStretchAwayFromThePins) {
  Fixture fixture;
  const std::vector<Choice> choices = fixture.choose({{"cornered", false}});
  ASSERT_TRUE(choices[0].passed) << choices[0].verdict;
  EXPECT_EQ(choices[0].substeps, 1u);
  EXPECT_EQ(choices[0].run->max_stretch.over_run, 1.3);
  EXPECT_EQ(choices[0].run->max_stretch_away_from_pins.over_run, 1.02);
  EXPECT_EQ(choices[0].run->p99_stretch.over_run, 1.01);
  const Row row = choice_rows(choices, fixture.settings).at(0);
  EXPECT_EQ(row["max_stretch"], 1.3);
  EXPECT_EQ(row["max_stretch_away_from_pins"], 1.02);
  EXPECT_NE(choice_table(choices, fixture.settings).find("2 %"), std::string::npos);
  // (Judged on the maximum, the mutant this test catches, it would fail at every setting: the
  // pin's spring does not shorten with the step.) The robust figure is judged all the same:
  // under a limit below it, nothing passes.
  Fixture strict;
  strict.settings.stretch_limit = 1.01;
  EXPECT_FALSE(strict.choose({{"cornered", false}})[0].passed);
}

// A method may not stretch more than reference_stretch_factor x the reference's own robust
// stretch (as strain): soft passes the 10 % limit from 2 substeps, but its 10 % is 5 x the
// reference's 2 %; it needs 7 substeps for 1.5 x (1 + 0.2 / 7 <= 1.03).
TEST(IntegratorChoice, HoldsTheStretchWithinAFactorOfTheReferences) {
  Fixture fixture;
  fixture.runs.reference_stretch = 1.02;
  const std::vector<Choice> choices = fixture.choose({{"soft", false}});
  ASSERT_TRUE(choices[0].passed) << choices[0].verdict;
  EXPECT_GE(choices[0].substeps, 7u);
  EXPECT_LE(choices[0].substeps, 8u);
  EXPECT_LE(choices[0].run->max_stretch_away_from_pins.over_run, 1.03);
  EXPECT_NE(fixture.progress.str().find("soft 2 substeps: stretch 1.1 away from the pins, a "
                                        "strain over 1.5 x the reference's (1.02)"),
            std::string::npos)
      << fixture.progress.str();
  // The factor is a setting: at 5 x the reference's strain, 2 substeps pass.
  Fixture lenient;
  lenient.runs.reference_stretch = 1.02;
  lenient.settings.reference_stretch_factor = 5;
  EXPECT_EQ(lenient.choose({{"soft", false}})[0].substeps, 2u);
}

// A local solver's predicted substeps (the m / h^2 bound, worked out by the caller) are stated
// in its verdict, its row and a progress line; a candidate without one gets none.
TEST(IntegratorChoice, StatesTheSubstepsPredictedForALocalSolver) {
  Fixture fixture;
  ChoiceCandidate local{"stretchy", false};
  local.solves_locally = true;
  local.predicted_substeps = 4;
  local.prediction = "h <= sqrt(m / ks) = 5 ms";
  const std::vector<Choice> choices = fixture.choose({local, {"explicit", false}});
  ASSERT_EQ(choices.size(), 2u);
  EXPECT_EQ(choices[0].integrator, "stretchy");
  EXPECT_EQ(choices[0].verdict,
            "real time; the m / h^2 bound predicts 4 substeps or more (h <= sqrt(m / ks) = 5 ms)");
  EXPECT_EQ(choices[1].verdict.find("m / h^2"), std::string::npos);
  const std::vector<Row> rows = choice_rows(choices, fixture.settings);
  EXPECT_EQ(rows[0]["predicted_substeps"], 4);
  EXPECT_TRUE(rows[1]["predicted_substeps"].is_null());
  EXPECT_NE(fixture.progress.str().find("choose [1/2] stretchy: the m / h^2 bound predicts 4"),
            std::string::npos);
}

TEST(IntegratorChoice, LeavesASubstepCountWhereIterationsDoNotHelp) {
  Fixture fixture;
  const std::vector<Choice> choices = fixture.choose({{"plateau", true}});
  ASSERT_TRUE(choices[0].passed);
  EXPECT_EQ(choices[0].substeps, 64u);
  EXPECT_EQ(choices[0].iterations, 1u);
  for (const char* substeps : {"1", "2", "32"})
    EXPECT_EQ(std::count(fixture.runs.runs.begin(), fixture.runs.runs.end(),
                         std::string("plateau 0 ") + substeps),
              2)
        << substeps;
  EXPECT_NE(fixture.progress.str().find("more iterations do not lower the error"),
            std::string::npos);
}

// An error that does not change with the step is no reason to stop while the scene's mesh is
// still unstable: the error is measured first, but only an error failure counts.
TEST(IntegratorChoice, KeepsSearchingWhileOnlyTheSceneMeshIsUnstable) {
  Fixture fixture;
  fixture.spec.fixed.push_back({"scenario.rows", "40", "test"});
  fixture.spec.fixed.push_back({"scenario.cols", "40", "test"});
  fixture.base = expand_cases(fixture.spec).at(0);
  fixture.settings.error_mesh = "10x10";
  const std::vector<Choice> choices = fixture.choose({{"stiff", false}});
  ASSERT_TRUE(choices[0].passed) << choices[0].verdict;
  EXPECT_GE(choices[0].substeps, 37u);
  EXPECT_LE(choices[0].substeps, 41u) << fixture.progress.str();
}

// Once another integrator's best is cheaper than anything a bracket can hold, the bisection
// ends at its passing end, and the verdict says so.
TEST(IntegratorChoice, StopsBisectingABracketThatCannotBeatTheBest) {
  Fixture fixture;
  const std::vector<Choice> choices = fixture.choose({{"steady", false}, {"explicit", false}});
  ASSERT_EQ(choices[0].integrator, "steady");
  ASSERT_TRUE(choices[1].passed) << choices[1].verdict;
  // 64 substeps pass at 64 ms/frame; 33 or more cost at least 33, over steady's 25.
  EXPECT_EQ(choices[1].substeps, 64u);
  EXPECT_NE(choices[1].verdict.find("not refined below 64 substeps: 33 or more cost at least 33 "
                                    "ms/frame, more than steady at 1 substep"),
            std::string::npos)
      << choices[1].verdict;
  EXPECT_EQ(std::count(fixture.runs.runs.begin(), fixture.runs.runs.end(), "explicit 0 48"), 0);
}

// Where only the lower part of a bracket could beat another integrator's best, the bisection
// probes the top of that part (the cut), not the middle: the bracket (8, 16] of a method at
// 2.5 ms per substep can beat 25 ms only up to 10 substeps.
TEST(IntegratorChoice, BisectsAtTheCutBelowWhichTheBracketCouldBeatTheBest) {
  Fixture fixture;
  const std::vector<Choice> choices = fixture.choose({{"steady", false}, {"dear", false}});
  ASSERT_EQ(choices[1].integrator, "dear");
  ASSERT_TRUE(choices[1].passed) << choices[1].verdict;
  EXPECT_EQ(choices[1].substeps, 16u);
  EXPECT_NE(choices[1].verdict.find("not refined below 16 substeps: 11 or more cost at least 27.5 "
                                    "ms/frame, more than steady at 1 substep"),
            std::string::npos)
      << choices[1].verdict;
  EXPECT_EQ(std::count(fixture.runs.runs.begin(), fixture.runs.runs.end(), "dear 0 10"),
            1);  // unstable at once
  EXPECT_EQ(std::count(fixture.runs.runs.begin(), fixture.runs.runs.end(), "dear 0 12"), 0);
}

// The iterations are bisected only where they can beat another integrator's best: 16 pass at
// 48 ms/frame, so 9 or more cost at least 27, more than steady's 25.
TEST(IntegratorChoice, RefinesIterationsOnlyWhereTheyCanBeatTheBest) {
  Fixture fixture;
  const std::vector<Choice> choices = fixture.choose({{"steady", false}, {"solver", true}});
  ASSERT_EQ(choices[1].integrator, "solver");
  ASSERT_TRUE(choices[1].passed) << choices[1].verdict;
  EXPECT_EQ(choices[1].substeps, 1u);
  EXPECT_EQ(choices[1].iterations, 16u);
  EXPECT_NE(choices[1].verdict.find("not refined below 16 iterations at 1 substep: 9 or more cost "
                                    "at least 27 ms/frame, more than steady at 1 substep"),
            std::string::npos)
      << choices[1].verdict;
  EXPECT_EQ(std::count(fixture.runs.settings.begin(), fixture.runs.settings.end(), "solver 1 x 12"),
            0);
}

// One iteration is the cheapest setting at a substep count and at every larger one: once its
// first frames cost over stop_factor / 2 x the best, the walk up the substeps ends there (under
// stop_factor x the best, which a doubling step needs).
TEST(IntegratorChoice, EndsTheSubstepWalkWhereOneIterationIsOverHalfTheBudget) {
  Fixture fixture;
  const std::vector<Choice> choices = fixture.choose({{"steady", false}, {"walker", true}});
  ASSERT_EQ(choices[1].integrator, "walker");
  EXPECT_FALSE(choices[1].passed);
  EXPECT_EQ(choices[1].verdict,
            "slower than steady at 1 substep (25 ms/frame): its fastest of 5 first frames took "
            "39.6 ms (twice), over 1.5 x (stop_factor / 2); stopped at 4 substeps x 1 iteration");
  EXPECT_EQ(std::count(fixture.runs.settings.begin(), fixture.runs.settings.end(), "walker 4 x 1"),
            2);
  EXPECT_EQ(std::count(fixture.runs.settings.begin(), fixture.runs.settings.end(), "walker 8 x 1"),
            0);
}

// Before a stop or a cut, the best's first frames are measured again beside the setting: where
// the load has grown since the best was measured, that is the yardstick. Here every run after
// steady's takes twice as long: dear's 16 substeps (80 ms/frame, 72 the fastest frames: 9 to 16
// cost at least 40.5) are over steady's 25 ms/frame, not over its 45 now.
TEST(IntegratorChoice, ComparesWithTheBestsFirstFramesMeasuredBesideAStop) {
  Fixture fixture;
  fixture.settings.stop_factor = 2;
  fixture.runs.loaded_from_call =
      4;  // the reference's two fixture.runs, steady's run over T, then loaded
  const std::vector<Choice> choices = fixture.choose({{"steady", false}, {"dear", false}});
  ASSERT_EQ(choices[1].integrator, "dear");
  ASSERT_TRUE(choices[1].passed) << choices[1].verdict;
  EXPECT_EQ(choices[1].substeps, 16u);
  EXPECT_NEAR(choices[1].ms_per_frame, 80, 1e-9);
  EXPECT_NE(fixture.progress.str().find("dear 16 substeps: passes"), std::string::npos);
  // The bracket's cut too: 80 against steady's 25 would leave nothing in (8, 16]; side by side
  // (72 and 45, the fastest first frames) up to 10 substeps can still win, and 10 is probed
  // (its first frames twice: over the yardstick as stored, not beside steady's).
  EXPECT_EQ(std::count(fixture.runs.runs.begin(), fixture.runs.runs.end(), "dear 0 10"), 2);
  EXPECT_NE(choices[1].verdict.find("not refined below 16 substeps: 11 or more cost at least 49.5 "
                                    "ms/frame, more than steady at 1 substep (45 ms its first "
                                    "frames now)"),
            std::string::npos)
      << choices[1].verdict;
}

// A bisection probe that the budget stops (here: a burst of other jobs through both of its
// first-frames measurements) ends the bisection at its passing end, and the verdict says so.
TEST(IntegratorChoice, EndsABisectionThatTheBudgetStops) {
  Fixture fixture;
  fixture.runs.burst_on = "explicit 48";
  fixture.runs.bursts = 2;
  const std::vector<Choice> choices = fixture.choose({{"explicit", false}});
  ASSERT_TRUE(choices[0].passed) << choices[0].verdict;
  EXPECT_EQ(choices[0].substeps, 64u);
  EXPECT_NE(choices[0].verdict.find("not refined below 64 substeps: 48 substeps slower than "
                                    "explicit at 64 substeps (64 ms/frame): its fastest of 5 "
                                    "first frames took 432 ms (twice)"),
            std::string::npos)
      << choices[0].verdict;
  EXPECT_EQ(std::count(fixture.runs.runs.begin(), fixture.runs.runs.end(), "explicit 0 56"), 0);
}

// An error that two halvings of the step leave flat ends the search; one flat halving (an
// error saturated at the coarsest steps) does not.
TEST(IntegratorChoice, GivesUpOnlyOnAnErrorFlatOverTwoHalvings) {
  Fixture fixture;
  const std::vector<Choice> choices = fixture.choose({{"damped", false}, {"saturated", false}});
  ASSERT_EQ(choices[0].integrator, "saturated");
  EXPECT_TRUE(choices[0].passed) << choices[0].verdict;
  EXPECT_EQ(choices[0].substeps, 8u);
  EXPECT_FALSE(choices[1].passed);
  EXPECT_EQ(choices[1].verdict.rfind("converges elsewhere: error 3.02 % at 4 substeps, 3.05 % "
                                     "and 3.1 % at 2 and 4 x the step",
                                     0),
            0u)
      << choices[1].verdict;
  EXPECT_EQ(std::count(fixture.runs.runs.begin(), fixture.runs.runs.end(), "damped 0 8"), 0);
}

// The iterations parameter is the plugin's (implicit_euler's CG cap, max_iterations), searched
// up to its own maximum.
TEST(IntegratorChoice, SearchesThePluginsIterationsParameterWithinItsRange) {
  Fixture fixture;
  ChoiceCandidate capped{"iterative", true};
  capped.iterations_param = "cap";
  capped.iterations_limit = 4;  // 1 x 8 is out of range: 2 x 4 is the cheapest left
  const std::vector<Choice> choices = fixture.choose({capped});
  ASSERT_TRUE(choices[0].passed) << choices[0].verdict;
  EXPECT_EQ(choices[0].substeps, 2u);
  EXPECT_EQ(choices[0].iterations, 4u);
  EXPECT_EQ(choose_rows_parameter(choices, fixture.settings), "cap");
  EXPECT_NE(choice_table(choices, fixture.settings).find(" cap=4 "), std::string::npos);
  EXPECT_EQ(std::count(fixture.runs.runs.begin(), fixture.runs.runs.end(), "iterative 0 1"),
            3);  // 1, 2, 4
}

// A burst of other jobs that slows one measurement of the first frames does not stop a setting:
// the first frames run again before a stop.
TEST(IntegratorChoice, MeasuresTheFirstFramesAgainBeforeAStop) {
  Fixture fixture;
  fixture.runs.burst_on = "explicit 64";
  const std::vector<Choice> choices = fixture.choose({{"steady", false}, {"explicit", false}});
  ASSERT_TRUE(choices[1].passed) << choices[1].verdict;
  EXPECT_EQ(choices[1].substeps, 64u);
  // 2 short, 1 T, and 1 short beside steady's before the bracket is cut
  EXPECT_EQ(std::count(fixture.runs.runs.begin(), fixture.runs.runs.end(), "explicit 0 64"), 4);
}

// In float32 the reference integrator runs once more, at the reference's own step in float32:
// its distance from the float64 run is the floor no float32 setting can be expected below. A
// tolerance under it is refused before any probe, naming the floor and the allowed ways out;
// above it, the floor is stored and reported.
TEST(IntegratorChoice, MeasuresThePrecisionFloorAndRefusesAToleranceBelowIt) {
  Fixture fixture;
  fixture.runs.precision_floor = 0.012;
  try {
    fixture.choose({{"explicit", false}});
    ADD_FAILURE() << "a tolerance below the float32 floor was searched";
  } catch (const SweepError& error) {
    EXPECT_STREQ(error.what(),
                 "choose: float32 cannot meet the tolerance here: rk4 float32 at the reference's "
                 "step is 1.2 % of the cloth diagonal from its float64 run at T = 1 s, above "
                 "choose.error_tolerance 1 %; allowed: choose.error_tolerance above 1.2 %, "
                 "precision float64, or a shorter choose.error_duration");
  }
  EXPECT_TRUE(fixture.runs.runs.empty());  // no probe ran
  // A floor just above the tolerance is printed with the digits that tell the two apart.
  Fixture just_above;
  just_above.runs.precision_floor = 0.010009;
  try {
    just_above.choose({{"explicit", false}});
    ADD_FAILURE() << "a tolerance just below the float32 floor was searched";
  } catch (const SweepError& error) {
    EXPECT_NE(std::string(error.what())
                  .find("is 1.001 % of the cloth diagonal from its float64 "
                        "run at T = 1 s, above choose.error_tolerance 1 %"),
              std::string::npos)
        << error.what();
  }
  // The floor's run is at the reference's own step: 1 / (50 x 512) / 2 s.
  ASSERT_EQ(fixture.runs.precision_floor_runs.size(), 1u);
  EXPECT_EQ(fixture.runs.precision_floor_runs[0], "float32 " + host::format_number(1.0 / 51200));

  Fixture below;
  below.runs.precision_floor = 0.004;
  EXPECT_TRUE(below.choose({{"explicit", false}}).at(0).passed);
  Row floor;
  for (const Row& row : below.store.rows())
    if (row["kind"] == "precision_floor") floor = row;
  ASSERT_TRUE(floor.is_object());
  EXPECT_DOUBLE_EQ(floor["precision_floor"].get<double>(), 0.004);
  EXPECT_EQ(precision_floor_line(floor), "float32 floor: rk4 float32 at dt " +
                                             host::format_number(1.0 / 51200) +
                                             " s is 0.4 % of the diagonal from its float64 run");
  EXPECT_NE(below.progress.str().find("choose: float32 floor 0.4 % of the diagonal"),
            std::string::npos)
      << below.progress.str();
  floor.erase("precision_floor");
  EXPECT_THROW(precision_floor_line(floor), SweepError);

  // A float64 search has no floor to measure: nothing runs.
  Fixture in_float64;
  in_float64.spec.fixed.push_back({"precision", "float64", "test"});
  in_float64.base = expand_cases(in_float64.spec).at(0);
  in_float64.runs.precision_floor = 0.5;
  EXPECT_EQ(compute_precision_floor(in_float64.spec, in_float64.base, 1e-3, Trajectory{},
                                    std::ref(in_float64.runs), in_float64.store),
            0.0);
  EXPECT_TRUE(in_float64.runs.precision_floor_runs.empty());
}

TEST(IntegratorChoice, RefusesAnUnconvergedReference) {
  Fixture fixture;
  fixture.runs.reference_gap =
      0.05;  // the two reference fixture.runs differ by 5 % of the diagonal
  EXPECT_THROW(fixture.choose({{"explicit", false}}), SweepError);
  EXPECT_EQ(fixture.runs.calls, 2);  // nothing judged against it
}

// On a scene with colliders, a probe whose particles lie deeper in a collider than its
// thickness fails with both figures in its verdict (tunnelling), and a shallower one passes.
TEST(IntegratorChoice, FailsAProbeThatPenetratesDeeperThanTheColliderThickness) {
  Fixture fixture;
  fixture.runs.colliders = 2;
  ChoiceCandidate tunneller{"tunneller", false};
  tunneller.resolves_contacts = true;
  ChoiceCandidate steady{"steady", false};
  steady.resolves_contacts = true;
  const std::vector<Choice> choices = fixture.choose({steady, tunneller});
  ASSERT_EQ(choices.size(), 2u);
  const auto found = [&](const std::string& id) {
    return *std::find_if(choices.begin(), choices.end(),
                         [&](const Choice& choice) { return choice.integrator == id; });
  };
  const Choice tunnelling = found("tunneller");
  ASSERT_TRUE(tunnelling.passed) << tunnelling.verdict;
  EXPECT_EQ(tunnelling.substeps, 4u);  // 0.04 / 4 = the thickness; 2 substeps: 0.02 m
  EXPECT_LE(tunnelling.run->max_penetration(), 0.01);
  EXPECT_EQ(tunnelling.run->collider_thickness(), 0.01);
  EXPECT_NE(fixture.progress.str().find("tunneller 2 substeps: a particle 0.01 m past the "
                                        "thickness of a collider (deepest penetration 0.02 m)"),
            std::string::npos)
      << fixture.progress.str();
  const Choice shallow = found("steady");
  ASSERT_TRUE(shallow.passed) << shallow.verdict;
  EXPECT_EQ(shallow.substeps, 1u);
  EXPECT_EQ(shallow.run->max_penetration(), 0.002);
  EXPECT_NE(choice_table(choices, fixture.settings).find("0.002 m"), std::string::npos);
  const std::vector<Row> ranked = choice_rows(choices, fixture.settings);
  EXPECT_EQ(ranked[0]["collider_thickness"], 0.01);
  EXPECT_TRUE(ranked[0]["max_penetration"].is_number());
}

// Each particle against the thickness of the collider it lies in: deeper than the thinnest
// collider's thickness but within its own collider's band passes (judged against the thinnest,
// "cushioned" would fail at every setting), and so does a depth past the thickness within the
// rounding tolerance.
TEST(IntegratorChoice, JudgesThePenetrationAgainstItsOwnCollidersThickness) {
  Fixture fixture;
  fixture.runs.colliders = 2;
  std::vector<ChoiceCandidate> candidates = {{"cushioned", false}, {"rounded", false}};
  for (ChoiceCandidate& candidate : candidates) candidate.resolves_contacts = true;
  const std::vector<Choice> choices = fixture.choose(candidates);
  ASSERT_EQ(choices.size(), 2u);
  for (const Choice& choice : choices) {
    ASSERT_TRUE(choice.passed) << choice.integrator << ": " << choice.verdict;
    EXPECT_EQ(choice.substeps, 1u) << choice.integrator;
  }
  const Choice& cushioned = choices[0].integrator == "cushioned" ? choices[0] : choices[1];
  EXPECT_GT(cushioned.run->max_penetration(), cushioned.run->collider_thickness());
}

// Without colliders the penetration judges nothing and the rows leave it empty.
TEST(IntegratorChoice, LeavesThePenetrationOutOnASceneWithoutColliders) {
  Fixture fixture;
  const std::vector<Choice> choices = fixture.choose({{"tunneller", false}});
  ASSERT_TRUE(choices.at(0).passed) << choices[0].verdict;
  EXPECT_EQ(choices[0].substeps, 1u);
  EXPECT_TRUE(choice_rows(choices, fixture.settings).at(0)["max_penetration"].is_null());
}

// A candidate that lacks a trait the scene needs is listed as refused, with what is missing,
// and never run; the others are searched as usual.
TEST(IntegratorChoice, RefusesCandidatesThatCannotMoveAttachmentsOrResolveContacts) {
  Fixture fixture;
  fixture.runs.attached_particles = 20;
  fixture.runs.colliders = 3;
  ChoiceCandidate able{"steady", false};
  able.moves_attachments = able.resolves_contacts = true;
  ChoiceCandidate no_contacts{"explicit", false};
  no_contacts.moves_attachments = true;
  const ChoiceCandidate neither{"stretchy", false};
  const std::vector<Choice> choices = fixture.choose({no_contacts, neither, able});
  ASSERT_EQ(choices.size(), 3u);
  EXPECT_EQ(choices[0].integrator, "steady");
  EXPECT_TRUE(choices[0].passed);
  EXPECT_EQ(choices[1].integrator, "explicit");
  EXPECT_FALSE(choices[1].passed);
  EXPECT_EQ(choices[1].verdict,
            "refused: does not resolve contacts (no CLOTHLAB_TRAIT_RESOLVES_CONTACTS), which the "
            "scene's 3 collider(s) need");
  EXPECT_EQ(choices[2].verdict,
            "refused: does not move attachments (no CLOTHLAB_TRAIT_MOVES_ATTACHMENTS), which the "
            "scene's 20 attached particle(s) need; does not resolve contacts (no "
            "CLOTHLAB_TRAIT_RESOLVES_CONTACTS), which the scene's 3 collider(s) need");
  for (const std::string& run : fixture.runs.runs) EXPECT_EQ(run.rfind("steady ", 0), 0u) << run;
  EXPECT_NE(fixture.progress.str().find("choose [1/3] explicit: refused: "), std::string::npos);
  EXPECT_NE(choice_table(choices, fixture.settings).find("refused: does not resolve contacts"),
            std::string::npos);
}

}  // namespace
}  // namespace clothlab::sweep
