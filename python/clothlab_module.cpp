// The Python module clothlab's entry: its exceptions, plugins(), Simulation and the CLI's
// modes (choose, sweep, conformance, view).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "plugin_listing.hpp"
#include "python_errors.hpp"
#include "simulation_binding.hpp"
#include "tools_binding.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_clothlab, module) {
  module.doc() = "ClothLab's session stepped from Python (docs/guide/python.md)";
  clothlab::python::register_errors(module);
  module.def(
      "plugins",
      [](const std::vector<std::string>& plugin_path) {
        const nlohmann::json listing = clothlab::cli::listing_json(
            clothlab::cli::plugin_listing(clothlab::python::module_search_path(plugin_path)));
        return py::module_::import("json").attr("loads")(listing.dump());
      },
      py::arg("plugin_path") = std::vector<std::string>{},
      "What `clothlab --list-plugins --json -` prints, as a dict "
      "(docs/reference/plugin-listing.md): "
      "each library with its integrators and scenarios, their parameters, traits and extensions.");
  clothlab::python::bind_simulation(module);
  clothlab::python::bind_tools(module);
}
