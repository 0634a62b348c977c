#include "simulation_binding.hpp"

#include <clothlab/ext/topology.h>
#include <dlfcn.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <clothlab/config/yaml_settings.hpp>
#include <clothlab/host/errors.hpp>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>

#include "frames_output.hpp"
#include "python_errors.hpp"
#include "run_config.hpp"
#include "run_report.hpp"
#include "simulation.hpp"
#include "sweep_file.hpp"

namespace py = pybind11;
namespace fs = std::filesystem;

namespace clothlab::python {

namespace {

// A config setting's value as --set would spell it: YAML's scalars and flow lists.
std::string value_text(const py::handle& value, const std::string& key) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value))
    return py::repr(value).cast<std::string>();
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    std::string text = "[";
    for (const py::handle& item : value)
      text += (text.size() > 1 ? ", " : "") + value_text(item, key);
    return text + "]";
  }
  throw host::InputError("overrides: " + key + ": a number, text, bool or list; got " +
                         py::type::of(value).attr("__name__").cast<std::string>());
}

}  // namespace

fs::path module_folder() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<const void*>(&module_folder), &info) == 0 ||
      info.dli_fname == nullptr)
    return {};
  return fs::absolute(info.dli_fname).parent_path();
}

std::vector<config::Setting> override_settings(const py::dict& overrides) {
  std::vector<config::Setting> settings;
  for (const auto& [key, value] : overrides) {
    const std::string name = py::str(key).cast<std::string>();
    settings.push_back({config::canonical_key(name), value_text(value, name), "overrides"});
  }
  return settings;
}

std::vector<config::Setting> settings_of(const py::object& config, const py::dict& overrides) {
  std::vector<config::Setting> settings;
  if (py::isinstance<py::dict>(config)) {
    // JSON is YAML: the one reader and flattener of config files reads the dict.
    const std::string text = py::module_::import("json").attr("dumps")(config).cast<std::string>();
    settings = config::flatten_settings(config::load_yaml_text(text, "config"), "config");
  } else if (py::isinstance<py::str>(config) || py::hasattr(config, "__fspath__")) {
    const fs::path path = py::module_::import("os").attr("fspath")(config).cast<std::string>();
    if (cli::is_sweep_file(path))
      throw host::InputError(path.string() +
                             " is a sweep: clothlab.Simulation runs one configuration");
    settings = config::read_config_file(path);
  } else {
    throw host::InputError("config: a dict of settings or a YAML file's path; got " +
                           py::type::of(config).attr("__name__").cast<std::string>());
  }
  const std::vector<config::Setting> added = override_settings(overrides);
  settings.insert(settings.end(), added.begin(), added.end());
  cli::refuse_sweep_settings(settings);
  return settings;
}

host::PluginSearchPath module_search_path(const std::vector<std::string>& plugin_path) {
  std::vector<fs::path> installed;
  const fs::path here = module_folder();
  for (const char* relative :
       {"plugins", CLOTHLAB_PLUGINS_FROM_MODULE, "../../lib/clothlab/plugins"}) {
    const fs::path folder = (here / relative).lexically_normal();
    std::error_code error;
    if (fs::is_directory(folder, error) &&
        std::find(installed.begin(), installed.end(), folder) == installed.end())
      installed.push_back(folder);
  }
  return host::PluginSearchPath::standard(plugin_path, std::move(installed));
}

namespace {

// One Python thread at a time: a second one gets an exception, never a torn state.
class Exclusive {
 public:
  Exclusive(std::recursive_mutex& mutex, const char* what) : lock_(mutex, std::try_to_lock) {
    if (!lock_.owns_lock())
      throw std::runtime_error(std::string("clothlab.Simulation.") + what +
                               ": the simulation is in use by another thread; allowed: one "
                               "thread at a time per simulation");
  }

 private:
  std::unique_lock<std::recursive_mutex> lock_;
};

class PythonSimulation {
 public:
  PythonSimulation(const py::object& config, const py::dict& overrides,
                   const std::vector<std::string>& plugin_path)
      : config_(cli::resolve_run_config(settings_of(config, overrides))),
        simulation_(std::make_unique<cli::Simulation>(config_, module_search_path(plugin_path))) {
    if (!config_.frames.dir.empty()) frames_.emplace(config_, *simulation_);
  }

  // A run left before its end still gets its summary so far in the frames' run.json.
  ~PythonSimulation() {
    if (!frames_ || frames_finished_) return;
    try {
      frames_->finish(simulation_->record());
    } catch (const std::exception& error) {
      std::fprintf(stderr, "clothlab: error: %s\n", host::one_line(error.what()).c_str());
    }
  }
  PythonSimulation(const PythonSimulation&) = delete;
  PythonSimulation& operator=(const PythonSimulation&) = delete;

