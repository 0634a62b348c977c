// A plugin library opened with dlopen(RTLD_NOW): the runner tests plugins below the host's
// loader, so it keeps its own thin layer and reports every failure as text.
#pragma once

#include <clothlab/plugin.h>

#include <string>

namespace clothlab::conformance {

class PluginLibrary {
 public:
  // Throws std::runtime_error with dlerror()'s text when the library does not open or
  // lacks the entry symbol.
  explicit PluginLibrary(const std::string& path);
  ~PluginLibrary();
  PluginLibrary(const PluginLibrary&) = delete;
  PluginLibrary& operator=(const PluginLibrary&) = delete;

  // Calls the entry point; the pointer stays valid while the library is open.
  const clothlab_plugin_descriptor* descriptor() const;

  // Whether the library at `path` is mapped in this process (RTLD_NOLOAD: opens nothing).
  static bool is_loaded(const std::string& path);

 private:
  void* handle_ = nullptr;
  clothlab_plugin_entry_fn entry_ = nullptr;
};

std::string to_string(const clothlab_abi_version& version);

}  // namespace clothlab::conformance
