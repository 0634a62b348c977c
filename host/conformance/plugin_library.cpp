#include "plugin_library.hpp"

#include <dlfcn.h>

#include <stdexcept>

namespace clothlab::conformance {

PluginLibrary::PluginLibrary(const std::string& path) {
  handle_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle_ == nullptr) throw std::runtime_error(std::string("dlopen failed: ") + dlerror());
  entry_ = reinterpret_cast<clothlab_plugin_entry_fn>(dlsym(handle_, CLOTHLAB_PLUGIN_ENTRY_SYMBOL));
  if (entry_ == nullptr) {
    dlclose(handle_);
    throw std::runtime_error(path + ": no symbol " CLOTHLAB_PLUGIN_ENTRY_SYMBOL);
  }
}

PluginLibrary::~PluginLibrary() { dlclose(handle_); }

const clothlab_plugin_descriptor* PluginLibrary::descriptor() const { return entry_(); }

bool PluginLibrary::is_loaded(const std::string& path) {
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_NOLOAD);
  if (handle == nullptr) return false;
  dlclose(handle);
  return true;
}

std::string to_string(const clothlab_abi_version& version) {
  return std::to_string(version.major) + "." + std::to_string(version.minor);
}

}  // namespace clothlab::conformance
