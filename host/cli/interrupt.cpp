#include "interrupt.hpp"

#include <signal.h>

#include <csignal>

namespace clothlab::cli {

namespace {

std::atomic<bool> requested{false};
std::atomic<pid_t> forward_to{0};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<pid_t>::is_always_lock_free,
              "used from a signal handler");

extern "C" void request_stop(int signal_number) {
  requested.store(true, std::memory_order_relaxed);
  if (const pid_t child = forward_to.load(std::memory_order_relaxed); child > 0)
    ::kill(child, signal_number);
}

}  // namespace

void install_interrupt_handler() {
  struct sigaction action {};
  action.sa_handler = request_stop;
  action.sa_flags = SA_RESETHAND;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

const std::atomic<bool>& interrupt_requested() { return requested; }

void forward_interrupts_to(pid_t child) { forward_to.store(child, std::memory_order_relaxed); }

}  // namespace clothlab::cli
