#include "clothlab/sweep/integrator_choice.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "clothlab/sweep/sweep_error.hpp"
#include "sweep_test_support.hpp"

namespace clothlab::sweep {
namespace {

using testing::ScratchFolder;

// Fake integrators with known limits, on one particle of a cloth whose diagonal is 1 (so the
// error is the particle's x). Costs: 1 ms per substep plus 0.1 ms per iteration.
//   explicit:  unstable below 37 substeps; error 0.5 / substeps (1 % from 50 substeps)
//   stretchy:  always stable, stretch 1 + 0.5 / substeps (10 % from 5 substeps)
//   iterative: passes when substeps x iterations >= 8; cheapest is 1 substep x 8 iterations
//   never:     always unstable
// The reference (rk4, float64) sits at x = 0 with a difference `reference_gap` between its two
// steps.
struct FakeRuns {
  double reference_gap = 0.0;
  int calls = 0;
  Trajectory operator()(const CaseSpec& c) {
    ++calls;
    Trajectory run;
    run.diagonal = 1.0;
    if (c.precision == "float64") {
      run.positions = {c.dt > 3e-5 ? reference_gap : 0.0, 0, 0};  // the coarser of the two
      return run;
    }
    const double substeps = std::stod(c.setting("substeps"));
    const std::string text = c.setting("integrator.iterations");
    const double iterations = text.empty() ? 0.0 : std::stod(text);
    run.ms_per_frame = substeps * (1.0 + 0.1 * iterations);
    run.max_stretch = 1.01;
    double error = 0.001;
    const bool unstable = (c.integrator == "explicit" && substeps < 37) ||
                          (c.integrator == "iterative" && substeps * iterations < 8) ||
                          c.integrator == "never";
    if (c.integrator == "explicit") error = 0.5 / substeps;
    if (c.integrator == "stretchy") run.max_stretch = 1.0 + 0.5 / substeps;
    if (unstable) {
      run.verdict.status = CaseStatus::Unstable;
      run.verdict.reason = "energy";
    }
    run.positions = {error, 0, 0};
    return run;
  }
};

struct Fixture {
  SweepSpec spec;
  CaseSpec base;
  ChoiceSettings settings;
  Fixture() {
    spec.source = "test";
    spec.fixed = {{"scenario.plugin", "flag", "test"}, {"duration", "1", "test"}};
    base = expand_cases(spec).at(0);
    settings.frame_rate = 50;  // reference dt 1 / (50 x 512) = 39 us, its check 78 us
    settings.max_substeps = 256;
  }
};

TEST(IntegratorChoice, FindsEachCheapestPassingSettingAndRanksByCost) {
  ScratchFolder folder;
  ResultsStore store(folder.path() / "choose", false);
  Fixture fixture;
  FakeRuns runs;
  std::ostringstream progress;
  const std::vector<Choice> choices = choose_integrators(
      fixture.spec, fixture.base,
      {{"never", false}, {"explicit", false}, {"stretchy", false}, {"iterative", true}},
      fixture.settings, std::ref(runs), store, progress);
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
  EXPECT_NE(progress.str().find("choose: explicit 64 substeps: passes"), std::string::npos);
  // One reference row, with its estimated error; rows for every probe.
  int references = 0, probes = 0;
  for (const Row& row : store.rows()) {
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

TEST(IntegratorChoice, RefusesAnUnconvergedReference) {
  ScratchFolder folder;
  ResultsStore store(folder.path() / "choose", false);
  Fixture fixture;
  FakeRuns runs;
  runs.reference_gap = 0.05;  // the two reference runs differ by 5 % of the diagonal
  std::ostringstream progress;
  EXPECT_THROW(choose_integrators(fixture.spec, fixture.base, {{"explicit", false}},
                                  fixture.settings, std::ref(runs), store, progress),
               SweepError);
  EXPECT_EQ(runs.calls, 2);  // nothing judged against it
}

}  // namespace
}  // namespace clothlab::sweep
