// SPDX-License-Identifier: MIT
#include "store/sql_database.hpp"

namespace depath::service {

int64_t sql_int(const SqlValue& v) {
  if (const auto* i = std::get_if<int64_t>(&v)) return *i;
  if (const auto* d = std::get_if<double>(&v)) return static_cast<int64_t>(*d);
  if (const auto* s = std::get_if<std::string>(&v)) return s->empty() ? 0 : std::stoll(*s);
  return 0;
}

double sql_double(const SqlValue& v) {
  if (const auto* d = std::get_if<double>(&v)) return *d;
  if (const auto* i = std::get_if<int64_t>(&v)) return static_cast<double>(*i);
  if (const auto* s = std::get_if<std::string>(&v)) return s->empty() ? 0.0 : std::stod(*s);
  return 0.0;
}

std::string sql_string(const SqlValue& v) {
  if (const auto* s = std::get_if<std::string>(&v)) return *s;
  if (const auto* i = std::get_if<int64_t>(&v)) return std::to_string(*i);
  return {};
}

bool sql_null(const SqlValue& v) { return std::holds_alternative<std::monostate>(v); }

SqlTransaction::SqlTransaction(SqlSession& session, SqlDialect dialect) : session_(session) {
  session_.exec(dialect == SqlDialect::sqlite ? "BEGIN IMMEDIATE" : "BEGIN");
}

SqlTransaction::~SqlTransaction() {
  if (!open_) return;
  try {
    session_.exec("ROLLBACK");
  } catch (...) {  // the connection is gone; nothing was committed
  }
}

void SqlTransaction::commit() {
  session_.exec("COMMIT");
  open_ = false;
}

}  // namespace depath::service
