// A faulty plugin's library of one integrator whose descriptor is the SDK's with an edit
// applied: faults the SDK itself would not let through (a create that skips validation, a
// precision mask).
#pragma once

#include <clothlab/sdk.hpp>

namespace clothlab::faulty {

template <class Impl, class Edit>
const clothlab_plugin_descriptor* edited_library(const char* library_name, Edit edit) {
  static const clothlab_integrator integrator = [&] {
    clothlab_integrator copy = *sdk::integrators<Impl>::list()[0];
    edit(copy);
    return copy;
  }();
  static const clothlab_integrator* const integrators[] = {&integrator};
  static const clothlab_plugin_descriptor descriptor = {
      {CLOTHLAB_ABI_VERSION_MAJOR, CLOTHLAB_ABI_VERSION_MINOR},
      sizeof(clothlab_plugin_descriptor),
      1,
      0,
      0,
      library_name,
      "0.0.1",
      integrators,
      nullptr,
  };
  return &descriptor;
}

}  // namespace clothlab::faulty
