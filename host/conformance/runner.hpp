// Runs every conformance check on a plugin library, each isolated in a child process
// unless asked to stay in-process, and reports each result as it completes.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "check.hpp"
#include "check_filter.hpp"

namespace clothlab::conformance {

struct CheckResult {
  std::string plugin;     // library file name without ".so"
  std::string component;  // "library" or a component id
  std::string check;      // "numerics.order-spring"
  bool passed = false;
  std::string reason;
  double seconds = 0;

  std::string full_name() const { return plugin + ":" + component + " " + check; }
};

struct RunOptions {
  Settings settings;
  double timeout_s = 10;
  bool in_process = false;
  std::shared_ptr<const CheckFilter> filter;  // matched against CheckResult::full_name()
};

using ResultSink = std::function<void(const CheckResult&)>;

// Checks one library; calls `sink` once per check that matches the filter. Throws
// std::invalid_argument when a --param override does not fit the component it names.
void run_plugin(const std::string& path, const RunOptions& options, const ResultSink& sink);

}  // namespace clothlab::conformance
