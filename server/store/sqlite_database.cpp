// SPDX-License-Identifier: MIT
// SqlDatabase over one SQLite connection: WAL journal (readers never block the writer, a
// kill -9 at any instant leaves the last committed transaction), synchronous=FULL (a
// committed submit survives a power cut too), statements prepared once and cached. One
// process owns the file: an flock'ed "<file>.lock" beside it refuses a second depathd.
#include <fcntl.h>
#include <sqlite3.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <map>
#include <mutex>

#include "store/sql_database.hpp"

namespace depath::service {
namespace {

std::string owner_hint() {
  return " (depathd runs as uid " + std::to_string(::getuid()) +
         "; the data directory and its files must be writable by that user)";
}

class SqliteDatabase;

class SqliteSession final : public SqlSession {
 public:
  SqliteSession(SqliteDatabase& db, std::unique_lock<std::mutex> lock) : db_(db), lock_(std::move(lock)) {}
  SqlResult exec(std::string_view sql, const std::vector<SqlParam>& params) override;
  void exec_script(std::string_view sql) override;

 private:
  SqliteDatabase& db_;
  std::unique_lock<std::mutex> lock_;
};

class SqliteDatabase final : public SqlDatabase {
 public:
  explicit SqliteDatabase(const std::string& path) : path_(path) {
    if (path != ":memory:") {
      const std::string lock_path = path + ".lock";
      lock_fd_ = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
      if (lock_fd_ < 0) {
        throw StoreError("cannot create " + lock_path + ": " + std::strerror(errno) + owner_hint());
      }
      if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
        ::close(lock_fd_);
        throw StoreError(
            "the store " + path +
            " is in use by another depathd (SQLite has one writer): give this one its own --data-dir, "
            "or run replicas on --store postgresql://...");
      }
    }
    const int rc = sqlite3_open_v2(path.c_str(), &db_,
                                   SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX, nullptr);
    if (rc != SQLITE_OK) {
      const std::string message = db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(rc);
      sqlite3_close(db_);
      db_ = nullptr;
      throw StoreError("cannot open the SQLite store " + path + ": " + message + owner_hint());
    }
    sqlite3_busy_timeout(db_, 10000);
    try {
      auto s = session();
      s->exec_script("PRAGMA journal_mode=WAL; PRAGMA synchronous=FULL; PRAGMA foreign_keys=OFF;");
      // Fails here, at start, on a read-only file or directory (not at the first upload).
      s->exec_script(
          "CREATE TABLE IF NOT EXISTS depath_write_check (x INTEGER); DROP TABLE depath_write_check;");
    } catch (const StoreError& e) {
      close();
      throw StoreError(std::string(e.what()) + owner_hint());
    }
  }
  ~SqliteDatabase() override { close(); }

  std::unique_ptr<SqlSession> session() override {
    return std::make_unique<SqliteSession>(*this, std::unique_lock(mutex_));
  }
  std::unique_ptr<SqlSession> try_session() override {
    std::unique_lock lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock()) return nullptr;
    return std::make_unique<SqliteSession>(*this, std::move(lock));
  }
  SqlDialect dialect() const override { return SqlDialect::sqlite; }

  [[noreturn]] void fail(const std::string& what) {
    throw StoreError("SQLite store " + path_ + ": " + what + ": " + sqlite3_errmsg(db_));
  }

  sqlite3_stmt* statement(std::string_view sql) {
    auto it = statements_.find(std::string(sql));
    if (it != statements_.end()) return it->second;
    // "$N" -> "?N": SQLite's numbered parameters, bound by index.
    std::string text(sql);
    for (auto& c : text) {
      if (c == '$') c = '?';
    }
    sqlite3_stmt* stmt = nullptr;
    if (sqlite3_prepare_v2(db_, text.c_str(), static_cast<int>(text.size()), &stmt, nullptr) != SQLITE_OK) {
      fail("cannot prepare '" + text.substr(0, 80) + "'");
    }
    statements_.emplace(std::string(sql), stmt);
    return stmt;
  }

  sqlite3* db_ = nullptr;
  std::mutex mutex_;

 private:
  void close() {
    for (auto& [sql, stmt] : statements_) sqlite3_finalize(stmt);
    statements_.clear();
    if (db_) sqlite3_close(db_);
    db_ = nullptr;
    if (lock_fd_ >= 0) ::close(lock_fd_);
    lock_fd_ = -1;
  }
  std::string path_;
  int lock_fd_ = -1;
  std::map<std::string, sqlite3_stmt*> statements_;
};

SqlResult SqliteSession::exec(std::string_view sql, const std::vector<SqlParam>& params) {
  sqlite3_stmt* stmt = db_.statement(sql);
  sqlite3_reset(stmt);
  sqlite3_clear_bindings(stmt);
  for (size_t i = 0; i < params.size(); ++i) {
    const int k = static_cast<int>(i) + 1;
    const SqlParam& p = params[i];
    int rc = SQLITE_OK;
    if (std::holds_alternative<std::monostate>(p.value))
      rc = sqlite3_bind_null(stmt, k);
    else if (const auto* v = std::get_if<int64_t>(&p.value))
      rc = sqlite3_bind_int64(stmt, k, *v);
    else if (const auto* d = std::get_if<double>(&p.value))
      rc = sqlite3_bind_double(stmt, k, *d);
    else {
      const auto& s = std::get<std::string>(p.value);
      rc = p.blob ? sqlite3_bind_blob64(stmt, k, s.data(), s.size(), SQLITE_STATIC)
                  : sqlite3_bind_text64(stmt, k, s.data(), s.size(), SQLITE_STATIC, SQLITE_UTF8);
    }
    if (rc != SQLITE_OK) db_.fail("cannot bind parameter " + std::to_string(k));
  }
  SqlResult result;
  for (;;) {
    const int rc = sqlite3_step(stmt);
    if (rc == SQLITE_DONE) break;
    if (rc != SQLITE_ROW) {
      sqlite3_reset(stmt);
      std::string what(sql.substr(0, 60));
      what.append(" failed");
      db_.fail(what);
    }
    SqlRow row(static_cast<size_t>(sqlite3_column_count(stmt)));
    for (int c = 0; c < static_cast<int>(row.size()); ++c) {
      switch (sqlite3_column_type(stmt, c)) {
        case SQLITE_INTEGER:
          row[c] = static_cast<int64_t>(sqlite3_column_int64(stmt, c));
          break;
        case SQLITE_FLOAT:
          row[c] = sqlite3_column_double(stmt, c);
          break;
        case SQLITE_NULL:
          break;
        default: {
          const auto* data = static_cast<const char*>(sqlite3_column_blob(stmt, c));
          row[c] = std::string(data ? data : "", static_cast<size_t>(sqlite3_column_bytes(stmt, c)));
        }
      }
    }
    result.rows.push_back(std::move(row));
  }
  result.affected = sqlite3_changes(db_.db_);
  sqlite3_reset(stmt);
  sqlite3_clear_bindings(stmt);
  return result;
}

void SqliteSession::exec_script(std::string_view sql) {
  char* error = nullptr;
  if (sqlite3_exec(db_.db_, std::string(sql).c_str(), nullptr, nullptr, &error) != SQLITE_OK) {
    const std::string message = error ? error : "unknown error";
    sqlite3_free(error);
    throw StoreError("SQLite store: " + message);
  }
}

}  // namespace

std::unique_ptr<SqlDatabase> open_sqlite(const std::string& path) {
  return std::make_unique<SqliteDatabase>(path);
}

}  // namespace depath::service
