#include "clothlab/sweep/results_store.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <clothlab/host/param_text.hpp>
#include <clothlab/io/atomic_file.hpp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "clothlab/sweep/case_result.hpp"
#include "clothlab/sweep/sweep_error.hpp"
#include "sqlite_database.hpp"

namespace clothlab::sweep {
namespace {

constexpr const char* store_format = "clothlab-results-1";

std::filesystem::path with_suffix(const std::filesystem::path& base, const char* suffix) {
  return base.string() + suffix;
}

nlohmann::ordered_json fingerprint_json(const Fingerprint& fingerprint) {
  nlohmann::ordered_json json = nlohmann::ordered_json::object();
  for (const auto& [name, value] : fingerprint) json[name] = value;
  return json;
}

Fingerprint fingerprint_from(const std::string& text) {
  Fingerprint fingerprint;
  const nlohmann::json json = nlohmann::json::parse(text);
  for (const auto& [name, value] : json.items()) fingerprint[name] = value.get<std::string>();
  return fingerprint;
}

// The meta table of an open store as name -> value; throws if it is not a results store.
std::map<std::string, std::string> read_meta(SqliteDatabase& database) {
  std::map<std::string, std::string> meta;
  try {
    SqliteStatement select = database.prepare("SELECT name, value FROM meta");
    while (select.step()) meta[select.text(0)] = select.text(1);
  } catch (const SweepError& error) {
    throw SweepError(database.path().string() + ": not a clothlab results store (" + error.what() +
                     ")");
  }
  if (meta["format"] != store_format)
    throw SweepError(database.path().string() + ": not a clothlab results store (format '" +
                     meta["format"] + "', expected '" + store_format + "')");
  return meta;
}

void write_meta(SqliteDatabase& database, const std::string& name, const std::string& value) {
  database.prepare("INSERT OR REPLACE INTO meta(name, value) VALUES(?, ?)")
      .bind(1, name)
      .bind(2, value)
      .run();
}

// Holds an exclusive flock on path, or throws naming the process that holds it.
int take_writer_lock(const std::filesystem::path& lock_path,
                     const std::filesystem::path& database_path) {
  const int fd = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0)
    throw SweepError(lock_path.string() + ": cannot open lock file: " + std::strerror(errno));
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    char holder[32] = {};
    const ssize_t n = ::pread(fd, holder, sizeof holder - 1, 0);
    ::close(fd);
    std::string pid = n > 0 ? std::string(holder, static_cast<std::size_t>(n)) : "?";
    pid.erase(std::remove(pid.begin(), pid.end(), '\n'), pid.end());
    throw SweepError(database_path.string() + ": another clothlab process (pid " + pid +
                     ") is writing these results; wait for it to finish or write elsewhere "
                     "(--out)");
  }
  const std::string pid = std::to_string(::getpid()) + "\n";
  // The pid only feeds the message above: the lock is held whether or not it is written.
  const bool pid_written = ::ftruncate(fd, 0) == 0 && ::pwrite(fd, pid.data(), pid.size(), 0) > 0;
  static_cast<void>(pid_written);
  return fd;
}

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

