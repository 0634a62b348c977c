#include "run_keys.hpp"

#include <algorithm>
#include <clothlab/config/mesh_sides.hpp>
#include <clothlab/host/errors.hpp>
#include <clothlab/host/identifiers.hpp>
#include <clothlab/host/param_text.hpp>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "run_config.hpp"

namespace clothlab::cli {

namespace {

using T = KeyType;

template <typename Whole>
Whole whole(const KeyValue& value) {
  return static_cast<Whole>(value.number);
}

Material& material_of(RunConfig& config, const KeyValue& value) {
  if (!config.material) config.material.emplace();
  if (config.material->source.empty()) config.material->source = value.setting.source;
  return *config.material;
}

// Throws the table's error for a value that is in range but breaks the key's own rule.
[[noreturn]] void refuse(const KeyValue& value, const std::string& allowed) {
  throw host::InputError(value.setting.source + ": " + value.setting.key + " = " +
                         value.setting.value + ": not allowed; allowed: " + allowed);
}

// File and folder names longer than this are refused by Linux file systems (NAME_MAX).
constexpr std::size_t max_name_bytes = 255;
// What the outputs append to a results path's last name (".sqlite-journal", "-references").
constexpr std::size_t output_suffix_bytes = 16;

// A path any of whose names the file system cannot hold is refused where it is set, not when
// the first file is created after the run. `suffix_bytes`: what the program appends to the
// last name.
std::string path_of(const KeyValue& value, std::size_t suffix_bytes) {
  const std::filesystem::path path(value.text);
  for (auto name = path.begin(); name != path.end(); ++name) {
    const std::size_t limit = max_name_bytes - (std::next(name) == path.end() ? suffix_bytes : 0);
    const std::size_t bytes = name->native().size();
    if (bytes > limit)
      throw host::InputError(value.setting.source + ": " + value.setting.key + ": the name " +
                             name->native().substr(0, 24) + "... is " + std::to_string(bytes) +
                             " bytes long; allowed: names of at most " +
                             std::to_string(max_name_bytes) + " bytes" +
                             (suffix_bytes > 0 ? ", the last at most " +
                                                     std::to_string(max_name_bytes - suffix_bytes) +
                                                     " (the outputs add their suffixes)"
                                               : ""));
  }
  return value.text;
}

std::string plugin_id_of(const KeyValue& value, const std::string& text) {
  if (!host::is_plugin_id(text)) refuse(value, "a plugin id ([a-z0-9_-]+)");
  return text;
}

// sbatch --time forms: M, M:S, H:M:S, D-H, D-H:M, D-H:M:S (groups after the first: 1-2 digits).
bool is_slurm_time(const std::string& text) {
  const std::size_t dash = text.find('-');
  if (dash != std::string::npos &&
      (dash == 0 || dash > 4 || text.find_first_not_of("0123456789") < dash))
    return false;
  const std::string clock = dash == std::string::npos ? text : text.substr(dash + 1);
  std::size_t groups = 0, start = 0;
  while (start <= clock.size()) {
    const std::size_t end = std::min(clock.find(':', start), clock.size());
    const std::size_t digits = end - start;
    if (digits == 0 || digits > (groups == 0 ? 6 : 2) ||
        clock.substr(start, digits).find_first_not_of("0123456789") != std::string::npos)
      return false;
    ++groups;
    start = end + 1;
  }
  return groups <= 3;
}

constexpr double max_dt_s = 10.0;
constexpr double max_steps = 1e9;
constexpr double max_substeps = 1e6;
constexpr double max_rate_hz = 1e6;
constexpr double max_timeout_s = 1e6;
constexpr double max_side = 4096;  // the grid scenarios' rows and cols
// More threads than this make libgomp fail with its own message on ordinary machines.
constexpr double max_threads = 256;

const KeyInfo keys[] = {
    {"integrator.plugin", T::NonEmptyText, 0, 0, "", "a plugin name or path", "rk4",
     "integrator plugin: NAME, NAME.so (searched) or a path with '/'", "integrator",
     [](Configuration& c, const KeyValue& v) {
       c.run.integrator = v.text;
       c.run.integrator_source = v.setting.source;
     }},
    {"scenario.plugin", T::NonEmptyText, 0, 0, "", "a plugin name or path", "sheet",
     "scenario plugin, found like the integrator", "scenario",
     [](Configuration& c, const KeyValue& v) {
       c.run.scenario = v.text;
       c.run.scenario_source = v.setting.source;
     }},
    {"dt", T::PositiveReal, 0, max_dt_s, "s", nullptr, "0.001", "time step", "dt",
     [](Configuration& c, const KeyValue& v) { c.run.dt = v.number; }},
    {"frame_rate", T::PositiveReal, 0, max_rate_hz, "Hz", nullptr, nullptr,
     "frames per second, instead of dt: dt = 1 / (frame_rate * substeps)", "frame-rate",
     [](Configuration& c, const KeyValue& v) { c.run.frame_rate = v.number; }},
    {"substeps", T::Whole, 1, max_substeps, "steps per frame", nullptr, "1",
     "steps per frame, with frame_rate", "substeps",
     [](Configuration& c, const KeyValue& v) { c.run.substeps = whole<uint64_t>(v); }},
    {"steps", T::Whole, 1, max_steps, "", nullptr, nullptr,
     "number of steps, instead of duration (the later one given wins)", "steps",
     [](Configuration& c, const KeyValue& v) { c.run.steps = whole<uint64_t>(v); }},
    {"duration", T::PositiveReal, 0, 1e6, "s", nullptr, "2", "simulated time, instead of steps",
     "duration", [](Configuration& c, const KeyValue& v) { c.run.duration = v.number; }},
    {"mesh", T::Mesh, 1, max_side, "", nullptr, nullptr,
     "the grid scenarios' size: sets scenario.rows and scenario.cols", nullptr,
     [](Configuration& c, const KeyValue& v) {
       const config::MeshSides sides = config::mesh_sides(v.text);
       c.run.scenario_params.push_back({"rows", sides.rows, v.setting.source});
       c.run.scenario_params.push_back({"cols", sides.cols, v.setting.source});
     }},
    {"precision", T::Choice, 0, 0, "", "float32, float64", "float32", "floating-point precision",
     "precision", [](Configuration& c, const KeyValue& v) { c.run.float64 = v.text == "float64"; }},
    {"threads", T::Whole, 0, max_threads, "", nullptr, "0", "worker threads, 0 = all cores",
     "threads", [](Configuration& c, const KeyValue& v) { c.run.threads = whole<int>(v); }},
    {"thread_team", T::Choice, 0, 0, "", "fixed, adaptive", "adaptive",
     "fixed: every step on `threads`; adaptive: steps run on one thread while a step on one "
     "thread, probed now and then, beats the team's (docs/architecture.md, threads)",
     nullptr,
     [](Configuration& c, const KeyValue& v) { c.run.adaptive_threads = v.text == "adaptive"; }},
    {"timeout", T::PositiveReal, 0, max_timeout_s, "s", nullptr, "600",
     "a single run, sweep case or --find-max-dt probe running longer is killed", nullptr,
     [](Configuration& c, const KeyValue& v) { c.run.timeout_s = v.number; }},
    {"material.name", T::Text, 0, 0, "", "a label for reports", nullptr,
     "the material's name (a material sets every material.* number)", nullptr,
     [](Configuration& c, const KeyValue& v) { material_of(c.run, v).name = v.text; }},
    {"material.areal_density", T::Real, 1e-6, 1e3, "kg/m^2", nullptr, nullptr,
     "mass per area; decides the scenario's mass", nullptr,
     [](Configuration& c, const KeyValue& v) { material_of(c.run, v).areal_density = v.number; }},
    {"material.stretch_stiffness", T::Real, 1e-3, 1e8, "N/m", nullptr, nullptr,
     "membrane stretch stiffness E", nullptr,
     [](Configuration& c, const KeyValue& v) { material_of(c.run, v).stretch_stiffness = v.number; }},
    {"material.shear_stiffness", T::Real, 0, 1e8, "N/m", nullptr, nullptr,
     "membrane shear stiffness G, below E", nullptr,
     [](Configuration& c, const KeyValue& v) { material_of(c.run, v).shear_stiffness = v.number; }},
    {"material.bending_stiffness", T::Real, 0, 1, "N m", nullptr, nullptr, "bending stiffness B",
     nullptr,
     [](Configuration& c, const KeyValue& v) { material_of(c.run, v).bending_stiffness = v.number; }},
    {"material.damping_time", T::Real, 0, 10, "s", nullptr, nullptr,
     "Rayleigh damping time kd / ks", nullptr,
     [](Configuration& c, const KeyValue& v) { material_of(c.run, v).damping_time = v.number; }},
    {"choose.duration", T::PositiveReal, 0, 1e3, "s", nullptr, "1",
     "--choose: simulated time of the runs judged for stability, stretch and cost", nullptr,
     [](Configuration& c, const KeyValue& v) { c.choose.search.duration = v.number; }},
    {"choose.error_duration", T::PositiveReal, 0, 1e3, "s", nullptr, nullptr,
     "--choose: simulated time of the error run; unset: choose.duration", nullptr,
     [](Configuration& c, const KeyValue& v) { c.choose.search.error_duration = v.number; }},
    {"choose.probe_timeout", T::PositiveReal, 0, max_timeout_s, "s", nullptr, "60",
     "--choose: wall-clock limit of one probe run", nullptr,
     [](Configuration& c, const KeyValue& v) { c.choose.search.probe_timeout_s = v.number; }},
    {"choose.stop_factor", T::Real, 0, 1e3, "", "0 (no cost budget) or a real in [2, 1000]", "3",
     "--choose: a search is stopped, and reported, where nothing it has left can cost within "
     "this / 2 x the best passing setting so far; 0: no cost budget; below 2 refused (it could "
     "stop a cheaper setting)",
     nullptr,
     [](Configuration& c, const KeyValue& v) {
       if (v.number > 0 && v.number < 2)
         throw host::InputError(v.setting.source + ": choose.stop_factor = " + v.setting.value +
                                ": out of range; allowed: 0 (no cost budget) or a real in [2, "
                                "1000]");
       c.choose.search.stop_factor = v.number;
     }},
    {"choose.stretch_limit", T::Real, 1, 1e6, "x rest length", nullptr, "1.1",
     "--choose: longest warp/weft spring allowed, those within two spacings of a pin left out",
     nullptr,
     [](Configuration& c, const KeyValue& v) { c.choose.search.stretch_limit = v.number; }},
    {"choose.reference_stretch_factor", T::Real, 1, 1e6, "", nullptr, "1.5",
     "--choose: a method's strain (stretch - 1, away from the pins) over the error run at most "
     "this x the reference's",
     nullptr,
     [](Configuration& c, const KeyValue& v) {
       c.choose.search.reference_stretch_factor = v.number;
     }},
    {"choose.error_tolerance", T::PositiveReal, 0, 1, "of the cloth diagonal", nullptr, "0.01",
     "--choose: RMS position error allowed against the reference", nullptr,
     [](Configuration& c, const KeyValue& v) { c.choose.search.error_tolerance = v.number; }},
    {"choose.max_substeps", T::Whole, 1, max_substeps, "", nullptr, "4096",
     "--choose: most substeps per frame tried", nullptr,
     [](Configuration& c, const KeyValue& v) { c.choose.search.max_substeps = whole<uint32_t>(v); }},
    {"choose.max_iterations", T::Whole, 1, 1e5, "", nullptr, "32",
     "--choose: most solver iterations tried", nullptr,
     [](Configuration& c, const KeyValue& v) { c.choose.search.max_iterations = whole<uint32_t>(v); }},
    {"choose.reference_substeps", T::Whole, 1, max_substeps, "", nullptr, "512",
     "--choose: the reference's substeps per frame", nullptr,
     [](Configuration& c, const KeyValue& v) { c.choose.search.reference_substeps = whole<uint32_t>(v); }},
    {"choose.reference_integrator", T::NonEmptyText, 0, 0, "", "a plugin name", "rk4",
     "--choose: the integrator of the reference", nullptr,
     [](Configuration& c, const KeyValue& v) { c.choose.search.reference_integrator = v.text; }},
    {"choose.error_mesh", T::Mesh, 1, max_side, "", nullptr, nullptr,
     "--choose: mesh of the error runs; unset: the scene's", nullptr,
     [](Configuration& c, const KeyValue& v) { c.choose.search.error_mesh = v.text; }},
    {"choose.integrators", T::Names, 0, 0, "", "plugin names", nullptr,
     "--choose: the integrators compared; unset: every one on the plugin path", nullptr,
     [](Configuration& c, const KeyValue& v) { c.choose.integrators = v.words; }},
    {"choose.output", T::NonEmptyText, 0, 0, "", "a path", "results/choose",
     "--choose: results file, without extension", nullptr,
     [](Configuration& c, const KeyValue& v) { c.choose.output = path_of(v, output_suffix_bytes); }},
    {"choose.reference_cache", T::NonEmptyText, 0, 0, "", "a folder path", nullptr,
     "--choose: folder of cached references; unset: choose-references beside choose.output",
     nullptr,
     [](Configuration& c, const KeyValue& v) { c.choose.reference_cache = path_of(v, 0); }},
    {"stability.interval", T::Whole, 1, max_steps, "steps", nullptr, "10",
     "steps between stability checks", nullptr,
     [](Configuration& c, const KeyValue& v) { c.run.monitor.check_interval = whole<uint64_t>(v); }},
    {"stability.max_stretch", T::Real, 1, 1e6, "", nullptr, "5",
     "longest spring / rest length before the run fails", nullptr,
     [](Configuration& c, const KeyValue& v) { c.run.monitor.stretch_limit = v.number; }},
    {"stability.stretch_stop", T::Real, 0, 1e6, "", "0 (run to the end) or a real in [1, 1e6]",
     "0",
     "end the run (not a failure) at the first check where the warp/weft stretch away from the "
     "pins exceeds this x rest (--choose sets its stretch limit); 0: run to the end",
     nullptr,
     [](Configuration& c, const KeyValue& v) {
       if (v.number > 0 && v.number < 1)
         throw host::InputError(v.setting.source + ": stability.stretch_stop = " +
                                v.setting.value +
                                ": out of range; allowed: 0 (run to the end) or a real in [1, "
                                "1e6]");
       c.run.stretch_stop = v.number;
     }},
    {"stability.unconverged", T::Choice, 0, 0, "", "fail, count", "fail",
     "fail: a run in which a solve missed its tolerance fails (check unconverged); count: the "
     "iteration limit is a fixed budget, the run is judged by its other checks and the misses "
     "are counted in its verdict and JSON",
     nullptr,
     [](Configuration& c, const KeyValue& v) { c.run.unconverged_fails = v.text == "fail"; }},
    {"stability.energy_margin", T::PositiveReal, 0, 1e12, "", nullptr, "1",
     "energy gain allowed, in units of the cloth's energy scale", nullptr,
     [](Configuration& c, const KeyValue& v) { c.run.monitor.energy_margin = v.number; }},
    {"stability.wind_work_safety", T::Real, 1, 1e6, "", nullptr, "2",
     "factor on the bound of the work the wind can do between two checks (the energy check's "
     "allowance)",
     nullptr,
     [](Configuration& c, const KeyValue& v) { c.run.monitor.wind_work_safety = v.number; }},
    {"find_max_dt.tolerance", T::Real, 1e-6, 0.5, "", nullptr, "0.02",
     "--find-max-dt and stability sweeps: relative width of the final bracket (the first probe "
     "is dt, or the predicted limit)",
     nullptr,
     [](Configuration& c, const KeyValue& v) { c.find_max_dt.relative_tolerance = v.number; }},
    {"find_max_dt.dt_min", T::PositiveReal, 0, max_dt_s, "s", nullptr, "1e-07",
     "--find-max-dt and stability sweeps: the smallest dt tried", nullptr,
     [](Configuration& c, const KeyValue& v) { c.find_max_dt.dt_lower_limit = v.number; }},
    {"find_max_dt.dt_max", T::PositiveReal, 0, max_dt_s, "s", nullptr, "1",
     "--find-max-dt and stability sweeps: the largest dt tried", nullptr,
     [](Configuration& c, const KeyValue& v) { c.find_max_dt.dt_upper_limit = v.number; }},
    {"find_max_dt.growth", T::Real, 1.01, 100, "", nullptr, "2",
     "--find-max-dt and stability sweeps: factor between probes while bracketing", nullptr,
     [](Configuration& c, const KeyValue& v) { c.find_max_dt.growth = v.number; }},
    {"find_max_dt.max_evaluations", T::Whole, 1, 1000, "", nullptr, "64",
     "--find-max-dt and stability sweeps: most probe runs of one search", nullptr,
     [](Configuration& c, const KeyValue& v) { c.find_max_dt.max_evaluations = whole<int>(v); }},
    {"sweep.name", T::NonEmptyText, 0, 0, "", "a plugin-id-like name ([a-z0-9_-]+)", nullptr,
     "a sweep file's name (required there)", nullptr,
     [](Configuration& c, const KeyValue& v) {
       if (!host::is_plugin_id(v.text)) refuse(v, "[a-z0-9_-]+");
       c.sweep.name = path_of(v, output_suffix_bytes);
     }},
    {"sweep.mode", T::Choice, 0, 0, "", "run, work-precision, stability", "run",
     "a sweep's kind: runs, a work-precision ladder per case, or a stable-dt search per case",
     nullptr,
     [](Configuration& c, const KeyValue& v) {
       for (const sweep::SweepMode mode : {sweep::SweepMode::Run, sweep::SweepMode::WorkPrecision,
                                           sweep::SweepMode::Stability})
         if (v.text == sweep::to_string(mode)) c.sweep.mode = mode;
     }},
    {"sweep.output", T::NonEmptyText, 0, 0, "", "a path without extension", nullptr,
     "a sweep's results (.sqlite, .csv, .json); unset: results/<sweep.name>", nullptr,
     [](Configuration& c, const KeyValue& v) { c.sweep.output = path_of(v, output_suffix_bytes); }},
    {"work_precision.reference_integrator", T::NonEmptyText, 0, 0, "", "a plugin id", "rk4",
     "work-precision sweeps: the integrator of the reference runs", nullptr,
     [](Configuration& c, const KeyValue& v) {
       c.sweep.work_precision.reference_integrator = plugin_id_of(v, v.text);
     }},
    {"work_precision.self_reference", T::Names, 0, 0, "", "plugin ids", nullptr,
     "work-precision sweeps: integrators measured against themselves at the reference step "
     "(they solve another ODE than the reference, e.g. Verlet's own drag)",
     nullptr,
     [](Configuration& c, const KeyValue& v) {
       c.sweep.work_precision.self_reference.clear();
       for (const std::string& id : v.words)
         c.sweep.work_precision.self_reference.push_back(plugin_id_of(v, id));
     }},
    {"work_precision.refinement", T::Real, 2, 1e6, "", nullptr, "32",
     "work-precision sweeps: the reference dt is the finest ladder dt / this", nullptr,
     [](Configuration& c, const KeyValue& v) { c.sweep.work_precision.refinement = v.number; }},
    {"work_precision.dt_start", T::Real, 1e-9, max_dt_s, "s", nullptr, "0.004",
     "work-precision sweeps: the coarsest ladder dt", nullptr,
     [](Configuration& c, const KeyValue& v) { c.sweep.work_precision.dt_start = v.number; }},
    {"work_precision.levels", T::Whole, 2, 30, "", nullptr, "6",
     "work-precision sweeps: ladder length (dt_start, dt_start / 2, ...)", nullptr,
     [](Configuration& c, const KeyValue& v) { c.sweep.work_precision.levels = whole<int>(v); }},
    {"slurm.partition", T::Text, 0, 0, "", "a partition name: up to 64 of [A-Za-z0-9_.-]",
     nullptr, "--slurm: sbatch --partition; unset: the cluster's default", nullptr,
     [](Configuration& c, const KeyValue& v) {
       const bool plain = !v.text.empty() && v.text.size() <= 64 &&
                          v.text.find_first_not_of(
                              "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                              "0123456789_.-") == std::string::npos;
       if (!plain) refuse(v, "a partition name: up to 64 of [A-Za-z0-9_.-]");
       c.sweep.slurm.partition = v.text;
     }},
    {"slurm.tasks", T::Whole, 1, 1e5, "", nullptr, "4",
     "--slurm: array tasks, one shard each (--array=1-N)", nullptr,
     [](Configuration& c, const KeyValue& v) { c.sweep.slurm.tasks = whole<std::size_t>(v); }},
    {"slurm.time", T::Text, 0, 0, "", "a Slurm time: MM, MM:SS, H:MM:SS or D-HH[:MM[:SS]]",
     nullptr, "--slurm: sbatch --time per task; unset: the partition's limit", nullptr,
     [](Configuration& c, const KeyValue& v) {
       if (!is_slurm_time(v.text)) refuse(v, "a Slurm time: MM, MM:SS, H:MM:SS or D-HH[:MM[:SS]]");
       c.sweep.slurm.time = v.text;
     }},
    {"slurm.cpus_per_task", T::Whole, 1, 1024, "", nullptr, "1",
     "--slurm: sbatch --cpus-per-task", nullptr,
     [](Configuration& c, const KeyValue& v) {
       c.sweep.slurm.cpus_per_task = whole<std::size_t>(v);
     }},
    {"slurm.sbatch", T::Names, 0, 0, "", "sbatch options --name or --name=value", nullptr,
     "--slurm: further sbatch options, passed as given (each setting adds to the list)", nullptr,
     [](Configuration& c, const KeyValue& v) {
       for (const std::string& option : v.words) {
         if (!option.starts_with("--") || option.find_first_of(" \t\n") != std::string::npos)
           refuse(v, "sbatch options of the form --name or --name=value");
         c.sweep.slurm.sbatch_options.push_back(option);
       }
     }},
    {"frames.dir", T::NonEmptyText, 0, 0, "", "a folder path", nullptr,
     "write the cloth every frame to this folder; `clothlab view DIR` plays it", "frames",
     [](Configuration& c, const KeyValue& v) { c.run.frames.dir = path_of(v, 0); }},
    {"frames.every", T::Whole, 1, max_steps, "steps", nullptr, nullptr,
     "steps between frames, instead of frames.rate", nullptr,
     [](Configuration& c, const KeyValue& v) { c.run.frames.every = whole<uint64_t>(v); }},
    {"frames.rate", T::PositiveReal, 0, max_rate_hz, "Hz", nullptr, nullptr,
     "frames per simulated second, instead of frames.every; unset: frame_rate, else 60 Hz",
     nullptr,
     [](Configuration& c, const KeyValue& v) {
       c.run.frames.rate = v.number;
       c.run.frames.every.reset();
     }},
    {"frames.format", T::ChoiceList, 0, 0, "", "vtp, obj, pc2", "vtp",
     "frame file formats (vtp comes with a .pvd index)", nullptr,
     [](Configuration& c, const KeyValue& v) { c.run.frames.formats = v.words; }},
    {"integrator.<parameter>", T::PluginParameter, 0, 0, "", "a parameter of the integrator",
     nullptr, "see clothlab --list-plugins", nullptr,
     [](Configuration& c, const KeyValue& v) {
       c.run.integrator_params.push_back({v.setting.key.substr(11), v.text, v.setting.source});
     }},
    {"scenario.<parameter>", T::PluginParameter, 0, 0, "", "a parameter of the scenario", nullptr,
     "see clothlab --list-plugins", nullptr,
     [](Configuration& c, const KeyValue& v) {
       c.run.scenario_params.push_back({v.setting.key.substr(9), v.text, v.setting.source});
     }},
    {"plugin_params.<plugin id>.<parameter>", T::PluginParameter, 0, 0, "",
     "a parameter of that plugin", nullptr,
     "applied only when that plugin runs, before integrator.* and scenario.*", nullptr,
     [](Configuration& c, const KeyValue& v) {
       c.run.plugin_params.push_back({v.setting.key.substr(14), v.text, v.setting.source});
     }},
};

// "integrator.<parameter>" -> "integrator."; "" for a plain key.
std::string_view family_prefix(const KeyInfo& info) {
  const std::string_view key = info.key;
  const size_t open = key.find('<');
  return open == std::string_view::npos ? std::string_view() : key.substr(0, open);
}

bool in_family(const KeyInfo& info, const std::string& key) {
  const std::string_view prefix = family_prefix(info);
  if (prefix.empty() || key.size() <= prefix.size() || !key.starts_with(prefix)) return false;
  // plugin_params.<plugin id>.<parameter> needs both parts.
  const bool two_parts =
      std::string_view(info.key).find('<', prefix.size() + 1) != std::string::npos;
  const std::string rest = key.substr(prefix.size());
  const size_t dot = rest.find('.');
  return !two_parts || (dot != std::string::npos && dot > 0 && dot + 1 < rest.size());
}

std::vector<std::string> split_list(const std::string& value) {
  std::string text = value;
  if (text.size() >= 2 && text.front() == '[' && text.back() == ']')
    text = text.substr(1, text.size() - 2);
  std::vector<std::string> words;
  size_t begin = 0;
  while (begin <= text.size()) {
    size_t end = text.find(',', begin);
    if (end == std::string::npos) end = text.size();
    std::string word = text.substr(begin, end - begin);
    word.erase(0, word.find_first_not_of(' '));
    word.erase(word.find_last_not_of(' ') + 1);
    words.push_back(word);
    begin = end + 1;
  }
  return words;
}

clothlab_param_spec number_spec(const KeyInfo& info) {
  clothlab_param_spec spec{};
  spec.struct_size = sizeof spec;
  spec.type =
      info.type == T::Whole || info.type == T::Mesh ? CLOTHLAB_PARAM_INT : CLOTHLAB_PARAM_REAL;
  // (0, max]: the smallest positive double is the inclusive lower bound.
  spec.min_value = info.type == T::PositiveReal ? std::nextafter(0.0, 1.0) : info.min_value;
  spec.max_value = info.max_value;
  spec.unit = info.unit;
  return spec;
}

// Why the text is not a number in the key's range, or "".
std::string number_problem(const KeyInfo& info, const std::string& text, double& number) {
  const clothlab_param_spec spec = number_spec(info);
  const host::ParsedParam parsed = host::parse_param_text(spec, text);
  if (!parsed.value) return parsed.problem;
  if (!host::in_range(spec, *parsed.value)) return "out of range";
  number = parsed.value->v[0];
  return "";
}

bool is_choice(const KeyInfo& info, const std::string& word) {
  const std::vector<std::string> choices = split_list(info.allowed);
  return std::find(choices.begin(), choices.end(), word) != choices.end();
}

// Why the value does not fit the key, or "".
std::string value_problem(const KeyInfo& info, const Setting& setting, KeyValue& value) {
  const std::string& text = setting.value;
  switch (info.type) {
    case T::Real:
    case T::PositiveReal:
    case T::Whole:
      return number_problem(info, text, value.number);
    case T::Choice:
      value.text = text;
      return is_choice(info, text) ? "" : "unknown value";
    case T::ChoiceList:
      for (const std::string& word : split_list(text)) {
        if (!is_choice(info, word)) return "unknown value '" + word + "'";
        if (std::find(value.words.begin(), value.words.end(), word) != value.words.end())
          return "repeats " + word;
        value.words.push_back(word);
      }
      return "";
    case T::Names:
      value.words = split_list(text);
      for (const std::string& word : value.words)
        if (word.empty()) return "an empty name";
      return "";
    case T::Mesh: {
      const config::MeshSides sides = config::mesh_sides(text);
      double side = 0;
      for (const std::string& part : {sides.rows, sides.cols})
        if (!number_problem(info, part, side).empty()) return "not a mesh";
      value.text = sides.rows + "x" + sides.cols;
      return "";
    }
    case T::NonEmptyText:
      value.text = text;
      return text.empty() ? "empty" : "";
    case T::Text:
    case T::PluginParameter:
      value.text = text;
      return "";
  }
  return "unknown key type";
}

// "a, b or c".
std::string one_of(const std::vector<std::string>& choices) {
  std::string text;
  for (size_t i = 0; i < choices.size(); ++i)
    text += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + choices[i];
  return text;
}

// Breaks text into lines of at most `width` characters.
std::vector<std::string> wrapped(const std::string& text, size_t width) {
  std::istringstream words(text);
  std::vector<std::string> lines{""};
  std::string word;
  while (words >> word) {
    if (!lines.back().empty() && lines.back().size() + 1 + word.size() > width)
      lines.emplace_back();
    lines.back() += (lines.back().empty() ? "" : " ") + word;
  }
  return lines;
}

}  // namespace

std::span<const KeyInfo> run_keys() { return keys; }

const KeyInfo* find_run_key(const std::string& key) {
  for (const KeyInfo& info : keys)
    if (key == info.key) return &info;
  for (const KeyInfo& info : keys)
    if (in_family(info, key)) return &info;
  return nullptr;
}

std::string describe_allowed(const KeyInfo& info) {
  const std::string unit = *info.unit ? std::string(" ") + info.unit : std::string();
  switch (info.type) {
    case T::Real:
    case T::Whole:
      // `allowed` for a number with a rule beyond its range (choose.stop_factor).
      return info.allowed ? info.allowed : host::describe_allowed(number_spec(info));
    case T::PositiveReal:
      return "real in (0, " + host::format_number(info.max_value) + "]" + unit;
    case T::Choice:
      return one_of(split_list(info.allowed));
    case T::ChoiceList: {
      const std::vector<std::string> choices = split_list(info.allowed);
      return one_of(choices) + ", or a list of them, e.g. [" + choices.at(0) + ", " +
             choices.at(1) + "]";
    }
    case T::Names:
      return std::string("a name or a list [a, b] of ") + info.allowed;
    case T::Mesh:
      return "ROWSxCOLS or N, each a whole number in [" + host::format_number(info.min_value) +
             ", " + host::format_number(info.max_value) + "]";
    case T::Text:
    case T::NonEmptyText:
    case T::PluginParameter:
      return info.allowed;
  }
  return "";
}

KeyValue check_value(const KeyInfo& info, const Setting& setting) {
  KeyValue value;
  value.setting = setting;
  const std::string problem = value_problem(info, setting, value);
  if (!problem.empty()) {
    const std::string what = problem == "empty"
                                 ? setting.key + " is empty"
                                 : setting.key + " = " + setting.value + ": " + problem;
    throw host::InputError(setting.source + ": " + what + "; allowed: " + describe_allowed(info));
  }
  return value;
}

std::string unknown_key_message(const Setting& setting) {
  std::vector<std::string> names;
  std::string valid;
  for (const KeyInfo& info : keys) {
    names.emplace_back(info.key);
    valid += (valid.empty() ? "" : ", ") + names.back();
  }
  const std::string nearest = host::nearest_name(setting.key, names);
  return setting.source + ": unknown key " + setting.key +
         (nearest.empty() ? "" : " (did you mean " + nearest + "?)") + "; valid: " + valid;
}

std::string keys_help_text() {
  constexpr size_t key_column = 28, width = 100;
  std::string text =
      "Keys (in a --config file, as --set KEY=VALUE, or by the flag named beside them):\n";
  for (const KeyInfo& info : keys) {
    const std::string name = std::string("  ") + info.key;
    std::string about = std::string(info.help) + "; allowed: " + describe_allowed(info);
    if (info.default_value) about += "; default " + std::string(info.default_value);
    if (info.flag) about += "; flag --" + std::string(info.flag);
    // A key too long for its column gets a line of its own.
    std::string column = name.size() < key_column
                             ? name + std::string(key_column - name.size(), ' ')
                             : name + "\n" + std::string(key_column, ' ');
    for (const std::string& line : wrapped(about, width - key_column)) {
      text += column + line + "\n";
      column = std::string(key_column, ' ');
    }
  }
  return text;
}

namespace {

// A table cell: a '|' would end the cell and a line break the row.
std::string markdown_cell(const std::string& text) {
  std::string cell;
  for (const char c : text) {
    if (c == '|') cell += '\\';
    cell += c == '\n' ? ' ' : c;
  }
  return cell;
}

}  // namespace

std::string keys_markdown_table() {
  std::string table = "| key | allowed | default | flag | what it does |\n|---|---|---|---|---|\n";
  for (const KeyInfo& info : keys) {
    table.append("| `").append(info.key).append("` | ");
    table.append(markdown_cell(describe_allowed(info))).append(" | ");
    if (info.default_value) table.append("`").append(markdown_cell(info.default_value)).append("`");
    table.append(" | ");
    if (info.flag) table.append("`--").append(info.flag).append("`");
    table.append(" | ").append(markdown_cell(info.help)).append(" |\n");
  }
  return table;
}

}  // namespace clothlab::cli
