// SPDX-License-Identifier: MIT
// The little SQL the job store needs, over SQLite or PostgreSQL: parameterised statements
// ($1, $2, ... in both), rows of integers, doubles, text/bytes and NULL, and transactions.
//
// A session is exclusive use of one connection until it is destroyed (SQLite: the one
// connection, behind a mutex; PostgreSQL: one of a small pool). Errors throw StoreError
// with the database's message.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace depath::service {

/// A store failure (unreachable, refused, corrupt, newer schema); the message says which.
class StoreError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

using SqlValue = std::variant<std::monostate, int64_t, double, std::string>;
using SqlRow = std::vector<SqlValue>;

/// A statement parameter; `blob` marks bytes (BLOB / BYTEA) rather than text.
struct SqlParam {
  SqlValue value;
  bool blob = false;
  SqlParam(std::monostate) {}
  SqlParam(int64_t v) : value(v) {}
  SqlParam(int v) : value(int64_t{v}) {}
  SqlParam(uint64_t v) : value(static_cast<int64_t>(v)) {}
  SqlParam(double v) : value(v) {}
  SqlParam(std::string v) : value(std::move(v)) {}
  SqlParam(const char* v) : value(std::string(v)) {}
};
inline SqlParam sql_blob(std::string bytes) {
  SqlParam p(std::move(bytes));
  p.blob = true;
  return p;
}
/// NULL for an empty string, else the text.
inline SqlParam sql_text_or_null(const std::string& s) {
  return s.empty() ? SqlParam(std::monostate{}) : SqlParam(s);
}

struct SqlResult {
  std::vector<SqlRow> rows;
  int64_t affected = 0;  ///< rows changed by INSERT / UPDATE / DELETE
};

int64_t sql_int(const SqlValue& v);         ///< 0 for NULL
double sql_double(const SqlValue& v);       ///< 0 for NULL
std::string sql_string(const SqlValue& v);  ///< "" for NULL
bool sql_null(const SqlValue& v);

enum class SqlDialect { sqlite, postgresql };

class SqlSession {
 public:
  virtual ~SqlSession() = default;
  virtual SqlResult exec(std::string_view sql, const std::vector<SqlParam>& params = {}) = 0;
  /// Several statements without parameters (schema migrations).
  virtual void exec_script(std::string_view sql) = 0;
};

class SqlDatabase {
 public:
  virtual ~SqlDatabase() = default;
  virtual std::unique_ptr<SqlSession> session() = 0;
  /// A session only if a connection is free right now (else nullptr): for writes that may
  /// be skipped rather than wait (progress rows while a large checkpoint is being stored).
  virtual std::unique_ptr<SqlSession> try_session() = 0;
  virtual SqlDialect dialect() const = 0;
};

/// BEGIN (IMMEDIATE on SQLite: take the write lock up front) ... COMMIT; rolls back if not
/// committed when destroyed.
class SqlTransaction {
 public:
  SqlTransaction(SqlSession& session, SqlDialect dialect);
  ~SqlTransaction();
  SqlTransaction(const SqlTransaction&) = delete;
  SqlTransaction& operator=(const SqlTransaction&) = delete;
  void commit();

 private:
  SqlSession& session_;
  bool open_ = true;
};

/// SQLite file (or ":memory:"), WAL mode; exclusive to this process (a lock file next to it).
std::unique_ptr<SqlDatabase> open_sqlite(const std::string& path);
/// PostgreSQL by libpq connection URI; `connections` in the pool.
std::unique_ptr<SqlDatabase> open_postgresql(const std::string& uri, int connections);

}  // namespace depath::service
