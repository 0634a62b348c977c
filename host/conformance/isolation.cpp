#include "isolation.hpp"

#include <clothlab/process/isolation.hpp>
#include <exception>
#include <string>

namespace clothlab::conformance {

Verdict run_guarded(const std::function<Verdict()>& body) {
  try {
    return body();
  } catch (const CheckFailure& failure) {
    return {false, failure.what()};
  } catch (const std::exception& e) {
    return {false, std::string("exception escaped: ") + e.what()};
  } catch (...) {
    return {false, "exception of unknown type escaped"};
  }
}

Verdict run_isolated(const std::function<Verdict()>& body, double timeout_s) {
  process::IsolationOptions options;
  options.timeout_s = timeout_s;
  options.capture_stderr = true;  // a sanitizer's report belongs in the failure's reason
  const process::ChildOutcome outcome = process::run_isolated(
      [&] {
        const Verdict verdict = run_guarded(body);
        return std::string(verdict.passed ? "P" : "F") + verdict.reason;
      },
      options);
  if (!outcome.answered() || outcome.answer.empty()) return {false, outcome.problem};
  return {outcome.answer[0] == 'P', outcome.answer.substr(1)};
}

}  // namespace clothlab::conformance
