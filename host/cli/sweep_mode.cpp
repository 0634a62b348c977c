#include "sweep_mode.hpp"

#include <algorithm>
#include <clothlab/host/errors.hpp>
#include <clothlab/host/param_text.hpp>
#include <clothlab/io/atomic_file.hpp>
#include <clothlab/sweep/fingerprint.hpp>
#include <clothlab/sweep/shard.hpp>
#include <clothlab/sweep/stability_search.hpp>
#include <clothlab/sweep/sweep_error.hpp>
#include <clothlab/sweep/sweep_runner.hpp>
#include <clothlab/sweep/work_precision.hpp>
#include <cmath>
#include <iostream>
#include <limits>
#include <utility>

#include "case_execution.hpp"
#include "case_worker.hpp"
#include "dry_run.hpp"
#include "isolation.hpp"
#include "last_setting.hpp"
#include "resident_plugins.hpp"
#include "run_config.hpp"
#include "simulation.hpp"
#include "slurm_sweep.hpp"
#include "sweep_file.hpp"

namespace clothlab::cli {

namespace {

// The verdict part of a case result from a run's summary.
sweep::CaseResult verdict_of(const host::RunSummary& run) {
  sweep::CaseResult result;
  if (!run.stable) {
    result.status = sweep::CaseStatus::Unstable;
    result.fail_step = run.failed_step.value_or(0);
    result.check = run.failed_check.value_or("");
    result.reason = run.verdict;
  }
  return result;
}

sweep::CaseResult run_row(const sweep::CaseSpec& c, CaseWorker& worker) {
  const host::RunSummary run = worker.run(c).summary;
  sweep::CaseResult result = verdict_of(run);
  result.metrics = {{"steps", static_cast<double>(run.steps)},
                    {"sim_time_s", run.sim_time_s},
                    {"wall_time_s", run.wall_time_s},
                    {"ms_per_step", run.ms_per_step.median},
                    {"ms_per_step_p90", run.ms_per_step.p90},
                    {"force_evals", static_cast<double>(run.force_evals)},
                    {"springs_per_second", run.springs_per_second},
                    {"real_time_factor", run.real_time_factor},
                    {"threads", static_cast<double>(run.threads)}};
  // The warp/weft stretch over the run: its maximum and the robust figures beside it (a
  // diverged run's are not finite and left out here).
  run.visit_stretch_over_run([&](const char* figure, double value) {
    if (std::isfinite(value)) result.metrics.emplace_back(figure, value);
  });
  result.notes = {{"verdict", run.verdict}};
  return result;
}

}  // namespace

sweep::Trajectory run_sweep_trajectory(const sweep::CaseSpec& c, CaseWorker& worker) {
  CaseRun run = worker.run(c, true);
  const sweep::CaseResult verdict = verdict_of(run.summary);
  return {std::move(run.positions), run.diagonal, std::move(run.summary), verdict};
}

namespace {

sweep::DtPrediction predict_row(const sweep::CaseSpec& c, CaseWorker& worker) {
  const nlohmann::json prediction = worker.predict(c);
  sweep::DtPrediction result;
  result.dt_max = prediction["dt_max"].is_number() ? prediction["dt_max"].get<double>()
                                                   : std::numeric_limits<double>::infinity();
  result.omega_max = prediction["omega_max"].get<double>();
  result.dominant_eigenvalue = {prediction["dominant_re"].get<double>(),
                                prediction["dominant_im"].get<double>()};
  return result;
}

// Every case goes through the checks of a single run (its settings, then its plugins and
// parameter values) before the first one runs: a sweep with bad input does nothing and
// exits 1. Loading plugins is plugin code, so it happens in one child for all cases.
void check_every_case(const std::vector<sweep::CaseSpec>& cases,
                      const host::PluginSearchPath& search_path) {
  std::vector<RunConfig> configs;
  for (const sweep::CaseSpec& c : cases) configs.push_back(resolve_run_config(c.settings));
  if (configs.empty()) return;
  try {
    run_isolated(
        [&] {
          ResidentPlugins resident;
          for (size_t i = 0; i < configs.size(); ++i) {
            try {
              resident.load(configs[i], search_path);
            } catch (const std::exception& error) {
              throw host::InputError(std::string(error.what()) + " (sweep case " + cases[i].key +
                                     ")");
            }
          }
          return nlohmann::json();
        },
        configs.front().timeout_s);
  } catch (const host::InputError&) {
    throw;
  } catch (const std::exception& error) {
    throw host::PluginError(CLOTHLAB_ERROR_INVALID_ARGUMENT,
                            "checking the sweep's cases: " + std::string(error.what()));
  }
}

// The reference of a work-precision sweep is loaded like a case's integrator, in float64, and
// a failure is reported at work_precision.reference_integrator, not in the first case's run.
void check_reference_integrator(const sweep::SweepSpec& spec,
                                const std::vector<sweep::CaseSpec>& cases,
                                const host::PluginSearchPath& search_path) {
  const std::vector<std::string>& own = spec.work_precision.self_reference;
  const auto referenced = std::find_if(cases.begin(), cases.end(), [&](const auto& c) {
    return std::find(own.begin(), own.end(), c.integrator) == own.end();
  });
  if (referenced == cases.end()) return;
  RunConfig reference = resolve_run_config(referenced->settings);
  reference.integrator = spec.work_precision.reference_integrator;
  reference.integrator_source = where_set(spec.fixed, "work_precision.reference_integrator");
  reference.integrator_params.clear();
  reference.float64 = true;
  check_plugins(reference, search_path);
}

}  // namespace

// A plugin file's identity for the fingerprint: where it was found, its size and content hash.
std::string plugin_identity(const host::PluginSearchPath& search_path, const std::string& id) {
  const std::filesystem::path path = search_path.resolve(id);
  std::error_code error;
  const auto size = std::filesystem::file_size(path, error);
  if (error) throw host::PluginLoadError("plugin " + path.string() + ": " + error.message());
  return path.string() + " size " + std::to_string(size) + " fnv1a " +
         sweep::file_hash(path.string());
}

std::string host_identity() {
  const std::filesystem::path executable = "/proc/self/exe";
  return "clothlab size " + std::to_string(std::filesystem::file_size(executable)) + " fnv1a " +
         sweep::file_hash(executable.string());
}

void run_sweep_file(const SweepRequest& request, const host::PluginSearchPath& search_path,
                    std::ostream& out) {
  try {
    sweep::SweepSpec spec = load_sweep(request.config_file, request.overrides);
    if (request.out_folder) spec.output = *request.out_folder / spec.output.filename();
    const std::vector<sweep::CaseSpec> all_cases = sweep::expand_cases(spec);
    if (spec.mode == sweep::SweepMode::WorkPrecision)
      sweep::check_work_precision_cases(spec, all_cases);
    check_every_case(all_cases, search_path);
    if (spec.mode == sweep::SweepMode::WorkPrecision)
      check_reference_integrator(spec, all_cases, search_path);
    const sweep::Fingerprint fingerprint = sweep::sweep_fingerprint(
        spec, [&](const std::string& id) { return plugin_identity(search_path, id); });
    if (request.shard) (void)sweep::parse_shard(*request.shard, "--shard");
    if (request.dry_run) {
      check_creatable_folder(spec.output.parent_path(), "sweep.output");
      out << "dry run: sweep " << spec.name << " (" << sweep::to_string(spec.mode)
          << "): " << all_cases.size() << " cases checked"
          << (request.slurm ? ", nothing submitted to Slurm" : ", none run") << "\n";
      return;
    }
    if (request.slurm) {
      run_sweep_on_slurm(request, spec, all_cases.size(), fingerprint, out);
      return;
    }
    std::optional<sweep::Shard> shard;
    if (request.shard) shard = sweep::parse_shard(*request.shard, "--shard");
    // A reference, not a copy: each worker's fork (the first, and one after each crash or
    // timeout) copies the page tables of all the memory the parent holds.
    const std::vector<sweep::CaseSpec> shard_part =
        shard ? sweep::shard_cases(all_cases, *shard) : std::vector<sweep::CaseSpec>{};
    const std::vector<sweep::CaseSpec>& cases = shard ? shard_part : all_cases;

    sweep::ResultsStore store(shard ? sweep::shard_base(spec.output, *shard) : spec.output,
                              request.resume, fingerprint);
    // An export that cannot be written is found before the first case runs.
    if (!shard)
      for (const auto& path : {store.csv_path(), store.json_path()}) io::check_output_path(path);
    store.set_metadata({{"name", spec.name},
                        {"mode", sweep::to_string(spec.mode)},
                        {"config", request.config_file.string()},
                        {"cases", all_cases.size()}});
    const bool terminal = sweep::stderr_is_terminal();
    CaseWorker worker(search_path);
    std::string counts;
    if (spec.mode == sweep::SweepMode::Run) {
      const auto done = std::count_if(cases.begin(), cases.end(),
                                      [&](const auto& c) { return store.contains(c.key); });
      sweep::Progress progress(cases.size(), static_cast<std::size_t>(done), std::cerr, terminal);
      const sweep::SweepSummary summary = sweep::run_sweep(
          cases, [&](const sweep::CaseSpec& c) { return run_row(c, worker); }, store, &progress);
      counts = std::to_string(summary.total) + " cases: " + std::to_string(summary.stable) +
               " stable, " + std::to_string(summary.unstable) + " unstable, " +
               std::to_string(summary.failed) + " failed, " + std::to_string(summary.skipped) +
               " already done";
    } else if (spec.mode == sweep::SweepMode::WorkPrecision) {
      sweep::Progress progress(sweep::work_precision_units(spec, cases), 0, std::cerr, terminal);
      const sweep::WorkPrecisionSummary summary = sweep::run_work_precision(
          spec, cases, [&](const sweep::CaseSpec& c) { return run_sweep_trajectory(c, worker); },
          store, &progress);
      counts = std::to_string(summary.references) + " references, " + std::to_string(summary.runs) +
               " ladder runs, " + std::to_string(summary.skipped) + " already done";
    } else {
      sweep::Progress progress(cases.size(), 0, std::cerr, terminal);
      const sweep::StabilitySummary summary = sweep::run_stability_search(
          spec, cases, [&](const sweep::CaseSpec& c) { return run_row(c, worker); },
          [&](const sweep::CaseSpec& c) { return predict_row(c, worker); }, store, &progress);
      counts = std::to_string(summary.searched) + " searched, " + std::to_string(summary.skipped) +
               " already done";
    }
    store.mark_complete();
    if (shard) {
      out << "sweep " << spec.name << " (" << sweep::to_string(spec.mode) << ") shard "
          << shard->index << "/" << shard->count << ": " << counts
          << "\n  results: " << store.database_path().string() << " (join the shards with "
          << "clothlab merge " << spec.output.string() << ")\n";
      return;
    }
    store.write_exports();
    out << "sweep " << spec.name << " (" << sweep::to_string(spec.mode) << "): " << counts
        << "\n  results: " << store.csv_path().string() << ", " << store.json_path().string()
        << " (store " << store.database_path().string() << ")\n";
  } catch (const sweep::SweepError& error) {
    throw host::InputError(error.what());
  } catch (const std::filesystem::filesystem_error& error) {
    throw host::InputError(error.what());
  }
}

void merge_sweep_outputs(const std::vector<std::string>& outputs, std::ostream& out) {
  try {
    for (const std::string& output : outputs) {
      const sweep::MergeSummary merged = sweep::merge_shards(output);
      out << "merged " << merged.shards << " shards of " << output << ": " << merged.rows
          << " rows\n  results: " << output << ".csv, " << output << ".json\n";
    }
  } catch (const sweep::SweepError& error) {
    throw host::InputError(error.what());
  } catch (const std::filesystem::filesystem_error& error) {
    throw host::InputError(error.what());
  }
}

}  // namespace clothlab::cli
