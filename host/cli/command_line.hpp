// The clothlab command line (Boost.Program_options).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "settings.hpp"

namespace clothlab::cli {

struct CommandLine {
  bool help = false;
  bool list_plugins = false;
  bool quiet = false;
  std::optional<std::string> config_file;
  std::vector<std::string> plugin_paths;
  std::optional<std::string> json_file;
  std::optional<std::string> state_file;
  std::optional<std::string> energy_file;  // energy over time as CSV
  bool find_max_dt = false;                // search the largest stable dt instead of one run
  bool choose = false;  // which integrator for this scene and frame rate (choose_mode.hpp)
  bool resume = false;  // sweep: skip cases already in the results
  // Sweep: results folder (files <out>/<sweep name>.csv/.json) instead of sweep.output.
  std::optional<std::string> out_folder;
  std::optional<std::string> shard;  // sweep: "K/N", run only shard K of N
  bool slurm = false;                // sweep: submit as a Slurm job array
  bool no_wait = false;              // --slurm: return once submitted
  bool keys_markdown = false;        // print the key table as Markdown (docs/reference)
  bool dry_run = false;  // check everything a run checks before its first step, then stop
  // --integrator, --dt, ... and --set key=value, in command-line order.
  std::vector<Setting> settings;
};

// Throws InputError for an unknown option, a missing value, a --set without '=' or
// both --steps and --duration.
CommandLine parse_command_line(int argc, const char* const argv[]);

std::string usage_text();

// `clothlab merge [--help] OUTPUT...`.
struct MergeCommandLine {
  bool help = false;
  std::vector<std::string> outputs;  // sweep outputs whose shards are joined
};

// argv[0] is "merge". Throws InputError for an unknown option, or no OUTPUT without --help.
MergeCommandLine parse_merge_command_line(int argc, const char* const argv[]);

std::string merge_usage_text();

}  // namespace clothlab::cli
