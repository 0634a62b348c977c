// Loads a plugin library with dlopen and exposes its descriptor, as a host would, so the
// tests drive the built .so through the C ABI only.
#pragma once

#include <clothlab/plugin.h>
#include <dlfcn.h>

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace clothlab::test {

class PluginLibrary {
 public:
  explicit PluginLibrary(const std::string& path)
      : handle_(dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL)) {
    if (handle_ == nullptr) throw std::runtime_error("dlopen " + path + ": " + dlerror());
    auto entry =
        reinterpret_cast<clothlab_plugin_entry_fn>(dlsym(handle_, CLOTHLAB_PLUGIN_ENTRY_SYMBOL));
    if (entry == nullptr) throw std::runtime_error(path + " has no entry symbol");
    descriptor_ = entry();
  }
  ~PluginLibrary() { dlclose(handle_); }
  PluginLibrary(const PluginLibrary&) = delete;
  PluginLibrary& operator=(const PluginLibrary&) = delete;

  const clothlab_plugin_descriptor& descriptor() const { return *descriptor_; }

  const clothlab_integrator& integrator() const {
    if (descriptor_->integrator_count != 1) throw std::runtime_error("expected one integrator");
    return *descriptor_->integrators[0];
  }
  const clothlab_scenario& scenario() const {
    if (descriptor_->scenario_count != 1) throw std::runtime_error("expected one scenario");
    return *descriptor_->scenarios[0];
  }

 private:
  void* handle_;
  const clothlab_plugin_descriptor* descriptor_ = nullptr;
};

// One value per spec, each its default.
inline std::vector<clothlab_param_value> default_values(const clothlab_param_spec* specs,
                                                        uint32_t count) {
  std::vector<clothlab_param_value> values(count);
  for (uint32_t i = 0; i < count; ++i)
    for (int k = 0; k < 3; ++k) values[i].v[k] = specs[i].default_value[k];
  return values;
}

// Sets the value of the parameter called `name`; throws if there is none.
inline void set_value(std::vector<clothlab_param_value>& values, const clothlab_param_spec* specs,
                      std::string_view name, clothlab_param_value value) {
  for (size_t i = 0; i < values.size(); ++i)
    if (name == specs[i].name) {
      values[i] = value;
      return;
    }
  throw std::runtime_error("no parameter " + std::string(name));
}

}  // namespace clothlab::test