  uint64_t step(int64_t count, const py::object& progress) {
    Exclusive exclusive(busy_, "step");
    if (count < 0)
      throw host::InputError("step(" + std::to_string(count) +
                             "): allowed: a whole number of steps >= 0");
    const uint64_t left = simulation_->steps_left();
    if (static_cast<uint64_t>(count) > left)
      throw host::InputError("step(" + std::to_string(count) + "): the run has " +
                             std::to_string(left) + " steps left of its " +
                             std::to_string(simulation_->config().steps) +
                             " (steps or duration); allowed: at most " + std::to_string(left));
    return run_steps(static_cast<uint64_t>(count), progress);
  }

  uint64_t advance(double seconds, const py::object& progress) {
    Exclusive exclusive(busy_, "advance");
    return run_steps(simulation_->steps_to_advance(seconds), progress);
  }

  // (3, n) over the engine's struct-of-arrays state: row k starts k * stride elements in.
  py::array state_view(bool velocities, const py::object& self) {
    Exclusive exclusive(busy_, velocities ? "velocities" : "positions");
    const clothlab_system& system = simulation_->cloth().system();
    const py::dtype dtype = run_dtype();
    const auto item = static_cast<py::ssize_t>(dtype.itemsize());
    return py::array(dtype, {py::ssize_t{3}, static_cast<py::ssize_t>(system.particle_count)},
                     {static_cast<py::ssize_t>(system.stride) * item, item},
                     velocities ? system.v : system.x, self);
  }

  // Copies a (3, n) or (n, 3) array of the run's dtype into the state, between steps.
  void set_state(bool velocities, const py::array& values) {
    Exclusive exclusive(busy_, velocities ? "velocities" : "positions");
    const char* name = velocities ? "velocities" : "positions";
    const clothlab_system& system = simulation_->cloth().system();
    const py::ssize_t n = system.particle_count;
    const py::dtype dtype = run_dtype();
    const bool by_rows = values.ndim() == 2 && values.shape(0) == 3 && values.shape(1) == n;
    const bool by_particles = values.ndim() == 2 && values.shape(0) == n && values.shape(1) == 3;
    if (!values.dtype().is(dtype))
      throw host::InputError(std::string(name) + ": dtype " +
                             py::str(py::handle(values.dtype())).cast<std::string>() +
                             "; allowed: " + py::str(py::handle(dtype)).cast<std::string>() +
                             " (the run's precision)");
    if (!by_rows && !by_particles)
      throw host::InputError(std::string(name) + ": shape " +
                             py::str(values.attr("shape")).cast<std::string>() + "; allowed: (3, " +
                             std::to_string(n) + ") or (" + std::to_string(n) + ", 3)");
    if (dtype.itemsize() == sizeof(double))
      copy_in<double>(values, by_rows, velocities ? system.v : system.x, system.stride);
    else
      copy_in<float>(values, by_rows, velocities ? system.v : system.x, system.stride);
    simulation_->state_written();
  }

  void state_written() {
    Exclusive exclusive(busy_, "state_written");
    simulation_->state_written();
  }

  py::array inverse_masses(const py::object& self) {
    const clothlab_system& system = simulation_->cloth().system();
    return read_only(py::array(run_dtype(), {static_cast<py::ssize_t>(system.particle_count)},
                               {static_cast<py::ssize_t>(run_dtype().itemsize())},
                               system.inverse_mass, self));
  }

  py::dict springs(const py::object& self) {
    const clothlab_topology& topology = this->topology();
    const auto m = static_cast<py::ssize_t>(topology.spring_count);
    py::dict springs;
    springs["first"] =
        read_only(py::array_t<uint32_t>({m}, {sizeof(uint32_t)}, topology.first, self));
    springs["second"] =
        read_only(py::array_t<uint32_t>({m}, {sizeof(uint32_t)}, topology.second, self));
    springs["rest_length"] =
        read_only(py::array_t<double>({m}, {sizeof(double)}, topology.rest_length, self));
    springs["ks"] = read_only(py::array_t<double>({m}, {sizeof(double)}, topology.ks, self));
    springs["kd"] = read_only(py::array_t<double>({m}, {sizeof(double)}, topology.kd, self));
    springs["family"] =
        read_only(py::array_t<uint8_t>({m}, {sizeof(uint8_t)}, topology.family, self));
    return springs;
  }

  py::array triangles(const py::object& self) {
    const clothlab_topology& topology = this->topology();
    return read_only(
        py::array_t<uint32_t>({static_cast<py::ssize_t>(topology.triangle_count), py::ssize_t{3}},
                              {3 * sizeof(uint32_t), sizeof(uint32_t)}, topology.triangles, self));
  }

