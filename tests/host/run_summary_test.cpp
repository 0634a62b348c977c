// The one run summary: every member is in its struct's field table (a figure left out of the
// table is caught, shown on a mutant), and every field survives the JSON writer and reader,
// also through the case worker's child process.
#include <gtest/gtest.h>

#include <clothlab/host/errors.hpp>
#include <clothlab/host/run_summary.hpp>
#include <cmath>
#include <string>
#include <type_traits>
#include <typeinfo>
#include <vector>

#include "isolation.hpp"

namespace clothlab::host {
namespace {

// Converts to any member type: T{any_member{} x N} compiles for N up to T's member count.
struct any_member {
  template <class T>
  operator T() const;
};

template <class T, class... Members>
constexpr std::size_t member_count() {
  if constexpr (requires { T{Members{}..., any_member{}}; })
    return member_count<T, Members..., any_member>();
  else
    return sizeof...(Members);
}

// Counts the fields a table names, and checks each nested struct's table the same way.
struct TableCheck {
  std::size_t fields = 0;
  std::vector<std::string> incomplete;  // structs with a member their table leaves out

  template <class T>
  void operator()(const char*, T& value) {
    ++fields;
    nested(value);
  }
  template <class T>
  void absent_when_empty(const char* name, std::optional<T>& value) {
    (*this)(name, value);
  }

  template <class T>
  void nested(T& value) {
    if constexpr (is_optional<T>::value) {
      typename T::value_type inner{};
      nested(inner);
    } else if constexpr (requires { T::fields(value, *this); }) {
      check(value);
    }
  }

  template <class T>
  void check(T& value) {
    TableCheck table;
    T::fields(value, table);
    if (table.fields != member_count<T>()) incomplete.push_back(typeid(T).name());
    incomplete.insert(incomplete.end(), table.incomplete.begin(), table.incomplete.end());
  }
};

template <class T>
std::vector<std::string> members_left_out_of_tables() {
  T value{};
  TableCheck table;
  table.check(value);
  return table.incomplete;
}

// A summary whose fields all differ from their defaults and from each other, set through the
// table (which the check above proves complete).
struct Filler {
  int next = 1;

  template <class T>
  void operator()(const char*, T& value) {
    fill(value);
  }
  template <class T>
  void absent_when_empty(const char*, std::optional<T>& value) {
    fill(value);
  }

  template <class T>
  void fill(T& value) {
    const int n = next++;
    if constexpr (is_optional<T>::value) {
      fill(value.emplace());
    } else if constexpr (std::is_same_v<T, nlohmann::json>) {
      value = {{"parameter", n}};
    } else if constexpr (std::is_same_v<T, std::string>) {
      value = "text " + std::to_string(n);
    } else if constexpr (std::is_same_v<T, bool>) {
      value = !value;
    } else if constexpr (std::is_floating_point_v<T>) {
      value = n + 0.25;
    } else if constexpr (std::is_integral_v<T>) {
      value = static_cast<T>(n);
    } else {
      T::fields(value, *this);
    }
  }
};

RunSummary filled_summary() {
  RunSummary summary;
  Filler filler;
  RunSummary::fields(summary, filler);
  return summary;
}

// A figure added as a member and forgotten in the table.
struct ForgottenFigure {
  double listed = 0;
  double forgotten = 0;
  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("listed", self.listed);
  }
};

TEST(RunSummary, EveryMemberIsInItsStructsFieldTable) {
  EXPECT_EQ(members_left_out_of_tables<RunSummary>(), std::vector<std::string>());
  // The mutant: the check finds the member its table leaves out.
  EXPECT_EQ(members_left_out_of_tables<ForgottenFigure>().size(), 1u);
}

TEST(RunSummary, EveryFieldSurvivesTheJsonWriterAndReader) {
  const RunSummary summary = filled_summary();
  ASSERT_NE(summary, RunSummary());
  const std::string text = to_json(summary).dump();
  EXPECT_EQ(run_summary_from_json(nlohmann::json::parse(text), "test"), summary);
}

TEST(RunSummary, EveryFieldSurvivesTheCaseWorkersAnswer) {
  const RunSummary summary = filled_summary();
  cli::JsonWorker worker([&](const nlohmann::json&) { return to_json(summary); });
  EXPECT_EQ(run_summary_from_json(worker.ask(nlohmann::json::object(), 30), "case worker"),
            summary);
}

TEST(RunSummary, EmptyOptionalsAreNullOrAbsentAndReadBack) {
  RunSummary summary;
  summary.max_stretch.over_run = NAN;  // a diverged run's
  // As written to a file or a pipe: a number that is not finite dumps as null.
  const nlohmann::json json = nlohmann::json::parse(to_json(summary).dump());
  EXPECT_TRUE(json["contacts"].is_null());
  EXPECT_TRUE(json["material"].is_null());
  EXPECT_TRUE(json["max_stretch"]["over_run"].is_null());
  EXPECT_FALSE(json["max_stretch"].contains("over_run_at"));
  const RunSummary read = run_summary_from_json(json, "test");
  EXPECT_TRUE(std::isnan(read.max_stretch.over_run));
  EXPECT_FALSE(read.contacts);
  EXPECT_FALSE(read.max_stretch.over_run_at);
}

std::string read_error(const nlohmann::json& json) {
  try {
    run_summary_from_json(json, "run.json");
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST(RunSummary, BadFieldsAreOneLineErrorsNamingTheFieldAndSource) {
  nlohmann::json json = to_json(filled_summary());
  json["contacts"].erase("work");
  EXPECT_EQ(read_error(json), "run.json: run summary field 'contacts.work': missing");
  json = to_json(filled_summary());
  json["p99_stretch"]["median"] = 1.0;
  EXPECT_EQ(read_error(json), "run.json: run summary field 'p99_stretch.median': unknown field");
  json = to_json(filled_summary());
  json["steps"] = -3;
  EXPECT_EQ(read_error(json),
            "run.json: run summary field 'steps': expected a whole number >= 0, got -3");
  json["steps"] = "many\nsteps";
  EXPECT_EQ(read_error(json),
            "run.json: run summary field 'steps': expected a whole number >= 0, got "
            "\"many\\nsteps\"");
  EXPECT_EQ(read_error(nlohmann::json::array()),
            "run.json: run summary: expected an object, got []");
}

}  // namespace
}  // namespace clothlab::host
