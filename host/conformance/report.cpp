#include "report.hpp"

#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace clothlab::conformance {
namespace {

std::string xml_escaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        // XML 1.0 forbids most control characters; a plugin message may contain any byte.
        if (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t')
          out += '?';
        else
          out += c;
    }
  }
  return out;
}

std::string seconds_text(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", seconds);
  return text;
}

}  // namespace

size_t RunReport::passed() const {
  size_t count = 0;
  for (const CheckResult& result : results) count += result.passed ? 1 : 0;
  return count;
}

size_t RunReport::failed() const { return results.size() - passed(); }

std::string result_line(const CheckResult& result) {
  std::string line = (result.passed ? "PASS " : "FAIL ") + result.full_name();
  if (!result.reason.empty()) line += " \u2014 " + result.reason;
  return line;
}

std::string summary_line(const RunReport& report) {
  return std::to_string(report.passed()) + " passed, " + std::to_string(report.failed()) +
         " failed";
}

std::string to_json(const RunReport& report) {
  nlohmann::json checks = nlohmann::json::array();
  for (const CheckResult& result : report.results)
    checks.push_back({{"plugin", result.plugin},
                      {"component", result.component},
                      {"check", result.check},
                      {"passed", result.passed},
                      {"reason", result.reason},
                      {"seconds", result.seconds}});
  const nlohmann::json document = {{"seed", report.seed},
                                   {"timeout_s", report.timeout_s},
                                   {"passed", report.passed()},
                                   {"failed", report.failed()},
                                   {"checks", checks}};
  return document.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

std::string to_junit(const RunReport& report) {
  std::map<std::string, std::vector<const CheckResult*>> by_plugin;
  for (const CheckResult& result : report.results) by_plugin[result.plugin].push_back(&result);
  std::string xml = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  xml += "<testsuites name=\"clothlab-conformance\" tests=\"" +
         std::to_string(report.results.size()) + "\" failures=\"" +
         std::to_string(report.failed()) + "\">\n";
  for (const auto& [plugin, results] : by_plugin) {
    size_t failures = 0;
    double seconds = 0;
    for (const CheckResult* result : results) {
      failures += result->passed ? 0 : 1;
      seconds += result->seconds;
    }
    xml += "  <testsuite name=\"" + xml_escaped(plugin) + "\" tests=\"" +
           std::to_string(results.size()) + "\" failures=\"" + std::to_string(failures) +
           "\" time=\"" + seconds_text(seconds) + "\">\n";
    xml += "    <properties><property name=\"seed\" value=\"" + std::to_string(report.seed) +
           "\"/></properties>\n";
    for (const CheckResult* result : results) {
      xml += "    <testcase classname=\"" + xml_escaped(plugin + "." + result->component) +
             "\" name=\"" + xml_escaped(result->check) + "\" time=\"" +
             seconds_text(result->seconds) + "\"";
      if (result->passed) {
        xml += "/>\n";
      } else {
        xml += ">\n      <failure message=\"" + xml_escaped(result->reason) + "\"/>\n";
        xml += "    </testcase>\n";
      }
    }
    xml += "  </testsuite>\n";
  }
  return xml + "</testsuites>\n";
}

}  // namespace clothlab::conformance
