// "Which integrator for my game": for one scene (scenario x mesh x material x frame rate), the
// cheapest setting of each integrator that is stable, keeps the cloth's stretch under a limit
// and its positions at T within a tolerance of a converged reference.
//
// Per integrator, a candidate (substeps, iterations) runs T at the scene's mesh; it passes when
//   - the run is stable by the monitor (finite, energy, divergence-sized stretch) and its
//     robust stretch over the run is at most stretch_limit: the largest structural (warp /
//     weft) spring stretch with the springs within two spacings of a pin left out (a pin is a
//     point load whose springs stretch more the finer the mesh: Cloth::Stretch), and
//   - the RMS position error at T over the cloth diagonal, against the reference, is at most
//     error_tolerance, and the run's robust strain (stretch - 1) over that run is at most
//     reference_stretch_factor x the reference's own (a method may not sag like a softer
//     cloth). Both are measured on error_mesh (a smaller mesh where the scene's own would make
//     the reference too expensive; the rows say which) with the same setting.
// On a scene with colliders, a run at the scene's mesh also fails when a particle lay deeper
// inside a collider's surface than that collider's thickness (by over 1e-6 m) after a step (it
// went through the band the contacts keep clear: tunnelling); the rows carry the largest
// penetration.
// A candidate that lacks what the scene needs (its traits do not declare moving attachments or
// resolving contacts, and the reference's run had attached particles or colliders) is not
// searched: its row says "refused: ..." and what is missing.
// The reference is compute_reference (work_precision.hpp): reference_integrator in float64 at
// dt = 1 / (frame_rate reference_substeps), checked against dt / 2; its estimated own error is
// stored with it. When the reference's two runs differ by more than the tolerance it is not
// converged at that T (the flag's wind makes its motion chaotic within ~0.5 s): SweepError.
// Search: substeps double from 1 until a candidate passes, then bisect down to the fewest that
// pass (criteria assumed monotone in the step). For an integrator with an `iterations`
// parameter, each substep count gets the fewest iterations (doubling, then bisection) that
// pass, and substep counts grow until the cost per frame stops improving. Cost = median wall
// time per frame of the run at the scene's mesh. A probe's runs go cheapest first, and a
// setting that fails one needs none of the later ones: its first 5 frames at the scene's mesh
// (only once a best exists, below), the error run (error mesh, error T), the run over T. The
// runs at the scene's mesh carry stability.stretch_stop = stretch_limit: the stretch over a run
// only grows, so a run ends at the first check past the limit, failing the probe there.
// Early stops, each reported in the probe's row and the integrator's verdict. They rest on one
// bound: a frame's cost per substep (and per iteration) does not grow with their number (cost =
// a + b n, a >= 0: per-frame and per-step overheads), so below a measured n, m costs at least
// cost(n) m / n; above it, more.
//   - cost budget: once some setting of any integrator passed (the best so far), a setting n
//     that tops the bracket (f, n] of the search along its parameter (f: the largest value
//     known to fail below n, 0 if none) is "slower than <best>", stopped, when nothing in the
//     bracket can cost within stop_factor / 2 of the best's ms/frame: its first 5 frames
//     (the fastest of them, p10, as other jobs only slow frames down; measured twice before a
//     stop) x (f + 1) / n exceed stop_factor / 2 x the best's (the larger of its ms/frame when
//     it passed and its first frames run again beside the setting's: a load that grew since
//     the best was measured stops nothing). Above n everything costs more,
//     and up to f everything fails: a stopped integrator's cheapest passing setting, if any,
//     costs over stop_factor / 2 x the best, so stop_factor >= 2 never loses the winner (up to
//     timing noise) and stop_factor trades only how far from the best the rows are worked out.
//     At a doubling step (f = n / 2) the limit is about stop_factor x the best; at one
//     iteration (f = 0, the cheapest setting at that substep count and every larger one) it is
//     stop_factor / 2 x, and the walk up the substeps ends there. The error run and the run
//     over T are also killed past 2 x stop_factor x the best's stepping time over T (times the
//     run's share of T) plus a start-up allowance. A stop ends the search (an iterations
//     method's: that substep count, and the search when it was at 1 iteration); a stop in a
//     bisection ends the bisection at its passing end, "not refined".
//   - refinement only where a row can win: a bisection bracket (f, p] can beat another
//     integrator's best only up to its cut, n = best x p / cost(p). Where the cut is below the
//     middle, the bisection probes the cut (failing there, nothing left can win); where it is
//     not above f, the bisection ends: p is returned and the verdict says "not refined". A cut
//     below the middle is also taken from p's and the best's first frames run side by side;
//     the larger cut stands. Along
//     substeps and along iterations alike. stop_factor 0: no budget and no such ends.
//   - a probe past probe_timeout ends the integrator's search ("too slow");
//   - an error that stays above the tolerance while two halvings of the step change it by
//     less than 10 % each ends the search (the method converges to another solution, e.g. other
//     damping: "converges elsewhere"); one that changes by less than 10 % when the iterations
//     double ends that substep count (the solver has converged there).
#pragma once

