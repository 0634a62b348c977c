// A sweep described in YAML: a single-run config (its keys are the fixed settings of every
// case) plus a `sweep:` section with the matrix. Every key but the matrix is a row of the one
// key table (clothlab --help lists them); host/cli/sweep_file.cpp reads the file.
//
//   integrator: {damping: 0.5}         # fixed settings, same keys as a single run
//   scenario: {mass: 100}
//   duration: 2.0                      # or steps: N
//   stability: {interval: 10, max_stretch: 5, energy_margin: 1}   # every case's monitor
//   work_precision: {reference_integrator: rk4, refinement: 32, dt_start: 0.004, levels: 6,
//                    self_reference: [verlet]}
//   find_max_dt: {dt_min: 1e-6, dt_max: 0.05, tolerance: 0.02, growth: 2, max_evaluations: 40}
//   sweep:
//     name: seed-2016-matrix
//     mode: run                        # run | work-precision | stability
//     output: results/seed-2016-matrix # .sqlite store, .csv and .json exports beside it
//     matrix:                          # every combination is one case, in this order:
//       integrator: [euler, rk4]
//       scenario: [sheet, flag]
//       mesh: [50x50, 100]             # rows x cols, or N for N x N (scenario.rows/cols)
//       dt: [0.001, 0.005]             # s (run mode only)
//       precision: [float32, float64]
//       scenario.structural.ks: [20, 200]   # any setting key: a list of values
//   slurm:                             # for --slurm only; not part of any case
//     partition: batch                 # sbatch --partition (default: the cluster's)
//     tasks: 8                         # array tasks = shards (--array=1-8)
//     time: "1:00:00"                  # sbatch --time per task
//     cpus_per_task: 2                 # sbatch --cpus-per-task
//     sbatch: [--mem=4G, --qos=short]  # further sbatch options, passed as given
#pragma once

#include <clothlab/analysis/find_max_dt.hpp>
#include <clothlab/config/setting.hpp>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace clothlab::sweep {

enum class SweepMode { Run, WorkPrecision, Stability };
const char* to_string(SweepMode mode);

// One setting as a single run would see it: "scenario.structural.ks" = "20".
using Setting = config::Setting;

// A matrix axis: a setting key and the values it takes, in file order.
struct Axis {
  std::string key;  // canonical: integrator.plugin, scenario.plugin, mesh, dt, precision, ...
  std::vector<Setting> values;
};

struct WorkPrecisionSettings {
  std::string reference_integrator = "rk4";
  // Integrators that solve a different ODE than the reference (e.g. position Verlet: no
  // velocity forces, its own drag) are measured against themselves at the reference step.
  std::vector<std::string> self_reference;
  double refinement = 32.0;  // reference dt = finest ladder dt / refinement
  double dt_start = 4e-3;    // coarsest ladder step, s
  int levels = 6;            // ladder length (dt_start, dt_start/2, ...)
};

struct SlurmSettings {
  std::string partition;
  std::size_t tasks = 4;
  std::string time;
  std::size_t cpus_per_task = 1;
  std::vector<std::string> sbatch_options;
};

struct SweepSpec {
  std::string source;  // file name, for messages
  std::string name;
  SweepMode mode = SweepMode::Run;
  std::filesystem::path output;  // without extension
  std::vector<Setting> fixed;    // keys outside `sweep:`, flattened
  std::vector<Axis> axes;        // matrix, in file order
  WorkPrecisionSettings work_precision;
  analysis::MaxDtOptions stability;
  SlurmSettings slurm;
};

}  // namespace clothlab::sweep
