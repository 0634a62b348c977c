// loading.*: the library opens, exports only its entry point, and the version gate works.
#include <clothlab/host/descriptor_findings.hpp>
#include <clothlab/host/errors.hpp>
#include <clothlab/host/library_handle.hpp>
#include <clothlab/host/plugin_library.hpp>
#include <string>

#include "check.hpp"
#include "elf_symbols.hpp"

namespace clothlab::conformance {
namespace {

constexpr int reload_rounds = 20;

Verdict exports_only_entry(const std::string& path) {
  const std::vector<std::string> names = exported_symbols(path);
  std::string listed;
  for (const std::string& name : names) listed += (listed.empty() ? "" : ", ") + name;
  require(names.size() == 1 && names[0] == CLOTHLAB_PLUGIN_ENTRY_SYMBOL,
          "exports " + std::to_string(names.size()) + " symbols (" + listed +
              "); expected exactly " CLOTHLAB_PLUGIN_ENTRY_SYMBOL);
  return {true, ""};
}

using host::abi_version_text;

Verdict opens(const std::string& path) {
  const auto library = host::LibraryHandle::open(path);
  const clothlab_plugin_descriptor* descriptor = library->descriptor();
  require(descriptor != nullptr, CLOTHLAB_PLUGIN_ENTRY_SYMBOL " returned null");
  return {true, "built for ABI " + abi_version_text(descriptor->abi_version)};
}

Verdict abi_version_accepted(const std::string& path) {
  const auto library = host::LibraryHandle::open(path);
  const clothlab_abi_version version = library->descriptor()->abi_version;
  require(clothlab_abi_is_compatible(version),
          "built for ABI " + abi_version_text(version) + "; this host accepts " +
              std::to_string(CLOTHLAB_ABI_VERSION_MAJOR) + ".x");
  return {true, "ABI " + abi_version_text(version)};
}

// The real loader's gate (host::descriptor_refusal, what PluginLibrary::load applies), applied
// to copies of this plugin's descriptor with edited versions.
Verdict abi_policy(const std::string& path) {
  const auto library = host::LibraryHandle::open(path);
  // A descriptor of another major may have another layout: copy only its version then.
  const clothlab_plugin_descriptor& original = *library->descriptor();
  clothlab_plugin_descriptor copy{};
  copy.abi_version = original.abi_version;
  const bool same_major = clothlab_abi_is_compatible(original.abi_version);
  if (same_major) copy = original;
  for (const clothlab_abi_version other :
       {clothlab_abi_version{CLOTHLAB_ABI_VERSION_MAJOR + 1, 0},
        clothlab_abi_version{CLOTHLAB_ABI_VERSION_MAJOR - 1, CLOTHLAB_ABI_VERSION_MINOR}}) {
    copy.abi_version = other;
    require(!host::descriptor_refusal(copy).empty(),
            "the host loader accepts major " + abi_version_text(other));
  }
  if (!same_major) return {true, "other majors refused (this plugin's own layout is not read)"};
  // A descriptor the loader refuses as it is says nothing about the version rule.
  const std::string as_built = host::descriptor_refusal(original);
  require(as_built.empty(), "the host loader refuses it at its own version " +
                                abi_version_text(original.abi_version) + ": " + as_built);
  for (uint32_t minor = 0; minor <= CLOTHLAB_ABI_VERSION_MINOR + 1; ++minor) {
    copy.abi_version = {CLOTHLAB_ABI_VERSION_MAJOR, minor};
    const std::string refusal = host::descriptor_refusal(copy);
    require(refusal.empty(), "the host loader refuses minor version " +
                                 abi_version_text(copy.abi_version) + ": " + refusal);
  }
  return {true, "the host loader refuses other majors and accepts every minor"};
}

// The real host's loader (PluginLibrary::load, the descriptor's first finding refused) accepts
// the library.
Verdict host_accepts(const std::string& path) {
  try {
    const host::PluginLibrary library = host::PluginLibrary::load(path);
    return {true, std::to_string(library.integrators().size()) + " integrators, " +
                      std::to_string(library.scenarios().size()) + " scenarios"};
  } catch (const host::PluginLoadError& e) {
    throw CheckFailure(std::string("the host refuses it: ") + e.what());
  }
}

// Each cycle runs the library's initialisers and finalisers again (the runner holds no handle
// meanwhile), unless it is linked NODELETE and stays mapped (xpbd, for its OpenMP threads).
Verdict reloads(const std::string& path) {
  std::string first_name;
  bool stays_mapped = false;
  for (int round = 0; round < reload_rounds; ++round) {
    {
      const auto library = host::LibraryHandle::open(path);
      const clothlab_plugin_descriptor* descriptor = library->descriptor();
      require(descriptor != nullptr, "entry returned null on load " + std::to_string(round + 1));
      const std::string name = descriptor->library_name != nullptr ? descriptor->library_name : "";
      if (round == 0) first_name = name;
      require(name == first_name, "library_name changed on reload " + std::to_string(round + 1));
    }
    stays_mapped = host::LibraryHandle::is_loaded(path);
  }
  return {true, std::to_string(reload_rounds) + " load/unload cycles" +
                    (stays_mapped ? " (stays mapped after dlclose: NODELETE)" : "")};
}

}  // namespace

std::vector<Check> loading_checks(const std::string& path) {
  return {
      {"library", "loading.dlopen", [path] { return opens(path); }},
      {"library", "loading.abi-version", [path] { return abi_version_accepted(path); }},
      {"library", "loading.exports", [path] { return exports_only_entry(path); }},
      {"library", "loading.abi-policy", [path] { return abi_policy(path); }},
      {"library", "loading.reload", [path] { return reloads(path); }},
      {"library", "loading.host-loader", [path] { return host_accepts(path); }},
  };
}

}  // namespace clothlab::conformance
