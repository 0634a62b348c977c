// `clothlab --config sweep.yaml`: a config with a `sweep:` section runs its matrix through
// clothlab_sweep in the mode it names (run, work-precision, stability). Every case is one
// Simulation, run in the sweep's worker child (case_worker.hpp), so a crash is a failed row.
#pragma once

#include <clothlab/host/plugin_search_path.hpp>
#include <clothlab/sweep/work_precision.hpp>
#include <filesystem>
#include <optional>
#include <ostream>
#include <vector>

#include "case_worker.hpp"
#include "settings.hpp"

namespace clothlab::cli {

struct SweepRequest {
  std::filesystem::path config_file;
  // Command-line settings: added to the sweep's fixed settings (matrix axes still win).
  std::vector<Setting> overrides;
  std::optional<std::filesystem::path> out_folder;  // replaces sweep.output's folder
  bool resume = false;
  std::optional<std::string> shard;  // "K/N" as given
  bool slurm = false;
  bool wait = true;      // --slurm without --no-wait
  bool dry_run = false;  // check every case and the outputs, run none, submit nothing
  std::vector<std::string> plugin_paths;  // --plugin-path entries, passed on to Slurm tasks
};

// One case run to its end in the worker, with its final positions: the trajectory runner
// of the work-precision and choose drivers.
sweep::Trajectory run_sweep_trajectory(const sweep::CaseSpec& c, CaseWorker& worker);

// A plugin file's identity for fingerprints and caches: where it was found, its size and
// content hash.
std::string plugin_identity(const host::PluginSearchPath& search_path, const std::string& id);
// The running host's identity, as a plugin file's: its executable's size and content hash.
std::string host_identity();

// Runs the sweep (with dry_run: checks it), prints a summary to out. Throws InputError for a bad
// sweep file or results that cannot be resumed or written. Unstable and failed cases are results,
// not errors.
void run_sweep_file(const SweepRequest& request, const host::PluginSearchPath& search_path,
                    std::ostream& out);

// `clothlab merge OUTPUT...`: merges each output's shard stores into its CSV/JSON/SQLite.
// Throws InputError when a shard is missing, incomplete or of another sweep.
void merge_sweep_outputs(const std::vector<std::string>& outputs, std::ostream& out);

}  // namespace clothlab::cli