#include <clothlab/host/run_summary.hpp>
#include <cmath>
#include <cstdint>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "clothlab/sweep/case_spec.hpp"
#include "clothlab/sweep/results_store.hpp"
#include "clothlab/sweep/work_precision.hpp"

namespace clothlab::sweep {

struct ChoiceSettings {
  double frame_rate = 60.0;     // Hz
  double duration = 1.0;        // T of the runs judged for stability, stretch and cost, s
  double error_duration = 0.0;  // T of the error; 0: duration (the flag needs it shorter)
  double stretch_limit = 1.10;  // x rest length, the robust figure (header)
  // A method's robust strain over the error run at most this x the reference's (header).
  double reference_stretch_factor = 1.5;
  double error_tolerance = 0.01;  // RMS position error / cloth diagonal
  uint32_t max_substeps = 4096;
  uint32_t max_iterations = 32;  // and at most the parameter's own maximum
  // Wall-clock limit of one probe run (s): a setting that slow is no answer for a game, and
  // more substeps or iterations only cost more, so the integrator's search stops there.
  double probe_timeout_s = 60.0;
  // A probe slower than this multiple of the best passing setting so far is stopped (header).
  double stop_factor = 3.0;
  uint32_t reference_substeps = 512;  // reference dt = 1 / (frame_rate reference_substeps)
  std::string reference_integrator = "rk4";
  std::string error_mesh;  // "ROWSxCOLS"; empty: the scene's mesh
};

struct ChoiceCandidate {
  std::string integrator;
  bool has_iterations = false;
  // A method with its own substeps parameter (xpbd) gets 1 there, so that the host's substeps
  // per frame are its only substeps.
  bool has_own_substeps = false;
  // The parameters' names (the plugin's clothlab.integrator-traits/1: implicit_euler's is its
  // CG cap, max_iterations), and the most iterations the parameter allows.
  std::string iterations_param = "iterations";
  std::string substeps_param = "substeps";
  uint32_t iterations_limit = UINT32_MAX;
  // A local solver's (CLOTHLAB_TRAIT_LOCAL_SOLVES) fewest substeps per frame by the m / h^2
  // bound (analysis/local_solve_bound.hpp) and how it follows ("h <= sqrt(m / ks) = ... s"),
  // stated in its verdict beside what the search measures; 0: no prediction.
  bool solves_locally = false;
  uint32_t predicted_substeps = 0;
  std::string prediction = {};
  // Its clothlab.integrator-traits/1 flags CLOTHLAB_TRAIT_MOVES_ATTACHMENTS and
  // CLOTHLAB_TRAIT_RESOLVES_CONTACTS: a scene with attachments or colliders needs them.
  bool moves_attachments = false;
  bool resolves_contacts = false;
};

struct Choice {
  std::string integrator;
  bool passed = false;
  uint32_t substeps = 0;
  uint32_t iterations = 0;       // 0: the method has none
  std::string iterations_param;  // the parameter they set ("iterations", "max_iterations")
  double ms_per_frame = 0, error = 0;
  // The figures of the passing setting's run over T at the scene's mesh (stretch, contacts).
  std::optional<host::RunSummary> run;
  uint32_t predicted_substeps = 0;  // ChoiceCandidate's
  // "real time", "slower than real time" or why nothing passed ("slower than <best> ...
  // (stopped at ...)", "too slow: ...", "converges elsewhere: ...", "no setting passed ...")
  std::string verdict;
  int probes = 0;
};

// `base`: the scene's case (its settings without frame_rate / substeps / dt, duration T).
// `scene` is written to every row ("scenario=flag;mesh=200x200;material=cotton;..."); rows go
// to the store (reference, probe), the returned choices are ranked: passing ones by cost, then
// the rest. The reference's two runs go through reference_runner (a TrajectoryCache in
// clothlab --choose), the probes through runner. Progress on `progress`: a line when the
// reference starts and when it is done, one per probe ("choose [2/7] euler 1024 substeps:
// passes (<ms> ms/frame) [<elapsed>]", elapsed since the start).
std::vector<Choice> choose_integrators(const SweepSpec& spec, const CaseSpec& base,
                                       const std::vector<ChoiceCandidate>& candidates,
                                       const ChoiceSettings& settings,
                                       const TrajectoryRunner& runner,
                                       const TrajectoryRunner& reference_runner,
                                       ResultsStore& store, std::ostream& progress);

// The ranked table as rows (integrator, substeps, iterations, ms_per_frame, error, max_stretch,
// verdict, ...) and as a fixed-width text table.
std::vector<Row> choice_rows(const std::vector<Choice>& choices, const ChoiceSettings& settings);
std::string choice_table(const std::vector<Choice>& choices, const ChoiceSettings& settings);

// The report's line on the reference, from its row (compute_reference): integrator, dt,
// estimated own error and its stretch figures over the run. A figure the row lacks is a
// SweepError naming it, never printed as 0.
std::string reference_line(const Row& reference);

// The report's line on the run's precision floor (compute_precision_floor's row): "float32
// floor: rk4 float32 at dt ... s is ... % of the diagonal from its float64 run". A figure the
// row lacks is a SweepError naming it.
std::string precision_floor_line(const Row& floor);

}  // namespace clothlab::sweep
