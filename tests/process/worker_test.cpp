// The reused child of host/process (Worker): one child serves request after request, and a
// crash, an exit, a hang or an outside kill ends only that child; the next request gets a new
// one.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <clothlab/process/isolation.hpp>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace {

using clothlab::process::ChildOutcome;
using clothlab::process::IsolationOptions;
using clothlab::process::Worker;

// "pid" answers the child's pid; "crash", "exit", "hang" and "throw" do what they say; any
// other request is echoed.
std::string serve(const std::string& request) {
  if (request == "pid") return std::to_string(::getpid());
  if (request == "crash") std::abort();
  if (request == "exit") std::_Exit(3);
  if (request == "hang")
    for (volatile bool forever = true; forever;) {
    }
  if (request == "throw") throw std::runtime_error("refused");
  return request;
}

Worker make_worker() {
  IsolationOptions options;
  options.timeout_s = 5;
  return Worker(serve, options);
}

std::string answered_pid(Worker& worker) {
  const ChildOutcome outcome = worker.ask("pid");
  EXPECT_EQ(outcome.end, ChildOutcome::End::Answered) << outcome.problem;
  EXPECT_EQ(outcome.answer, std::to_string(worker.pid()));
  return outcome.answer;
}

TEST(ProcessWorker, OneChildServesManyRequests) {
  Worker worker = make_worker();
  EXPECT_EQ(worker.pid(), 0);
  const std::string first = answered_pid(worker);
  EXPECT_NE(first, std::to_string(::getpid()));
  for (int request = 0; request < 20; ++request) EXPECT_EQ(answered_pid(worker), first);
}

// Empty, a byte that is not UTF-8, more than a pipe holds, several MiB.
TEST(ProcessWorker, AnswersOfAnySizeComeBackWhole) {
  Worker worker = make_worker();
  std::string large(size_t{3} << 20, 'a');
  for (size_t i = 0; i < large.size(); ++i) large[i] = static_cast<char>('a' + i % 26);
  for (const std::string& request :
       {std::string(), std::string(1, '\xff'), large.substr(0, 70000), large}) {
    const ChildOutcome outcome = worker.ask(request);
    ASSERT_EQ(outcome.end, ChildOutcome::End::Answered) << outcome.problem;
    EXPECT_EQ(outcome.answer, request) << request.size();
  }
}

TEST(ProcessWorker, AnExceptionIsAnAnswerAndKeepsTheChild) {
  Worker worker = make_worker();
  const std::string child = answered_pid(worker);
  const ChildOutcome refused = worker.ask("throw");
  EXPECT_EQ(refused.end, ChildOutcome::End::Threw);
  EXPECT_EQ(refused.problem, "refused");
  EXPECT_EQ(answered_pid(worker), child);
}

TEST(ProcessWorker, ACrashOrAnExitEndsOnlyThatRequest) {
  Worker worker = make_worker();
  const std::string first = answered_pid(worker);
  const ChildOutcome crash = worker.ask("crash");
  EXPECT_EQ(crash.end, ChildOutcome::End::Crashed);
  EXPECT_EQ(crash.problem, "crashed: signal 6 (SIGABRT)");
  EXPECT_EQ(worker.pid(), 0);
  const std::string second = answered_pid(worker);
  EXPECT_NE(second, first);
  const ChildOutcome exit = worker.ask("exit");
  EXPECT_EQ(exit.problem, "crashed: exited with status 3 before reporting");
  EXPECT_NE(answered_pid(worker), second);
}

TEST(ProcessWorker, AHangIsKilledAtTheDeadlineAndTheNextRequestIsServed) {
  Worker worker = make_worker();
  const std::string first = answered_pid(worker);
  const ChildOutcome hang = worker.ask("hang", 0.3);
  EXPECT_EQ(hang.end, ChildOutcome::End::TimedOut);
  EXPECT_EQ(hang.problem, "timed out after 0.3 s");
  EXPECT_NE(::kill(static_cast<pid_t>(std::stoi(first)), 0), 0) << "the hung child still runs";
  EXPECT_NE(answered_pid(worker), first);
}

// A child killed from outside between requests (the OOM killer) is replaced, and the next
// request is not blamed for it.
TEST(ProcessWorker, AChildKilledBetweenRequestsIsReplaced) {
  Worker worker = make_worker();
  const std::string first = answered_pid(worker);
  ASSERT_EQ(::kill(worker.pid(), SIGKILL), 0);
  ::usleep(100000);
  const ChildOutcome echo = worker.ask("still here");
  ASSERT_EQ(echo.end, ChildOutcome::End::Answered) << echo.problem;
  EXPECT_EQ(echo.answer, "still here");
  EXPECT_NE(answered_pid(worker), first);
}

}  // namespace
