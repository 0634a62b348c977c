// run_program: another program's output, exit status, a missing program and the deadline.
#include <gtest/gtest.h>

#include <chrono>
#include <clothlab/process/program.hpp>
#include <stdexcept>
#include <string>

namespace {

using clothlab::process::find_on_path;
using clothlab::process::ProgramOutput;
using clothlab::process::run_program;

std::string shell() {
  const auto found = find_on_path("sh");
  if (!found) throw std::runtime_error("no sh on PATH");
  return found->string();
}

TEST(RunProgram, CollectsStdoutStderrAndTheExitStatus) {
  const ProgramOutput output =
      run_program({shell(), "-c", "printf 'out line'; printf 'err line' >&2; exit 3"});
  EXPECT_EQ(output.out, "out line");
  EXPECT_EQ(output.err, "err line");
  EXPECT_EQ(output.exit_status, 3);
  EXPECT_FALSE(output.timed_out);
}

TEST(RunProgram, DrainsBothPipesWhenEachHoldsMoreThanAPipeBuffer) {
  // 1 MiB to each: a runner that read one pipe to its end first would deadlock here.
  const ProgramOutput output =
      run_program({shell(), "-c",
                   "head -c 1048576 /dev/zero | tr '\\0' o & head -c 1048576 /dev/zero | "
                   "tr '\\0' e >&2; wait"});
  EXPECT_EQ(output.exit_status, 0);
  EXPECT_EQ(output.out, std::string(1 << 20, 'o'));
  EXPECT_EQ(output.err, std::string(1 << 20, 'e'));
}

TEST(RunProgram, AProgramThatCannotStartThrowsNamingIt) {
  try {
    run_program({"/nonexistent/sbatch", "--version"});
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& error) {
    EXPECT_EQ(std::string(error.what()),
              "/nonexistent/sbatch: cannot run: No such file or directory");
  }
}

TEST(RunProgram, AProgramPastTheDeadlineIsKilled) {
  const auto start = std::chrono::steady_clock::now();
  const ProgramOutput output = run_program({shell(), "-c", "echo started; sleep 30"}, 0.5);
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(output.timed_out);
  EXPECT_EQ(output.exit_status, -1);
  EXPECT_EQ(output.out, "started\n");
  EXPECT_LT(elapsed, 10.0);
}

TEST(RunProgram, FindsAProgramOnPathAndNotAMissingOne) {
  EXPECT_TRUE(find_on_path("sh").has_value());
  EXPECT_FALSE(find_on_path("clothlab-no-such-program-anywhere").has_value());
}

}  // namespace
