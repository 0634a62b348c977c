// The CLI's own machinery, in-process: the same checks, results files and error texts as
// `clothlab --choose`, `clothlab --config sweep.yaml`, `clothlab-conformance` and `clothlab
// view`. Plugin code still runs where the CLI runs it, in forked children (a sweep's and a
// choice's case worker, a conformance check's child), so a crashing plugin fails a row or a
// check and leaves the interpreter running; the GIL is released meanwhile.
#include "tools_binding.hpp"

#include <pybind11/stl.h>

#include <clothlab/config/yaml_settings.hpp>
#include <clothlab/host/errors.hpp>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <sstream>

#include "check_filter.hpp"
#include "choose_mode.hpp"
#include "report.hpp"
#include "run_config.hpp"
#include "runner.hpp"
#include "simulation_binding.hpp"
#include "sweep_file.hpp"
#include "sweep_mode.hpp"
#include "view_bundle.hpp"

namespace py = pybind11;
namespace fs = std::filesystem;

namespace clothlab::python {

namespace {

py::object parse_json_text(const std::string& text) {
  return py::module_::import("json").attr("loads")(text);
}

py::object read_json_file(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw host::InputError("cannot read " + path.string());
  return parse_json_text(std::string(std::istreambuf_iterator<char>(in), {}));
}

// --choose: returns the ranking (<choose.output>-ranked.json's "ranking").
py::object choose(const py::object& config, const py::dict& overrides,
                  const std::vector<std::string>& plugin_path) {
  const std::vector<config::Setting> settings = settings_of(config, overrides);
  const fs::path output = cli::resolve_configuration(settings).choose.output;
  const host::PluginSearchPath search_path = module_search_path(plugin_path);
  std::ostringstream table;
  {
    py::gil_scoped_release released;
    cli::run_choose(settings, search_path, table, false);
  }
  return read_json_file(output.string() + "-ranked.json")["ranking"];
}

// A sweep file: returns its rows (<sweep.output>.json's "rows").
py::object sweep(const py::object& config, const py::dict& overrides,
                 const std::vector<std::string>& plugin_path) {
  cli::SweepRequest request;
  request.config_file = py::module_::import("os").attr("fspath")(config).cast<std::string>();
  if (!cli::is_sweep_file(request.config_file)) {
    (void)config::read_config_file(request.config_file);  // the reader's error, if it has one
    throw host::InputError(request.config_file.string() +
                           " has no sweep: section; clothlab.sweep runs a sweep file");
  }
  request.overrides = override_settings(overrides);
  request.plugin_paths = plugin_path;
  const fs::path output = cli::load_sweep(request.config_file, request.overrides).output;
  const host::PluginSearchPath search_path = module_search_path(plugin_path);
  std::ostringstream summary;
  {
    py::gil_scoped_release released;
    cli::run_sweep_file(request, search_path, summary);
  }
  return read_json_file(output.string() + ".json")["rows"];
}

// clothlab-conformance on one plugin (a name found on the plugin path, or a file): returns the
// results of its checks, as its --json report lists them.
py::object conformance(const std::string& plugin, const std::vector<std::string>& plugin_path,
                       const std::string& filter, uint64_t seed, double timeout_s) {
  if (!(timeout_s > 0) || timeout_s > 86400)
    throw host::InputError("timeout = " + std::to_string(timeout_s) +
                           ": allowed (0, 86400] seconds");
  conformance::RunOptions options;
  options.settings.seed = seed;
  options.timeout_s = timeout_s;
  if (!filter.empty()) {
    try {
      options.filter = std::make_shared<const conformance::CheckFilter>(filter);
    } catch (const std::invalid_argument& error) {
      throw host::InputError("filter = \"" + filter + "\": not a valid regular expression (" +
                             error.what() + ")");
    }
  }
  const fs::path path = module_search_path(plugin_path).resolve(plugin);
  conformance::RunReport report;
  report.seed = seed;
  report.timeout_s = timeout_s;
  {
    py::gil_scoped_release released;
    try {
      conformance::run_plugin(path.string(), options, [&](const conformance::CheckResult& result) {
        report.results.push_back(result);
      });
    } catch (const std::invalid_argument& error) {
      throw host::InputError(error.what());
    }
  }
  if (options.filter && report.results.empty())
    throw host::InputError("filter = \"" + filter + "\" matched no check");
  return parse_json_text(conformance::to_json(report))["checks"];
}

// The viewer's assets as seen from this module: inside the package (pip), the install tree's,
// the build tree's.
fs::path viewer_assets() {
  const fs::path here = module_folder();
  for (const char* relative :
       {"viewer", CLOTHLAB_VIEWER_FROM_MODULE, "../../share/clothlab/viewer"}) {
    const fs::path folder = (here / relative).lexically_normal();
    std::error_code error;
    if (fs::is_regular_file(folder / "index.html", error)) return folder;
  }
  return (here / "viewer").lexically_normal();
}

// clothlab view: writes the page for the frame folders; returns its index.html.
std::string view(const std::vector<std::string>& runs, const std::string& out, size_t max_frames) {
  if (runs.empty()) throw host::InputError("view: no frames folder; allowed: one or more");
  if (max_frames < 2)
    throw host::InputError("max_frames = " + std::to_string(max_frames) + ": allowed 2 or more");
  viewer::ViewRequest request;
  request.runs.assign(runs.begin(), runs.end());
  request.out = out;
  request.assets = viewer_assets();
  request.max_frames = max_frames;
  return viewer::write_view_bundle(request).string();
}

}  // namespace

void bind_tools(py::module_& module) {
  module.def("choose", &choose, py::arg("config"), py::arg("overrides") = py::dict(),
             py::arg("plugin_path") = std::vector<std::string>{},
             R"(What `clothlab --choose` does, in-process (probes in its forked worker): writes
<choose.output>-ranked.csv/.json and the probes, and returns the ranking, one dict per
integrator as in <choose.output>-ranked.json (docs/guide/choosing.md). config and overrides
as for Simulation; frame_rate is required.)");
  module.def("sweep", &sweep, py::arg("config"), py::arg("overrides") = py::dict(),
             py::arg("plugin_path") = std::vector<std::string>{},
             R"(What `clothlab --config SWEEP.yaml` does, in-process (cases in its forked worker):
runs the sweep file's cases into <sweep.output>.sqlite/.csv/.json (resuming none) and returns
the rows of <sweep.output>.json, one dict per case (docs/guide/sweeps.md). overrides: dotted
keys added to the sweep's fixed settings.)");
  module.def("conformance", &conformance, py::arg("plugin"),
             py::arg("plugin_path") = std::vector<std::string>{}, py::arg("filter") = "",
             py::arg("seed") = 1, py::arg("timeout") = 10.0,
             R"(What `clothlab-conformance PLUGIN --json` reports, in-process (each check in its
own forked child): one dict per check, as the JSON report's "checks"
(docs/reference/conformance.md). plugin: a name on the plugin path or a file; filter: a POSIX
extended regular expression searched in "plugin:component check".)");
  module.def("view", &view, py::arg("runs"), py::arg("out"), py::arg("max_frames") = 600,
             R"(What `clothlab view RUN... --out OUT` writes: the page that plays the frame
folders (docs/guide/frames-and-viewer.md). Returns the path of its index.html.)");
}

}  // namespace clothlab::python
