#include "clothlab/sweep/results_store.hpp"

#include <clothlab/host/param_text.hpp>
#include <clothlab/io/atomic_file.hpp>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "clothlab/sweep/case_result.hpp"
#include "clothlab/sweep/sweep_error.hpp"

namespace clothlab::sweep {
namespace {

std::string csv_field(const nlohmann::ordered_json& value) {
  std::string text;
  if (value.is_null()) return text;
  if (value.is_string()) {
    text = value.get<std::string>();
  } else if (value.is_number_float()) {
    text = host::format_number(value.get<double>());
  } else {
    text = value.dump();
  }
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

}  // namespace

const char* to_string(CaseStatus status) {
  switch (status) {
    case CaseStatus::Stable:
      return "stable";
    case CaseStatus::Unstable:
      return "unstable";
    case CaseStatus::Failed:
      return "failed";
  }
  return "unknown";
}

std::string rows_to_csv(const std::vector<Row>& rows) {
  std::vector<std::string> columns;
  std::unordered_set<std::string> seen;
  for (const Row& row : rows) {
    for (const auto& [name, value] : row.items()) {
      if (seen.insert(name).second) columns.push_back(name);
    }
  }
  std::ostringstream csv;
  for (std::size_t i = 0; i < columns.size(); ++i) csv << (i ? "," : "") << csv_field(columns[i]);
  csv << '\n';
  for (const Row& row : rows) {
    for (std::size_t i = 0; i < columns.size(); ++i) {
      csv << (i ? "," : "");
      if (row.contains(columns[i])) csv << csv_field(row[columns[i]]);
    }
    csv << '\n';
  }
  return csv.str();
}

ResultsStore::ResultsStore(std::filesystem::path base, bool resume)
    : csv_path_(base.string() + ".csv"), json_path_(base.string() + ".json") {
  std::error_code error;
  if (base.has_parent_path()) std::filesystem::create_directories(base.parent_path(), error);
  if (error)
    throw SweepError(base.parent_path().string() + ": cannot create folder: " + error.message());
  if (!resume || !std::filesystem::exists(json_path_)) return;
  std::ifstream stream(json_path_);
  nlohmann::ordered_json document;
  try {
    document = nlohmann::ordered_json::parse(stream);
  } catch (const nlohmann::json::exception& error) {
    throw SweepError(json_path_.string() + ": cannot resume, not a results file: " + error.what());
  }
  if (!document.is_object() || !document.contains("rows") || !document["rows"].is_array()) {
    throw SweepError(json_path_.string() + ": cannot resume: expected {\"rows\": [...]}");
  }
  if (document.contains("sweep")) metadata_ = document["sweep"];
  for (Row& row : document["rows"]) {
    if (!row.is_object() || !row.contains("key") || !row["key"].is_string()) {
      throw SweepError(json_path_.string() + ": cannot resume: a row lacks a string \"key\"");
    }
    keys_.insert(row["key"].get<std::string>());
    rows_.push_back(std::move(row));
  }
  resumed_ = rows_.size();
}

void ResultsStore::set_metadata(const nlohmann::ordered_json& metadata) { metadata_ = metadata; }

bool ResultsStore::contains(const std::string& key) const { return keys_.count(key) > 0; }

void ResultsStore::append(Row row) {
  if (!row.is_object() || !row.contains("key") || !row["key"].is_string()) {
    throw SweepError("results: a row needs a string \"key\"");
  }
  const std::string key = row["key"].get<std::string>();
  if (!keys_.insert(key).second) throw SweepError("results: duplicate case key '" + key + "'");
  rows_.push_back(std::move(row));
  flush();
}

void ResultsStore::flush() const {
  nlohmann::ordered_json document;
  document["sweep"] = metadata_;
  document["rows"] = rows_;
  io::write_file_atomically(
      json_path_, document.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  io::write_file_atomically(csv_path_, rows_to_csv(rows_));
}

}  // namespace clothlab::sweep
