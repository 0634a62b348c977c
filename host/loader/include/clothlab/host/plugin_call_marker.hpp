// Which plugin code the host is running: the library, the component and the phase (create,
// prepare, step, ...), kept in a record that a crash leaves behind. The clothlab CLI places the
// record in memory its child process shares with the parent, so a crash's message names the
// plugin, the phase and the step ("crashed: signal 11 (SIGSEGV) in xpbd.step (.../xpbd.so) at
// step 12"). Without a placed record marking costs one branch.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace clothlab::host {

// Plain bytes, readable from another process after this one died.
struct PluginCallRecord {
  char library[256];   // the library's path (truncated when longer)
  char component[64];  // the component's id
  char phase[16];      // "create", "prepare", "step", "describe", "statistics", "destroy"
  uint64_t step;       // step: the instance's steps since its prepare, this one included
  uint32_t active;     // 1 from just before the plugin's function is called until it returns
};

// The plugin library and component a call goes to.
struct PluginCallSite {
  std::filesystem::path library;
  std::string component;
};

// From now on, plugin calls are marked in *record (nullptr: not marked, the default). Calls are
// marked from one thread at a time: the CLI's run child steps one instance.
void mark_plugin_calls_in(PluginCallRecord* record);

// Marks one call while it lives.
class PluginCallMark {
 public:
  PluginCallMark(const PluginCallSite& site, const char* phase, uint64_t step = 0) noexcept;
  ~PluginCallMark();
  PluginCallMark(const PluginCallMark&) = delete;
  PluginCallMark& operator=(const PluginCallMark&) = delete;
};

// " in xpbd.step (plugins/xpbd.so) at step 12" (" in flag.create (...)" outside step) while a
// call was active, "" otherwise.
std::string describe_active_call(const PluginCallRecord& record);

}  // namespace clothlab::host
