// clothlab.choose, clothlab.sweep, clothlab.conformance and clothlab.view: the CLI's modes
// called in-process, each returning its table as a list of dicts.
#pragma once

#include <pybind11/pybind11.h>

namespace clothlab::python {

void bind_tools(pybind11::module_& module);

}  // namespace clothlab::python
