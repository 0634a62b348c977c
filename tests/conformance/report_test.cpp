#include "report.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

using namespace clothlab::conformance;

namespace {
RunReport two_results() {
  RunReport report;
  report.seed = 7;
  report.timeout_s = 10;
  report.results = {
      {"rk4", "rk4", "numerics.order-spring", true, "measured order 4.00", 0.5},
      {"bad", "library", "loading.exports", false, "exports 2 symbols <a & b>", 0.25}};
  return report;
}
}  // namespace

TEST(Report, LinesNameThePluginComponentCheckAndReason) {
  const RunReport report = two_results();
  EXPECT_EQ(result_line(report.results[0]),
            "PASS rk4:rk4 numerics.order-spring \u2014 measured order 4.00");
  EXPECT_EQ(result_line(report.results[1]),
            "FAIL bad:library loading.exports \u2014 exports 2 symbols <a & b>");
  EXPECT_EQ(summary_line(report), "1 passed, 1 failed");
}

TEST(Report, JsonCarriesEveryResultAndTheSeed) {
  const nlohmann::json document = nlohmann::json::parse(to_json(two_results()));
  EXPECT_EQ(document["seed"], 7);
  EXPECT_EQ(document["passed"], 1);
  EXPECT_EQ(document["failed"], 1);
  ASSERT_EQ(document["checks"].size(), 2u);
  EXPECT_EQ(document["checks"][1]["check"], "loading.exports");
  EXPECT_EQ(document["checks"][1]["passed"], false);
}

TEST(Report, JunitEscapesReasonsAndCountsFailuresPerPlugin) {
  const std::string xml = to_junit(two_results());
  EXPECT_NE(xml.find("<testsuites name=\"clothlab-conformance\" tests=\"2\" failures=\"1\">"),
            std::string::npos);
  EXPECT_NE(xml.find("<testsuite name=\"bad\" tests=\"1\" failures=\"1\""), std::string::npos);
  EXPECT_NE(xml.find("<failure message=\"exports 2 symbols &lt;a &amp; b&gt;\"/>"),
            std::string::npos);
  EXPECT_NE(
      xml.find("<testcase classname=\"rk4.rk4\" name=\"numerics.order-spring\" time=\"0.500\"/>"),
      std::string::npos);
}