  py::dict energies() {
    Exclusive exclusive(busy_, "energies");
    const Cloth::Energy energy = simulation_->cloth().energy();
    py::dict result;
    result["kinetic"] = energy.kinetic;
    result["spring"] = energy.spring;
    result["gravity"] = energy.gravity;
    result["total"] = energy.total();
    return result;
  }

  py::dict stretch() {
    Exclusive exclusive(busy_, "stretch");
    const Cloth& cloth = simulation_->cloth();
    const Cloth::Stretch stretch = cloth.stretch(Cloth::Springs::Structural);
    py::dict result;
    result["max"] = stretch.max;
    result["mean"] = stretch.mean;
    result["max_away_from_pins"] = stretch.max_away_from_pins;
    result["p99"] = cloth.stretch_percentile(Cloth::Springs::Structural, 0.99);
    return result;
  }

  std::string verdict() {
    Exclusive exclusive(busy_, "verdict");
    return simulation_->record().verdict;
  }

  py::object summary() {
    Exclusive exclusive(busy_, "summary");
    return py::module_::import("json").attr("loads")(
        cli::summary_json(simulation_->record()).dump());
  }

  double time() const { return simulation_->time(); }
  uint64_t steps_taken() const { return simulation_->steps_taken(); }
  uint64_t steps_left() const { return simulation_->steps_left(); }
  bool finished() const { return simulation_->finished(); }
  double dt() const { return simulation_->config().dt; }
  const Cloth& cloth() const { return simulation_->cloth(); }
  std::string precision() const { return to_string(simulation_->cloth().precision()); }

 private:
  cli::RunConfig config_;
  std::unique_ptr<cli::Simulation> simulation_;
  // frames.*: written as the program writes them, from the stepping thread.
  std::optional<cli::FramesOutput> frames_;
  bool frames_finished_ = false;
  // Recursive: a progress callback may look at the simulation it reports on.
  std::recursive_mutex busy_;

  py::dtype run_dtype() const {
    return simulation_->cloth().precision() == Precision::Float64 ? py::dtype::of<double>()
                                                                  : py::dtype::of<float>();
  }

  // Any strides of the source; the state's rows are `stride` elements apart.
  template <class Real>
  static void copy_in(const py::array& values, bool by_rows, void* state, uint32_t stride) {
    const auto source = values.unchecked<Real, 2>();
    Real* target = static_cast<Real*>(state);
    const py::ssize_t n = by_rows ? source.shape(1) : source.shape(0);
    for (py::ssize_t k = 0; k < 3; ++k)
      for (py::ssize_t i = 0; i < n; ++i)
        target[k * stride + i] = by_rows ? source(k, i) : source(i, k);
  }

  static py::array read_only(py::array array) {
    array.attr("flags").attr("writeable") = false;
    return array;
  }

  const clothlab_topology& topology() {
    if (!topology_) {
      const clothlab_system& system = simulation_->cloth().system();
      const auto* extension = static_cast<const clothlab_topology_extension*>(
          system.get_extension(system.context, CLOTHLAB_EXT_TOPOLOGY));
      clothlab_topology topology{};
      topology.struct_size = sizeof topology;
      if (extension == nullptr || extension->get(system.context, &topology) != CLOTHLAB_OK)
        throw std::runtime_error("the cloth's topology (" CLOTHLAB_EXT_TOPOLOGY
                                 ") is not available");
      topology_ = topology;
    }
    return *topology_;
  }
  std::optional<clothlab_topology> topology_;

  // Steps in chunks of about a twentieth of a second with the GIL released: between them
  // Ctrl-C (KeyboardInterrupt) and the progress callback get their turn, at a cost per chunk
  // that is nothing beside its steps. The steps are the same whatever the chunks.
  uint64_t run_steps(uint64_t count, const py::object& progress) {
    uint64_t taken = 0;
    uint64_t chunk = 1;
    while (taken < count) {
      const uint64_t asked = std::min(chunk, count - taken);
      const auto start = std::chrono::steady_clock::now();
      uint64_t done = 0;
      {
        py::gil_scoped_release release;
        done = simulation_->step(asked, {frames_ ? &*frames_ : nullptr});
        // The frames folder's run.json gets the summary once the run is over.
        if (frames_ && simulation_->finished() && !frames_finished_) {
          frames_->finish(simulation_->record());
          frames_finished_ = true;
        }
      }
      taken += done;
      raise_if_failed();
      if (done < asked) break;
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if (!progress.is_none()) progress(taken, count);
      if (std::chrono::steady_clock::now() - start < std::chrono::milliseconds(50)) chunk *= 2;
    }
    return taken;
  }

