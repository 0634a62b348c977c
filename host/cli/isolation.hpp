// The clothlab program's use of the one child-process runner (clothlab::process): plugin
// code runs in a child whose JSON answer comes back, so a crash, hang or runaway exception
// ends only that child, and is reported with the plugin call it happened in.
#pragma once

#include <clothlab/process/isolation.hpp>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>

namespace clothlab::host {
struct PluginCallRecord;
}

namespace clothlab::cli {

// A process::Worker that takes and answers JSON: serve(request) runs in the worker child.
// ask returns serve's JSON, or throws std::runtime_error with a one-line reason when the child
// threw (its message), crashed (the signal or exit status) or outlived timeout_s (then the
// next ask starts a new child); a crash or timeout inside a plugin call names it
// (plugin_call_marker.hpp): "crashed: signal 11 (SIGSEGV) in ID.PHASE (LIBRARY) at step N".
// Throws InputError / PluginLoadError / PluginError as the child did, so exit codes do not
// depend on where the work ran. With forward_interrupt, a SIGINT or SIGTERM the program gets
// (interrupt.hpp) is passed on to the child.
class JsonWorker {
 public:
  using Serve = std::function<nlohmann::json(const nlohmann::json& request)>;
  explicit JsonWorker(const Serve& serve, bool forward_interrupt = false);
  nlohmann::json ask(const nlohmann::json& request, double timeout_s);

 private:
  // Shared with the child: where its plugin calls are marked. Declared before the worker, so
  // it outlives it.
  std::shared_ptr<host::PluginCallRecord> call_;
  process::Worker worker_;
};

// Runs work() in a child of its own (a JsonWorker asked once) and returns its JSON.
nlohmann::json run_isolated(const std::function<nlohmann::json()>& work, double timeout_s,
                            bool forward_interrupt = false);

}  // namespace clothlab::cli
