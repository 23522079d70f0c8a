// SPDX-License-Identifier: MIT
// SqlDatabase over PostgreSQL (libpq): a small pool of connections, parameters sent as text
// (numbers) or binary (bytes), results received binary and decoded by column type. A broken
// connection is reset on its next use, so a restarted PostgreSQL is picked up again.
#include <arpa/inet.h>
#include <libpq-fe.h>

#include <bit>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <mutex>

#include "store/sql_database.hpp"

namespace depath::service {
namespace {

// Type oids of pg_type (stable across versions).
constexpr Oid kBool = 16, kInt8 = 20, kInt2 = 21, kInt4 = 23, kFloat4 = 700, kFloat8 = 701;

/// The URI without its password, for messages.
std::string redact(const std::string& uri) {
  const auto scheme = uri.find("://");
  const auto at = uri.find('@');
  if (scheme == std::string::npos || at == std::string::npos) return uri;
  const auto colon = uri.find(':', scheme + 3);
  if (colon == std::string::npos || colon > at) return uri;
  return uri.substr(0, colon) + ":***" + uri.substr(at);
}

template <class T>
T read_be(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  if constexpr (std::endian::native == std::endian::little) {
    if constexpr (sizeof(T) == 8)
      v = static_cast<T>(__builtin_bswap64(static_cast<uint64_t>(v)));
    else if constexpr (sizeof(T) == 4)
      v = static_cast<T>(__builtin_bswap32(static_cast<uint32_t>(v)));
    else
      v = static_cast<T>(__builtin_bswap16(static_cast<uint16_t>(v)));
  }
  return v;
}

class PgDatabase;

class PgSession final : public SqlSession {
 public:
  PgSession(PgDatabase& db, PGconn* conn) : db_(db), conn_(conn) {}
  ~PgSession() override;
  SqlResult exec(std::string_view sql, const std::vector<SqlParam>& params) override;
  void exec_script(std::string_view sql) override;

 private:
  PgDatabase& db_;
  PGconn* conn_;
};

class PgDatabase final : public SqlDatabase {
 public:
  PgDatabase(const std::string& uri, int connections) : uri_(uri) {
    for (int i = 0; i < connections; ++i) {
      PGconn* conn = PQconnectdb(uri.c_str());
      if (PQstatus(conn) != CONNECTION_OK) {
        const std::string message = PQerrorMessage(conn);
        PQfinish(conn);
        for (PGconn* c : free_) PQfinish(c);
        throw StoreError("cannot connect to the PostgreSQL store " + redact(uri) + ": " + trim(message));
      }
      PQsetNoticeProcessor(
          conn, [](void*, const char*) {}, nullptr);  // "already exists" notices
      free_.push_back(conn);
    }
  }
  ~PgDatabase() override {
    for (PGconn* c : free_) PQfinish(c);
  }

  std::unique_ptr<SqlSession> session() override {
    std::unique_lock lock(mutex_);
    available_.wait(lock, [&] { return !free_.empty(); });
    PGconn* conn = free_.back();
    free_.pop_back();
    lock.unlock();
    if (PQstatus(conn) != CONNECTION_OK) PQreset(conn);
    return std::make_unique<PgSession>(*this, conn);
  }
  std::unique_ptr<SqlSession> try_session() override {
    std::unique_lock lock(mutex_);
    if (free_.empty()) return nullptr;
    lock.unlock();
    return session();
  }
  SqlDialect dialect() const override { return SqlDialect::postgresql; }

  void give_back(PGconn* conn) {
    {
      std::lock_guard lock(mutex_);
      free_.push_back(conn);
    }
    available_.notify_one();
  }

  static std::string trim(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    return s;
  }
  const std::string& uri() const { return uri_; }

