// A thin RAII layer over the SQLite C API for the results store: one connection, prepared
// statements, errors as SweepError naming the database file.
#pragma once

#include <sqlite3.h>

#include <cstdint>
#include <filesystem>
#include <string>

namespace clothlab::sweep {

class SqliteStatement;

class SqliteDatabase {
 public:
  enum class Access { ReadWrite, ReadOnly };
  // Opens (ReadWrite: creates) the file; a busy database is waited on for busy_timeout_ms.
  SqliteDatabase(const std::filesystem::path& path, Access access, int busy_timeout_ms = 10000);
  ~SqliteDatabase();
  SqliteDatabase(const SqliteDatabase&) = delete;
  SqliteDatabase& operator=(const SqliteDatabase&) = delete;

  void execute(const std::string& sql);
  SqliteStatement prepare(const std::string& sql);
  [[noreturn]] void fail(const std::string& what) const;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  sqlite3* handle_ = nullptr;
};

class SqliteStatement {
 public:
  SqliteStatement(SqliteDatabase& database, sqlite3_stmt* statement)
      : database_(&database), statement_(statement) {}
  ~SqliteStatement();
  SqliteStatement(SqliteStatement&& other) noexcept;
  SqliteStatement(const SqliteStatement&) = delete;
  SqliteStatement& operator=(const SqliteStatement&) = delete;
  SqliteStatement& operator=(SqliteStatement&&) = delete;

  SqliteStatement& bind(int index, const std::string& text);
  SqliteStatement& bind(int index, int64_t value);
  // Steps once: true while a result row is available. Throws on an error.
  bool step();
  // Steps to completion (for statements without results) and resets for the next use.
  void run();
  void reset();
  std::string text(int column) const;
  int64_t integer(int column) const;

 private:
  SqliteDatabase* database_;
  sqlite3_stmt* statement_;
};

}  // namespace clothlab::sweep
