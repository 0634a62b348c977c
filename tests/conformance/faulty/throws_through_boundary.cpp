// Faulty: a hand-written C ABI integrator (no SDK guard) whose step throws a C++
// exception straight through the C boundary (robustness.no-throw catches it).
#include <clothlab/plugin.h>

#include <cstdio>
#include <new>
#include <stdexcept>

namespace {

struct Instance {};

clothlab_status create(const clothlab_param_value*, uint32_t count, void** out,
                       clothlab_message* error) {
  if (count != 0) {
    std::snprintf(error->text, sizeof error->text, "expected 0 parameter values, got %u",
                  static_cast<unsigned>(count));
    return CLOTHLAB_ERROR_INVALID_ARGUMENT;
  }
  *out = new (std::nothrow) Instance;
  return *out != nullptr ? CLOTHLAB_OK : CLOTHLAB_ERROR_OUT_OF_MEMORY;
}

clothlab_status prepare(void*, const clothlab_system*, clothlab_message*) { return CLOTHLAB_OK; }

clothlab_status step(void*, const clothlab_system*, double, double, clothlab_message*) {
  throw std::runtime_error("thrown through the C ABI");
}

void destroy(void* instance) { delete static_cast<Instance*>(instance); }

const clothlab_integrator integrator = {
    sizeof(clothlab_integrator),
    0,
    "throws-through-boundary",
    "Integrator whose step throws",
    "0.0.1",
    "faulty: step throws a C++ exception across the C ABI",
    1,
    1,
    (1u << CLOTHLAB_FLOAT32) | (1u << CLOTHLAB_FLOAT64),
    0,
    nullptr,
    create,
    prepare,
    step,
    destroy,
    nullptr,
};

const clothlab_integrator* const integrators[] = {&integrator};

}  // namespace

extern "C" CLOTHLAB_EXPORT const clothlab_plugin_descriptor* clothlab_plugin_entry(void) {
  static const clothlab_plugin_descriptor descriptor = {
      {CLOTHLAB_ABI_VERSION_MAJOR, CLOTHLAB_ABI_VERSION_MINOR},
      sizeof(clothlab_plugin_descriptor),
      1,
      0,
      0,
      "faulty-throws-through-boundary",
      "0.0.1",
      integrators,
      nullptr,
  };
  return &descriptor;
}