 private:
  std::string uri_;
  std::mutex mutex_;
  std::condition_variable available_;
  std::vector<PGconn*> free_;
};

PgSession::~PgSession() {
  // A session dropped inside a failed transaction must not hand the next user an aborted one.
  if (PQtransactionStatus(conn_) != PQTRANS_IDLE) {
    PGresult* r = PQexec(conn_, "ROLLBACK");
    PQclear(r);
  }
  db_.give_back(conn_);
}

SqlResult PgSession::exec(std::string_view sql, const std::vector<SqlParam>& params) {
  std::vector<std::string> text(params.size());
  std::vector<const char*> values(params.size());
  std::vector<int> lengths(params.size()), formats(params.size());
  for (size_t i = 0; i < params.size(); ++i) {
    const SqlParam& p = params[i];
    if (std::holds_alternative<std::monostate>(p.value)) {
      values[i] = nullptr;
      continue;
    }
    if (const auto* v = std::get_if<int64_t>(&p.value)) {
      text[i] = std::to_string(*v);
    } else if (const auto* d = std::get_if<double>(&p.value)) {
      char buf[40];
      std::snprintf(buf, sizeof buf, "%.17g", *d);
      text[i] = buf;
    }
    const std::string& s = std::get_if<std::string>(&p.value) ? std::get<std::string>(p.value) : text[i];
    values[i] = s.data();
    lengths[i] = static_cast<int>(s.size());
    formats[i] = p.blob ? 1 : 0;
  }
  PGresult* r = PQexecParams(conn_, std::string(sql).c_str(), static_cast<int>(params.size()), nullptr,
                             values.data(), lengths.data(), formats.data(), 1);
  const auto status = PQresultStatus(r);
  if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK) {
    const std::string message = PgDatabase::trim(r ? PQresultErrorMessage(r) : PQerrorMessage(conn_));
    const bool gone = PQstatus(conn_) != CONNECTION_OK;
    PQclear(r);
    throw StoreError(std::string(gone ? "PostgreSQL store unreachable: " : "PostgreSQL store: ") + message);
  }
  SqlResult result;
  const int rows = PQntuples(r), cols = PQnfields(r);
  result.rows.reserve(static_cast<size_t>(rows));
  for (int i = 0; i < rows; ++i) {
    SqlRow row(static_cast<size_t>(cols));
    for (int c = 0; c < cols; ++c) {
      if (PQgetisnull(r, i, c)) continue;
      const char* v = PQgetvalue(r, i, c);
      const int len = PQgetlength(r, i, c);
      switch (PQftype(r, c)) {
        case kInt8:
          row[c] = read_be<int64_t>(v);
          break;
        case kInt4:
          row[c] = int64_t{read_be<int32_t>(v)};
          break;
        case kInt2:
          row[c] = int64_t{read_be<int16_t>(v)};
          break;
        case kBool:
          row[c] = int64_t{v[0] != 0};
          break;
        case kFloat8:
          row[c] = std::bit_cast<double>(read_be<uint64_t>(v));
          break;
        case kFloat4:
          row[c] = double{std::bit_cast<float>(read_be<uint32_t>(v))};
          break;
        default:
          row[c] = std::string(v, static_cast<size_t>(len));  // text, bytea: the raw bytes
      }
    }
    result.rows.push_back(std::move(row));
  }
  const char* affected = PQcmdTuples(r);
  result.affected = affected && *affected ? std::stoll(affected) : 0;
  PQclear(r);
  return result;
}

void PgSession::exec_script(std::string_view sql) {
  PGresult* r = PQexec(conn_, std::string(sql).c_str());
  const auto status = PQresultStatus(r);
  if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK) {
    const std::string message = PgDatabase::trim(r ? PQresultErrorMessage(r) : PQerrorMessage(conn_));
    PQclear(r);
    throw StoreError("PostgreSQL store: " + message);
  }
  PQclear(r);
}

}  // namespace

std::unique_ptr<SqlDatabase> open_postgresql(const std::string& uri, int connections) {
  return std::make_unique<PgDatabase>(uri, connections);
}

}  // namespace depath::service
