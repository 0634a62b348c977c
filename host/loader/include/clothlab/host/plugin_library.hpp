// One loaded plugin library: opened once (LibraryHandle), its descriptor validated
// (descriptor_findings), its components wrapped. The one way the host, the conformance runner,
// the tests and the benchmarks load a plugin.
#pragma once

#include <clothlab/plugin.h>

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "clothlab/host/components.hpp"
#include "clothlab/host/plugin_search_path.hpp"

namespace clothlab::host {

class PluginLibrary {
 public:
  // Opens the file and refuses it on the first of descriptor_findings (ABI major, struct sizes,
  // strings, functions, parameter specs, ids). Throws PluginLoadError naming the file, and for a
  // finding its field, value and what is allowed; `searched` (the search path) is added when
  // given.
  static PluginLibrary load(const std::filesystem::path& path, std::string_view searched = {});

  // Resolves an --integrator/--scenario argument on the search path, then loads it.
  static PluginLibrary find(std::string_view argument, const PluginSearchPath& search_path);

  const std::filesystem::path& path() const { return path_; }
  std::string_view name() const { return descriptor_->library_name; }
  std::string_view version() const { return descriptor_->library_version; }
  clothlab_abi_version abi_version() const { return descriptor_->abi_version; }

  const std::vector<IntegratorPlugin>& integrators() const { return integrators_; }
  const std::vector<ScenarioPlugin>& scenarios() const { return scenarios_; }

  // The library's only integrator, or the one whose id is the file's stem; otherwise a
  // PluginLoadError listing what the library provides.
  const IntegratorPlugin& integrator() const;
  const ScenarioPlugin& scenario() const;

 private:
  PluginLibrary() = default;

  std::shared_ptr<const LibraryHandle> handle_;
  std::filesystem::path path_;
  const clothlab_plugin_descriptor* descriptor_ = nullptr;
  std::vector<IntegratorPlugin> integrators_;
  std::vector<ScenarioPlugin> scenarios_;
};

// The loader's gate, as load() applies it: the first of descriptor_findings as one line, or ""
// when load() accepts the descriptor.
std::string descriptor_refusal(const clothlab_plugin_descriptor& descriptor);

// Load errors for one of several libraries, and ids that appear in more than one.
struct LibraryScan {
  std::vector<PluginLibrary> libraries;
  std::vector<std::string> errors;  // one line each
};
// Loads every library on the search path; duplicate component ids across libraries are
// reported as errors naming both files.
LibraryScan scan_libraries(const PluginSearchPath& search_path);

}  // namespace clothlab::host
