#include "python_errors.hpp"

#include <clothlab/host/errors.hpp>
#include <clothlab/io/atomic_file.hpp>
#include <stdexcept>

namespace py = pybind11;

namespace clothlab::python {

namespace {

PyObject* input_error = nullptr;
PyObject* plugin_load_error = nullptr;
PyObject* plugin_error = nullptr;
PyObject* diverged_error = nullptr;

PyObject* new_exception(py::module_& module, const char* name, PyObject* base) {
  const std::string qualified = std::string("clothlab.") + name;
  PyObject* type = PyErr_NewException(qualified.c_str(), base, nullptr);
  module.add_object(name, py::handle(type));
  return type;
}

void set_error(PyObject* type, const std::string& message) {
  PyErr_SetString(type, host::one_line(message).c_str());
}

}  // namespace

void register_errors(py::module_& module) {
  input_error = new_exception(module, "InputError", PyExc_ValueError);
  plugin_error = new_exception(module, "PluginError", PyExc_RuntimeError);
  plugin_load_error = new_exception(module, "PluginLoadError", plugin_error);
  diverged_error = new_exception(module, "DivergedError", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      std::rethrow_exception(thrown);
    } catch (const host::InputError& error) {
      set_error(input_error, error.what());
    } catch (const io::WriteError& error) {
      set_error(input_error, error.what());
    } catch (const host::PluginLoadError& error) {
      set_error(plugin_load_error, error.what());
    } catch (const host::PluginError& error) {
      set_error(plugin_error, error.what());
    }
  });
}

void raise_diverged(const std::string& message, uint64_t step, const std::string& check) {
  py::object error = py::reinterpret_steal<py::object>(
      PyObject_CallFunction(diverged_error, "s", host::one_line(message).c_str()));
  if (!error) throw py::error_already_set();
  error.attr("step") = step;
  error.attr("check") = check;
  PyErr_SetObject(diverged_error, error.ptr());
  throw py::error_already_set();
}

}  // namespace clothlab::python
