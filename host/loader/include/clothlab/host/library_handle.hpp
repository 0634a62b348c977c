// One plugin library file, opened once with dlopen and its entry point found. The components
// and instances of a library share one handle, so the code stays loaded while any of them lives.
#pragma once

#include <clothlab/plugin.h>

#include <filesystem>
#include <memory>
#include <string_view>

namespace clothlab::host {

class LibraryHandle {
 public:
  // Opens the file with RTLD_NOW | RTLD_LOCAL and finds clothlab_plugin_entry. Throws
  // PluginLoadError naming the file: no such file, not a loadable shared library (with the
  // dynamic loader's reason) or no entry symbol; `searched` (the search path) is added when given.
  static std::shared_ptr<const LibraryHandle> open(const std::filesystem::path& path,
                                                   std::string_view searched = {});
  ~LibraryHandle();
  LibraryHandle(const LibraryHandle&) = delete;
  LibraryHandle& operator=(const LibraryHandle&) = delete;

  // Calls the entry point; null when the plugin returns null. The descriptor stays valid while
  // the handle lives.
  const clothlab_plugin_descriptor* descriptor() const { return entry_(); }

  // Whether the file is mapped in this process (RTLD_NOLOAD: opens nothing).
  static bool is_loaded(const std::filesystem::path& path);

 private:
  LibraryHandle(void* library, clothlab_plugin_entry_fn entry) : library_(library), entry_(entry) {}

  void* library_;
  clothlab_plugin_entry_fn entry_;
};

}  // namespace clothlab::host