ResultsStore::ResultsStore(std::filesystem::path base, bool resume, const Fingerprint& fingerprint)
    : database_path_(with_suffix(base, ".sqlite")),
      lock_path_(with_suffix(base, ".lock")),
      csv_path_(with_suffix(base, ".csv")),
      json_path_(with_suffix(base, ".json")) {
  std::error_code error;
  if (base.has_parent_path()) std::filesystem::create_directories(base.parent_path(), error);
  if (error)
    throw SweepError(base.parent_path().string() + ": cannot create folder: " + error.message());
  lock_fd_ = take_writer_lock(lock_path_, database_path_);
  try {
    const bool existed = std::filesystem::exists(database_path_);
    if (!resume && existed) {
      for (const char* suffix : {"", "-wal", "-shm"})
        std::filesystem::remove(database_path_.string() + suffix);
    }
    database_ = std::make_unique<SqliteDatabase>(database_path_, SqliteDatabase::Access::ReadWrite);
    if (resume && existed) {
      const auto meta = read_meta(*database_);
      const Fingerprint stored = fingerprint_from(meta.at("fingerprint"));
      const std::string changes = describe_changes(stored, fingerprint);
      if (!changes.empty())
        throw SweepError(database_path_.string() +
                         ": cannot resume: the sweep changed since these results were written: " +
                         changes + "; run without --resume to replace them, or use another --out");
      metadata_ = nlohmann::ordered_json::parse(meta.at("metadata"));
      SqliteStatement select = database_->prepare("SELECT key FROM rows");
      while (select.step()) keys_.insert(select.text(0));
      resumed_ = keys_.size();
      write_meta(*database_, "complete", "0");
    } else {
      // WAL: readers (merge, progress) never block the writer; NORMAL: a commit is one write
      // to the log, not an fsync, and a crash still leaves the last committed row whole.
      database_->execute("PRAGMA journal_mode=WAL; PRAGMA synchronous=NORMAL");
      database_->execute(
          "BEGIN;"
          "CREATE TABLE meta(name TEXT PRIMARY KEY, value TEXT NOT NULL);"
          "CREATE TABLE rows(seq INTEGER PRIMARY KEY, case_index INTEGER NOT NULL,"
          " key TEXT NOT NULL UNIQUE, row TEXT NOT NULL)");
      write_meta(*database_, "format", store_format);
      write_meta(*database_, "fingerprint", fingerprint_json(fingerprint).dump());
      write_meta(*database_, "metadata",
                 metadata_.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
      write_meta(*database_, "complete", "0");
      database_->execute("COMMIT");
    }
    database_->execute("PRAGMA synchronous=NORMAL");
    insert_ = std::make_unique<SqliteStatement>(
        database_->prepare("INSERT INTO rows(case_index, key, row) VALUES(?, ?, ?)"));
  } catch (...) {
    insert_.reset();
    database_.reset();
    ::close(lock_fd_);
    throw;
  }
}

ResultsStore::~ResultsStore() {
  insert_.reset();
  database_.reset();
  ::close(lock_fd_);
}

void ResultsStore::set_metadata(const nlohmann::ordered_json& metadata) {
  metadata_ = metadata;
  write_meta(*database_, "metadata",
             metadata_.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

bool ResultsStore::contains(const std::string& key) const { return keys_.count(key) > 0; }

void ResultsStore::append(Row row, std::size_t case_index) {
  if (!row.is_object() || !row.contains("key") || !row["key"].is_string()) {
    throw SweepError("results: a row needs a string \"key\"");
  }
  const std::string key = row["key"].get<std::string>();
  if (keys_.count(key)) throw SweepError("results: duplicate case key '" + key + "'");
  insert_->bind(1, static_cast<int64_t>(case_index))
      .bind(2, key)
      .bind(3, row.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
  insert_->run();
  keys_.insert(key);
}

std::vector<Row> ResultsStore::rows() const {
  return select_rows("SELECT row FROM rows ORDER BY seq");
}

std::optional<Row> ResultsStore::find(const std::string& key) const {
  if (!keys_.count(key)) return std::nullopt;
  SqliteStatement select = database_->prepare("SELECT row FROM rows WHERE key = ?");
  select.bind(1, key);
  if (!select.step()) return std::nullopt;
  return Row::parse(select.text(0));
}

std::vector<Row> ResultsStore::select_rows(const std::string& sql) const {
  std::vector<Row> rows;
  SqliteStatement select = database_->prepare(sql);
  while (select.step()) rows.push_back(Row::parse(select.text(0)));
  return rows;
}

void ResultsStore::mark_complete() { write_meta(*database_, "complete", "1"); }

void ResultsStore::write_exports() const {
  const std::vector<Row> ordered = select_rows("SELECT row FROM rows ORDER BY case_index, seq");
  io::write_file_atomically(json_path_, rows_to_json(metadata_, ordered));
  io::write_file_atomically(csv_path_, rows_to_csv(ordered));
}

StoredResults read_results(const std::filesystem::path& database_path) {
  if (!std::filesystem::exists(database_path))
    throw SweepError(database_path.string() + ": no such results store");
  SqliteDatabase database(database_path, SqliteDatabase::Access::ReadOnly);
  const auto meta = read_meta(database);
  StoredResults results;
  results.fingerprint = fingerprint_from(meta.at("fingerprint"));
  results.metadata = nlohmann::ordered_json::parse(meta.at("metadata"));
  results.complete = meta.count("complete") && meta.at("complete") == "1";
  SqliteStatement select =
      database.prepare("SELECT case_index, row FROM rows ORDER BY case_index, seq");
  while (select.step())
    results.rows.emplace_back(static_cast<std::size_t>(select.integer(0)),
                              Row::parse(select.text(1)));
  return results;
}

std::size_t stored_case_count(const std::filesystem::path& database_path) {
  if (!std::filesystem::exists(database_path)) return 0;
  SqliteDatabase database(database_path, SqliteDatabase::Access::ReadOnly);
  // A shard task that has just started may have created the file but not yet its tables.
  SqliteStatement tables =
      database.prepare("SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = 'rows'");
  if (!tables.step() || tables.integer(0) == 0) return 0;
  SqliteStatement count = database.prepare("SELECT count(DISTINCT case_index) FROM rows");
  return count.step() ? static_cast<std::size_t>(count.integer(0)) : 0;
}

std::string rows_to_json(const nlohmann::ordered_json& metadata, const std::vector<Row>& rows) {
  nlohmann::ordered_json document;
  document["sweep"] = metadata;
  document["rows"] = rows;
  return document.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace clothlab::sweep
