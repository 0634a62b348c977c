// The program's use of the child-process runner (host/cli/isolation.cpp).
#include <gtest/gtest.h>
#include <unistd.h>

#include <clothlab/host/errors.hpp>
#include <fstream>
#include <string>

#include "isolation.hpp"

namespace {

using clothlab::cli::run_isolated;

// Item 1 of issue 12: an answer holding a byte that is not UTF-8 made the child throw outside
// its try, return into the caller and fork again (12 cases -> 4096 processes). Each process
// that returns from run_isolated appends its pid here: only the parent may.
TEST(JsonIsolation, AnAnswerThatIsNotUtf8DoesNotEscapeTheChild) {
  const std::string marker = ::testing::TempDir() + "/returned-" + std::to_string(::getpid());
  std::remove(marker.c_str());
  std::string reason;
  std::string value;
  try {
    value =
        run_isolated([] { return nlohmann::json(std::string("mass \xff")); }, 5).get<std::string>();
  } catch (const std::exception& error) {
    reason = error.what();
  }
  std::ofstream(marker, std::ios::app) << ::getpid() << "\n";
  std::ifstream lines(marker);
  int count = 0;
  for (std::string line; std::getline(lines, line);) ++count;
  EXPECT_EQ(count, 1);
  EXPECT_EQ(value, "mass \xef\xbf\xbd") << reason;
}

TEST(JsonIsolation, TheChildsErrorKindSurvives) {
  EXPECT_THROW(run_isolated([]() -> nlohmann::json { throw clothlab::host::InputError("x"); }, 5),
               clothlab::host::InputError);
  try {
    run_isolated([]() -> nlohmann::json { throw clothlab::host::InputError("bad \xff"); }, 5);
    FAIL() << "no exception";
  } catch (const clothlab::host::InputError& error) {
    EXPECT_EQ(std::string(error.what()), "bad \xef\xbf\xbd");
  }
}

}  // namespace
