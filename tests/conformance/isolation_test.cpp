#include "isolation.hpp"

#include <gtest/gtest.h>

#include <csignal>
#include <cstdlib>
#include <stdexcept>
#include <thread>

using namespace clothlab::conformance;

TEST(RunIsolated, ReturnsTheChildsVerdict) {
  const Verdict pass = run_isolated([] { return Verdict{true, "fine"}; }, 5);
  EXPECT_TRUE(pass.passed);
  EXPECT_EQ(pass.reason, "fine");
  const Verdict fail = run_isolated([]() -> Verdict { throw CheckFailure("broken"); }, 5);
  EXPECT_FALSE(fail.passed);
  EXPECT_EQ(fail.reason, "broken");
}

TEST(RunIsolated, ReportsASignalAsACrash) {
  const Verdict crash = run_isolated(
      []() -> Verdict {
        std::raise(SIGSEGV);
        return {true, ""};
      },
      5);
  EXPECT_FALSE(crash.passed);
  EXPECT_EQ(crash.reason, "crashed: signal 11 (SIGSEGV)");
  const Verdict abort = run_isolated([]() -> Verdict { std::abort(); }, 5);
  EXPECT_EQ(abort.reason, "crashed: signal 6 (SIGABRT)");
}

TEST(RunIsolated, ReportsAnExitWithoutVerdict) {
  const Verdict quit = run_isolated([]() -> Verdict { std::_Exit(3); }, 5);
  EXPECT_FALSE(quit.passed);
  EXPECT_EQ(quit.reason, "crashed: exited with status 3 before reporting");
}

TEST(RunIsolated, KillsAChildThatOutlivesTheTimeout) {
  const Verdict hang = run_isolated(
      []() -> Verdict {
        for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));
      },
      0.2);
  EXPECT_FALSE(hang.passed);
  EXPECT_EQ(hang.reason, "timed out after 0.2 s");
}

TEST(RunGuarded, TurnsEscapingExceptionsIntoFailures) {
  const Verdict escaped = run_guarded([]() -> Verdict { throw std::runtime_error("boom"); });
  EXPECT_FALSE(escaped.passed);
  EXPECT_EQ(escaped.reason, "exception escaped: boom");
  EXPECT_EQ(run_guarded([]() -> Verdict { throw 42; }).reason, "exception of unknown type escaped");
}