  // A run that failed a check, or that ended with its solver short of its tolerance, raises
  // what the CLI says of it.
  void raise_if_failed() {
    if (simulation_->stable() && !simulation_->finished()) return;
    const cli::RunRecord record = simulation_->record();
    if (record.stable) return;
    const bool unconverged = record.failed_check == cli::unconverged_check;
    raise_diverged((unconverged ? "run " : "run diverged: ") + record.verdict,
                   record.failed_step.value_or(record.steps_taken), record.failed_check);
  }
};

}  // namespace

void bind_simulation(py::module_& module) {
  py::class_<PythonSimulation>(
      module, "Simulation",
      R"(One run: its plugins loaded, its scene assembled once, stepped by the caller.

config: a dict of settings (nested or dotted keys, as in a config file) or a YAML config
file's path; overrides: {"dotted.key": value} applied after it, as `clothlab --set`;
plugin_path: folders searched before CLOTHLAB_PLUGIN_PATH and the module's own plugins.)")
      .def(py::init<const py::object&, const py::dict&, const std::vector<std::string>&>(),
           py::arg("config"), py::arg("overrides") = py::dict(),
           py::arg("plugin_path") = std::vector<std::string>{})
      .def("step", &PythonSimulation::step, py::arg("count") = 1, py::arg("progress") = py::none(),
           "Takes `count` steps (the GIL released); returns the steps taken. Raises "
           "DivergedError when a stability check fails, InputError past the run's end. "
           "progress(taken, asked) is called about every twentieth of a second.")
      .def("advance", &PythonSimulation::advance, py::arg("seconds"),
           py::arg("progress") = py::none(),
           "Steps until the time has grown by `seconds` (whole steps, rounded up) or the run "
           "ends; returns the steps taken. progress as for step.")
      .def_property_readonly("time", &PythonSimulation::time, "Simulated time (s).")
      .def_property_readonly("steps_taken", &PythonSimulation::steps_taken)
      .def_property_readonly("steps_left", &PythonSimulation::steps_left)
      .def_property_readonly("finished", &PythonSimulation::finished)
      .def_property_readonly("dt", &PythonSimulation::dt)
      .def_property_readonly("precision", &PythonSimulation::precision)
      .def_property_readonly("rows",
                             [](const PythonSimulation& s) { return s.cloth().scene().rows; })
      .def_property_readonly("cols",
                             [](const PythonSimulation& s) { return s.cloth().scene().cols; })
      .def_property_readonly("particle_count",
                             [](const PythonSimulation& s) { return s.cloth().particle_count(); })
      .def_property(
          "positions",
          [](py::object self) { return self.cast<PythonSimulation&>().state_view(false, self); },
          [](PythonSimulation& s, const py::array& values) { s.set_state(false, values); },
          "(3, n) writable view of the engine's positions (rows x, y, z; .T is (n, 3)); call "
          "state_written() after writing into it. Assigning an array copies it in, checking its "
          "shape and dtype.")
      .def_property(
          "velocities",
          [](py::object self) { return self.cast<PythonSimulation&>().state_view(true, self); },
          [](PythonSimulation& s, const py::array& values) { s.set_state(true, values); },
          "(3, n) writable view of the engine's velocities, as positions.")
      .def_property_readonly(
          "inverse_masses",
          [](py::object self) { return self.cast<PythonSimulation&>().inverse_masses(self); },
          "(n,) read-only view; 0 for pinned particles.")
      .def_property_readonly(
          "springs", [](py::object self) { return self.cast<PythonSimulation&>().springs(self); },
          "Read-only views: first, second, rest_length, ks, kd, family (0 structural, 1 shear, "
          "2 flexion).")
      .def_property_readonly(
          "triangles",
          [](py::object self) { return self.cast<PythonSimulation&>().triangles(self); },
          "(m, 3) read-only view of the surface's particle indices.")
      .def("state_written", &PythonSimulation::state_written,
           "After writing through the positions or velocities views: the integrator drops its "
           "history (Verlet's previous step) and the next step starts from the state as it is. "
           "Assigning a whole array (sim.positions = a) does this itself.")
      .def("energies", &PythonSimulation::energies, "kinetic, spring, gravity and total (J).")
      .def("stretch", &PythonSimulation::stretch,
           "Warp/weft length over rest length now: max, mean, max_away_from_pins, p99.")
      .def_property_readonly("verdict", &PythonSimulation::verdict, "The verdict so far.")
      .def("summary", &PythonSimulation::summary,
           "The run so far as the CLI's --json summary, a dict with its fields.");
}

}  // namespace clothlab::python
