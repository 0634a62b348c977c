// The settings of every mode, merged from the config file, the sweep file and the command line
// and checked by the one key table (run_keys.cpp): a plain run's (RunConfig), --choose's,
// --find-max-dt's and a sweep's.
#pragma once

#include <clothlab/analysis/find_max_dt.hpp>
#include <clothlab/analysis/stability_monitor.hpp>
#include <clothlab/sweep/integrator_choice.hpp>
#include <clothlab/sweep/sweep_spec.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "material.hpp"
#include "settings.hpp"

namespace clothlab::cli {

// frames.*: the cloth written every few steps for ParaView, Blender and the viewer.
struct FramesConfig {
  std::string dir;                // empty: no frames
  std::optional<uint64_t> every;  // frames.every (steps); else from rate
  // frames.rate, Hz of simulated time; unset: frame_rate when given, else 60 Hz.
  std::optional<double> rate;
  std::vector<std::string> formats;  // vtp (+ .pvd index), obj, pc2
  uint64_t every_steps = 1;          // resolved: steps between frames
};

// The defaults are the key table's (run_keys.cpp), applied by resolve_run_config.
struct RunConfig {
  std::string integrator;
  std::string scenario;
  // Where each plugin was named ("configs/x.yaml:2:13", "--integrator"), for load errors.
  std::string integrator_source, scenario_source;
  double dt = 0;
  // Frames: with frame_rate given, dt = 1 / (frame_rate * substeps); without, every step is
  // a frame (frame_rate = 1 / dt, substeps = 1).
  double frame_rate = 0;  // Hz
  uint64_t substeps = 0;  // steps per frame
  uint64_t steps = 0;
  double duration = 0;  // s; when the length was given as steps: steps * dt
  bool float64 = false;
  int threads = 0;               // 0: all cores
  bool adaptive_threads = true;  // thread_team: PipelineOptions::adaptive_threads
  // s: a run in a child process (a sweep case, a --find-max-dt probe, a single run) that
  // takes longer is killed and reported as timed out.
  double timeout_s = 0;
  // Plugin parameter settings with the "integrator." / "scenario." prefix removed, in
  // the order given; applied to the plugins' ParamSets once they are loaded.
  std::vector<Setting> integrator_params;
  std::vector<Setting> scenario_params;
  // plugin_params.<id>.<param> settings with "plugin_params." removed: parameters for one
  // plugin id, applied only when that plugin runs (before integrator.* / scenario.*), so
  // one config can carry e.g. verlet's damping and still run with rk4.
  std::vector<Setting> plugin_params;
  // material.*: when set, decides the scenario's mass and every spring's ks and kd.
  std::optional<Material> material;
  // stability.*: the objective verdict of every run.
  analysis::MonitorOptions monitor;
  // End the run at the first check where the warp/weft stretch exceeds this (x rest): the
  // maximum over the run can only grow, so --choose learns "stretch above its limit" without
  // the rest of the run. 0: run to the end.
  double stretch_stop = 0;
  // stability.unconverged: whether a solve that missed its tolerance fails the run (fail) or
  // is only counted, its iteration limit taken as a fixed budget (count).
  bool unconverged_fails = true;
  FramesConfig frames;
};

// choose.*: the --choose search (frame_rate from the key frame_rate).
struct ChooseConfig {
  sweep::ChoiceSettings search;
  std::vector<std::string> integrators;  // empty: every integrator on the plugin path
  std::string output;
  // Folder of cached references (trajectory_cache.hpp); empty: choose-references beside the
  // output.
  std::string reference_cache;
};

// sweep.*, work_precision.*, slurm.*: what a sweep file says beyond its cases' settings (the
// matrix is read by sweep_file.cpp, each value checked here as a case's setting).
struct SweepConfig {
  std::string name;
  sweep::SweepMode mode = sweep::SweepMode::Run;
  std::string output;  // without extension; empty: results/<name>
  sweep::WorkPrecisionSettings work_precision;
  sweep::SlurmSettings slurm;
};

struct Configuration {
  RunConfig run;
  ChooseConfig choose;
  // find_max_dt.*: --find-max-dt, and a sweep in stability mode; the first probe is the run's
  // dt (or the predicted limit), so dt_initial is not a key.
  analysis::MaxDtOptions find_max_dt;
  SweepConfig sweep;
};

// Applies settings in order (later wins; steps and duration replace each other) to the
// key table's defaults. Throws InputError naming source, key, value and what is allowed for an
// unknown key or a bad value.
Configuration resolve_configuration(const std::vector<Setting>& settings);
// The plain run's part of it.
RunConfig resolve_run_config(const std::vector<Setting>& settings);
// Throws InputError for a sweep.* or slurm.* setting: those belong in a sweep file.
void refuse_sweep_settings(const std::vector<Setting>& settings);

}  // namespace clothlab::cli
