#include "isolation.hpp"

#include <sys/mman.h>

#include <clothlab/host/errors.hpp>
#include <clothlab/host/plugin_call_marker.hpp>
#include <clothlab/process/isolation.hpp>
#include <exception>
#include <new>
#include <stdexcept>
#include <string>

#include "interrupt.hpp"

namespace clothlab::cli {

namespace {

// JSON as text for the pipe: a request, or an answer's envelope ({"value": ...} or {"error":
// kind, "message": text}). Strings that are not UTF-8 (a plugin's message with byte 0xFF) are
// kept, with U+FFFD for the bad bytes.
std::string envelope(const nlohmann::json& body) {
  return body.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string answer_of(const std::function<nlohmann::json()>& work) {
  try {
    return envelope({{"value", work()}});
  } catch (const host::InputError& error) {
    return envelope({{"error", "input"}, {"message", error.what()}});
  } catch (const host::PluginLoadError& error) {
    return envelope({{"error", "load"}, {"message", error.what()}});
  } catch (const host::PluginError& error) {
    return envelope({{"error", "plugin"},
                     {"status", static_cast<int>(error.status())},
                     {"message", error.what()}});
  } catch (const std::bad_alloc&) {
    return envelope({{"error", "other"}, {"message", "out of memory"}});
  } catch (const std::exception& error) {
    return envelope({{"error", "other"}, {"message", error.what()}});
  }
}

// A page the worker child marks its plugin calls in and the parent reads after a crash or hang;
// nullptr without one (no memory for a page): crashes are then reported without the call.
std::shared_ptr<host::PluginCallRecord> shared_call_record() {
  void* page = ::mmap(nullptr, sizeof(host::PluginCallRecord), PROT_READ | PROT_WRITE,
                      MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (page == MAP_FAILED) return nullptr;
  return {static_cast<host::PluginCallRecord*>(page),
          [](host::PluginCallRecord* record) { ::munmap(record, sizeof(host::PluginCallRecord)); }};
}

// "crashed: signal 11 (SIGSEGV) in xpbd.step (.../xpbd.so) at step 12": the call goes after the
// signal or exit status, before any sanitizer report (": ==12==ERROR: ...").
std::string with_call(const std::string& problem, const host::PluginCallRecord* record) {
  if (record == nullptr) return problem;
  const std::string where = host::describe_active_call(*record);
  if (where.empty()) return problem;
  constexpr std::string_view crashed = "crashed: ";
  const size_t report =
      problem.starts_with(crashed) ? problem.find(": ", crashed.size()) : std::string::npos;
  if (report == std::string::npos) return problem + where;
  return problem.substr(0, report) + where + problem.substr(report);
}

process::IsolationOptions worker_options(bool forward_interrupt) {
  process::IsolationOptions options;
  if (forward_interrupt) options.on_child = forward_interrupts_to;
  return options;
}

}  // namespace

JsonWorker::JsonWorker(const Serve& serve, bool forward_interrupt)
    : call_(shared_call_record()),
      worker_(
          [serve, call = call_.get()](const std::string& request) {
            host::mark_plugin_calls_in(call);
            return answer_of([&] { return serve(nlohmann::json::parse(request)); });
          },
          worker_options(forward_interrupt)) {}

nlohmann::json JsonWorker::ask(const nlohmann::json& request, double timeout_s) {
  // A child that crashed in a plugin call left its mark; this request starts unmarked.
  if (call_) call_->active = 0;
  const process::ChildOutcome outcome = worker_.ask(envelope(request), timeout_s);
  if (!outcome.answered()) throw std::runtime_error(with_call(outcome.problem, call_.get()));
  const nlohmann::json answer = nlohmann::json::parse(outcome.answer, nullptr, false);
  if (answer.is_discarded() || !answer.is_object())
    throw std::runtime_error("child process answered something that is not JSON");
  if (answer.contains("value")) return answer["value"];
  const std::string kind = answer.value("error", "other");
  const std::string message = answer.value("message", "failed");
  if (kind == "input") throw host::InputError(message);
  if (kind == "load") throw host::PluginLoadError(message);
  if (kind == "plugin")
    throw host::PluginError(static_cast<clothlab_status>(answer.value("status", 0)), message);
  throw std::runtime_error(message);
}

nlohmann::json run_isolated(const std::function<nlohmann::json()>& work, double timeout_s,
                            bool forward_interrupt) {
  JsonWorker worker([&](const nlohmann::json&) { return work(); }, forward_interrupt);
  return worker.ask(nullptr, timeout_s);
}

}  // namespace clothlab::cli
