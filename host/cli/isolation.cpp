#include "isolation.hpp"

#include <clothlab/host/errors.hpp>
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

process::IsolationOptions worker_options(bool forward_interrupt) {
  process::IsolationOptions options;
  if (forward_interrupt) options.on_child = forward_interrupts_to;
  return options;
}

}  // namespace

JsonWorker::JsonWorker(const Serve& serve, bool forward_interrupt)
    : worker_(
          [serve](const std::string& request) {
            return answer_of([&] { return serve(nlohmann::json::parse(request)); });
          },
          worker_options(forward_interrupt)) {}

nlohmann::json JsonWorker::ask(const nlohmann::json& request, double timeout_s) {
  const process::ChildOutcome outcome = worker_.ask(envelope(request), timeout_s);
  if (!outcome.answered()) throw std::runtime_error(outcome.problem);
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
