#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <clothlab/process/isolation.hpp>
#include <cstdio>
#include <stdexcept>
#include <thread>

#include "../support/sanitizer.hpp"

namespace {

using clothlab::process::ChildOutcome;
using clothlab::process::IsolationOptions;
using clothlab::process::run_isolated;

IsolationOptions with_timeout(double seconds) {
  IsolationOptions options;
  options.timeout_s = seconds;
  return options;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

TEST(ProcessIsolation, ReturnsTheChildsAnswer) {
  const ChildOutcome outcome =
      run_isolated([] { return std::string("hello\xff"); }, with_timeout(5));
  ASSERT_EQ(outcome.end, ChildOutcome::End::Answered) << outcome.problem;
  EXPECT_EQ(outcome.answer, "hello\xff");
}

TEST(ProcessIsolation, ReportsAnExceptionWithItsText) {
  const ChildOutcome outcome = run_isolated(
      []() -> std::string { throw std::runtime_error("bad \xff byte"); }, with_timeout(5));
  EXPECT_EQ(outcome.end, ChildOutcome::End::Threw);
  EXPECT_EQ(outcome.problem, "bad \xff byte");
  const ChildOutcome unknown = run_isolated([]() -> std::string { throw 42; }, with_timeout(5));
  EXPECT_EQ(unknown.problem, "exception of unknown type");
}

TEST(ProcessIsolation, ReportsASignalAsACrash) {
  if (clothlab::testing::address_sanitizer) GTEST_SKIP() << "ASan turns SIGSEGV into an exit";
  const ChildOutcome outcome = run_isolated(
      []() -> std::string {
        ::raise(SIGSEGV);
        return "";
      },
      with_timeout(5));
  EXPECT_EQ(outcome.end, ChildOutcome::End::Crashed);
  EXPECT_EQ(outcome.problem, "crashed: signal 11 (SIGSEGV)");
}

TEST(ProcessIsolation, ReportsAnExitWithoutAnswer) {
  const ChildOutcome outcome =
      run_isolated([]() -> std::string { std::_Exit(3); }, with_timeout(5));
  EXPECT_EQ(outcome.end, ChildOutcome::End::Crashed);
  EXPECT_EQ(outcome.problem, "crashed: exited with status 3 before reporting");
}

// Item 2 of issue 12: a busy loop or a stopped child hung the sweep forever.
TEST(ProcessIsolation, KillsABusyOrStoppedChildAtTheDeadline) {
  const auto start = std::chrono::steady_clock::now();
  const ChildOutcome busy = run_isolated(
      []() -> std::string {
        for (volatile bool forever = true; forever;) {
        }
        return "";
      },
      with_timeout(0.3));
  EXPECT_EQ(busy.end, ChildOutcome::End::TimedOut);
  EXPECT_EQ(busy.problem, "timed out after 0.3 s");
  const ChildOutcome stopped = run_isolated(
      []() -> std::string {
        ::raise(SIGSTOP);
        return "woke";
      },
      with_timeout(0.3));
  EXPECT_EQ(stopped.end, ChildOutcome::End::TimedOut);
  EXPECT_LT(seconds_since(start), 5.0);
}

// Item 2: a grandchild that keeps the answer pipe open must not stall the parent, and it
// ends with the child (its process group is killed).
TEST(ProcessIsolation, AGrandchildHoldingThePipeDoesNotStallTheParent) {
  int grandchild_pid_pipe[2];
  ASSERT_EQ(::pipe(grandchild_pid_pipe), 0);
  const auto start = std::chrono::steady_clock::now();
  const ChildOutcome outcome = run_isolated(
      [&]() -> std::string {
        const pid_t grandchild = ::fork();
        if (grandchild == 0) {
          ::sleep(60);
          ::_exit(0);
        }
        if (::write(grandchild_pid_pipe[1], &grandchild, sizeof grandchild) < 0) return "";
        return "answered";
      },
      with_timeout(30));
  EXPECT_LT(seconds_since(start), 10.0);
  ASSERT_EQ(outcome.end, ChildOutcome::End::Answered) << outcome.problem;
  EXPECT_EQ(outcome.answer, "answered");
  pid_t grandchild = 0;
  ASSERT_EQ(::read(grandchild_pid_pipe[0], &grandchild, sizeof grandchild),
            static_cast<ssize_t>(sizeof grandchild));
  ::close(grandchild_pid_pipe[0]);
  ::close(grandchild_pid_pipe[1]);
  // Killed, so it is gone (reaped by init) or at most a zombie for a moment.
  bool gone = false;
  for (int attempt = 0; attempt < 200 && !gone; ++attempt) {
    char path[64];
    std::snprintf(path, sizeof path, "/proc/%d/stat", static_cast<int>(grandchild));
    FILE* stat = std::fopen(path, "r");
    if (stat == nullptr) {
      gone = true;
      break;
    }
    char state = '?';
    if (std::fscanf(stat, "%*d %*s %c", &state) != 1) state = '?';
    std::fclose(stat);
    gone = state == 'Z' || state == 'X';
    if (!gone) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_TRUE(gone);
}

// A sanitizer's report reaches the reason: its first line and its SUMMARY line are appended.
TEST(ProcessIsolation, ACapturedSanitizerSummaryReachesTheProblem) {
  IsolationOptions options = with_timeout(5);
  options.capture_stderr = true;
  const ChildOutcome outcome = run_isolated(
      []() -> std::string {
        std::fputs(
            "a line the plugin printed\n"
            "==1==ERROR: AddressSanitizer: heap-buffer-overflow on address 0x6020\n"
            "WRITE of size 4 at 0x6020 thread T0\n"
            "SUMMARY: AddressSanitizer: heap-buffer-overflow plugin.cpp:7 in step\n",
            stderr);
        std::fflush(stderr);
        std::_Exit(1);
      },
      options);
  EXPECT_EQ(outcome.problem,
            "crashed: exited with status 1 before reporting: ==1==ERROR: AddressSanitizer: "
            "heap-buffer-overflow on address 0x6020; SUMMARY: AddressSanitizer: "
            "heap-buffer-overflow plugin.cpp:7 in step");
  EXPECT_NE(outcome.child_stderr.find("==1==ERROR"), std::string::npos);
}

// A sanitizer that stops before any report (an ASan-built plugin in a runner without the
// runtime preloaded) still says why.
TEST(ProcessIsolation, ASanitizerLineWithoutASummaryReachesTheProblem) {
  IsolationOptions options = with_timeout(5);
  options.capture_stderr = true;
  const ChildOutcome outcome = run_isolated(
      []() -> std::string {
        std::fputs("==7==ASan runtime does not come first in initial library list\n", stderr);
        std::fflush(stderr);
        std::_Exit(1);
      },
      options);
  EXPECT_EQ(outcome.problem,
            "crashed: exited with status 1 before reporting: ==7==ASan runtime does not come "
            "first in initial library list");
}

}  // namespace
