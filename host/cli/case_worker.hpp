// The cases of a sweep, a stability search or a choice, run one after another in one reused
// child process (a JsonWorker): a case costs a round trip, not a process start, and a crash or
// a hang still ends only the case that caused it (the next case gets a new child).
#pragma once

#include <clothlab/host/plugin_search_path.hpp>
#include <clothlab/sweep/case_spec.hpp>
#include <nlohmann/json.hpp>

#include "case_execution.hpp"
#include "isolation.hpp"

namespace clothlab::cli {

class CaseWorker {
 public:
  // search_path must outlive the worker.
  explicit CaseWorker(const host::PluginSearchPath& search_path);

  // run_case, predict_case and local_solve_case (case_execution.hpp) of the case's settings, in
  // the child, bounded by the case's timeout; throws as JsonWorker::ask.
  CaseRun run(const sweep::CaseSpec& c, bool with_positions = false);
  nlohmann::json predict(const sweep::CaseSpec& c);
  nlohmann::json local_solve(const sweep::CaseSpec& c);

 private:
  nlohmann::json ask(const std::string& task, const sweep::CaseSpec& c);
  JsonWorker worker_;
};

}  // namespace clothlab::cli
