// SPDX-License-Identifier: MIT
#include "store/job_store.hpp"

#include <grpcpp/support/status.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>

namespace depath::service {

namespace {

constexpr int kCancelledCode = static_cast<int>(grpc::StatusCode::CANCELLED);

// Schema migrations, in order: migration k brings the store from version k to k + 1. Each
// has a name, recorded in the store when applied (schema_migrations): a store migrated by
// another build whose migration k differs is refused instead of trusted by its number.
// {BLOB}, {SERIAL} stand for the dialect's byte and auto-numbered key types.
struct Migration {
  const char* name;
  const char* sql;
};
const Migration kMigrations[] = {
    {"initial",
     R"(CREATE TABLE meshes (
         id TEXT PRIMARY KEY, name TEXT NOT NULL, format TEXT NOT NULL, size_bytes BIGINT NOT NULL,
         bytes {BLOB} NOT NULL, created DOUBLE PRECISION NOT NULL);
       CREATE TABLE jobs (
         number {SERIAL},
         id TEXT NOT NULL UNIQUE,
         request_id TEXT UNIQUE,
         mesh_id TEXT NOT NULL,
         spec {BLOB} NOT NULL,
         state BIGINT NOT NULL,
         created DOUBLE PRECISION NOT NULL,
         started DOUBLE PRECISION NOT NULL DEFAULT 0,
         finished DOUBLE PRECISION NOT NULL DEFAULT 0,
         error_code BIGINT NOT NULL DEFAULT 0,
         error_message TEXT NOT NULL DEFAULT '',
         progress {BLOB},
         owner TEXT,
         lease_until DOUBLE PRECISION NOT NULL DEFAULT 0,
         cancel_requested BIGINT NOT NULL DEFAULT 0,
         last_sequence BIGINT NOT NULL DEFAULT 0,
         seq_reserved BIGINT NOT NULL DEFAULT 0,
         has_result BIGINT NOT NULL DEFAULT 0);
       CREATE INDEX jobs_by_state ON jobs (state, number);
       CREATE TABLE events (
         job_id TEXT NOT NULL, sequence BIGINT NOT NULL, progress BIGINT NOT NULL, body {BLOB} NOT NULL,
         PRIMARY KEY (job_id, sequence));
       CREATE TABLE results (job_id TEXT PRIMARY KEY, body {BLOB} NOT NULL);
       CREATE TABLE checkpoints (
         job_id TEXT PRIMARY KEY, generation BIGINT NOT NULL, saved DOUBLE PRECISION NOT NULL, body {BLOB} NOT NULL);
       CREATE TABLE expired_jobs (id TEXT PRIMARY KEY, expired DOUBLE PRECISION NOT NULL);)"},
    // 1 -> 2: per-generation convergence, for the chart of a finished job (events keep only
    // the latest progress).
    {"progress_history",
     R"(CREATE TABLE progress_history (
         job_id TEXT NOT NULL, generation BIGINT NOT NULL, best_energy DOUBLE PRECISION NOT NULL,
         mean_energy DOUBLE PRECISION, PRIMARY KEY (job_id, generation));)"},
    // 2 -> 3: the submitting client of each job, for --max-jobs-per-client across replicas.
    {"jobs_client",
     R"(ALTER TABLE jobs ADD COLUMN client TEXT;
       CREATE INDEX jobs_by_client ON jobs (client, state);)"},
    // 3 -> 4: the trial energies of each generation since a running job's checkpoint, so
    // that a resume from it need not decode those trials again.
    {"trial_journal",
     R"(CREATE TABLE trial_journal (
         job_id TEXT NOT NULL, first_generation BIGINT NOT NULL, last_generation BIGINT NOT NULL,
         energies {BLOB} NOT NULL, PRIMARY KEY (job_id, first_generation));)"},
};
constexpr int kSchemaVersion = static_cast<int>(std::size(kMigrations));

std::string dialect_sql(std::string sql, SqlDialect d) {
  auto replace = [&](const std::string& from, const std::string& to) {
    for (size_t at = sql.find(from); at != std::string::npos; at = sql.find(from, at + to.size())) {
      sql.replace(at, from.size(), to);
    }
  };
  replace("{BLOB}", d == SqlDialect::sqlite ? "BLOB" : "BYTEA");
  replace("{SERIAL}",
          d == SqlDialect::sqlite ? "INTEGER PRIMARY KEY AUTOINCREMENT" : "BIGSERIAL PRIMARY KEY");
  return sql;
}

double now_unix() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

const char* const kJobColumns =
    "number, id, request_id, mesh_id, spec, state, created, started, finished, error_code, error_message, "
    "progress, owner, lease_until, cancel_requested, last_sequence, seq_reserved, has_result";

JobRecord job_from_row(const SqlRow& r) {
  JobRecord j;
  j.number = sql_int(r[0]);
  j.id = sql_string(r[1]);
  j.request_id = sql_string(r[2]);
  j.mesh_id = sql_string(r[3]);
  if (!j.spec.ParseFromString(sql_string(r[4]))) throw StoreError("job " + j.id + ": stored spec is damaged");
  j.state = static_cast<v1::JobState>(sql_int(r[5]));
  j.created = sql_double(r[6]);
  j.started = sql_double(r[7]);
  j.finished = sql_double(r[8]);
  j.error_code = static_cast<int>(sql_int(r[9]));
  j.error_message = sql_string(r[10]);
  if (!sql_null(r[11])) {
    v1::Progress p;
    if (p.ParseFromString(sql_string(r[11]))) j.progress = std::move(p);
  }
  j.owner = sql_string(r[12]);
  j.lease_until = sql_double(r[13]);
  j.cancel_requested = sql_int(r[14]) != 0;
  j.last_sequence = static_cast<uint64_t>(sql_int(r[15]));
  j.seq_reserved = static_cast<uint64_t>(sql_int(r[16]));
  j.has_result = sql_int(r[17]) != 0;
  return j;
}

// What a finished job keeps of its spec: everything but the per-vertex arrays (densities,
// field vectors), which only the run needed; JobInfo never shows them anyway.
std::string finished_spec_blob(const v1::JobSpec& spec) {
  v1::JobSpec slim = spec;
  slim.mutable_energy()->clear_density();
  slim.mutable_energy()->clear_field();
  return slim.SerializeAsString();
}

// The job's stored result (none if it has none).
std::optional<v1::JobResult> read_result(SqlSession& s, const std::string& id) {
  auto rows = s.exec("SELECT body FROM results WHERE job_id = $1", {id}).rows;
  if (rows.empty()) return std::nullopt;
  v1::JobResult result;
  if (!result.ParseFromString(sql_string(rows[0][0])))
    throw StoreError("job " + id + ": the stored result is damaged");
  return result;
}

bool terminal(int state) {
  return state == v1::JOB_STATE_SUCCEEDED || state == v1::JOB_STATE_FAILED ||
         state == v1::JOB_STATE_CANCELLED;
}

}  // namespace

int job_store_schema_version() { return kSchemaVersion; }

int progress_history_stride(int latest) {
  int stride = 1;
  while (latest / stride >= kProgressHistoryPoints) stride *= 2;
  return stride;
}

void thin_progress_history(std::vector<ProgressPoint>& points, int latest) {
  if (points.size() <= 2) return;
  const int stride = progress_history_stride(latest);
  const int first = points.front().generation, last = points.back().generation;
  std::erase_if(points, [&](const ProgressPoint& p) {
    return p.generation % stride != 0 && p.generation != first && p.generation != last;
  });
}

JobStore::JobStore(std::unique_ptr<SqlDatabase> db, std::string description, bool durable, bool keeps_meshes)
    : db_(std::move(db)),
      description_(std::move(description)),
      durable_(durable),
      keeps_meshes_(keeps_meshes) {
  migrate();
  if (db_->dialect() == SqlDialect::sqlite) {
    // One process owns a SQLite store (its lock file): leases of an earlier process are
    // void, its jobs may run again at once.
    auto s = db_->session();
    s->exec("UPDATE jobs SET owner = NULL, lease_until = 0 WHERE owner IS NOT NULL");
  }
}

std::unique_ptr<JobStore> JobStore::open(const std::string& uri) {
  if (uri == "memory") return std::make_unique<JobStore>(open_sqlite(":memory:"), "memory", false, false);
  if (uri.rfind("sqlite:", 0) == 0) {
    const std::string path = uri.substr(7);
    if (path.empty()) throw StoreError("--store sqlite:PATH needs a file path");
    std::error_code ec;
    const auto parent = std::filesystem::path(path).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent, ec);
    if (ec)
      throw StoreError("cannot create the directory " + parent.string() + " for the store: " + ec.message());
    return std::make_unique<JobStore>(open_sqlite(path), "sqlite:" + path, true, true);
  }
  if (uri.rfind("postgresql://", 0) == 0 || uri.rfind("postgres://", 0) == 0) {
    return std::make_unique<JobStore>(open_postgresql(uri, 4), "postgresql", true, true);
  }
  throw StoreError("unknown --store '" + uri + "' (expected memory, sqlite:PATH or postgresql://...)");
}

void JobStore::migrate() {
  auto s = db_->session();
  const SqlDialect d = db_->dialect();
  SqlTransaction tx(*s, d);
  // Replicas starting together: one migrates, the others wait for it here.
  if (d == SqlDialect::postgresql) s->exec("SELECT pg_advisory_xact_lock(4242424201)");
  // schema_version stays the number older depathd builds check; schema_migrations names
  // what was applied.
  s->exec_script(
      "CREATE TABLE IF NOT EXISTS schema_version (version BIGINT NOT NULL);"
      "CREATE TABLE IF NOT EXISTS schema_migrations (version BIGINT PRIMARY KEY, name TEXT NOT NULL)");
  auto rows = s->exec("SELECT version FROM schema_version").rows;
  int version = rows.empty() ? 0 : static_cast<int>(sql_int(rows[0][0]));
  if (rows.empty()) s->exec("INSERT INTO schema_version (version) VALUES (0)");
  const auto applied = s->exec("SELECT version, name FROM schema_migrations ORDER BY version").rows;
  const std::string other_build = "it was written by another build of depathd (a development branch?): use "
                                  "the depathd that wrote it, or another --data-dir / --store";
  for (size_t k = 0; k < applied.size(); ++k) {
    const int64_t number = sql_int(applied[k][0]);
    const std::string name = sql_string(applied[k][1]);
    if (number != static_cast<int64_t>(k) + 1 || number > version) {
      throw StoreError("the store " + description_ + " records schema migration " + std::to_string(number) +
                       " \"" + name + "\" out of order (schema version " + std::to_string(version) +
                       "): " + other_build);
    }
    if (number <= kSchemaVersion && name != kMigrations[number - 1].name) {
      throw StoreError("the store " + description_ + " has schema migration " + std::to_string(number) +
                       " \"" + name + "\" where this depathd has \"" + kMigrations[number - 1].name +
                       "\": " + other_build);
    }
  }
  if (version > kSchemaVersion) {
    throw StoreError("the store " + description_ + " has schema version " + std::to_string(version) +
                     ", newer than this depathd understands (" + std::to_string(kSchemaVersion) +
                     "): run a newer depathd");
  }
  // A store migrated before names were recorded: its number is all there is to go by.
  for (int k = static_cast<int>(applied.size()); k < version; ++k) {
    s->exec("INSERT INTO schema_migrations (version, name) VALUES ($1, $2)", {k + 1, kMigrations[k].name});
  }
  for (; version < kSchemaVersion; ++version) {
    const Migration& m = kMigrations[version];
    try {
      s->exec_script(dialect_sql(m.sql, d));
    } catch (const StoreError& e) {
      throw StoreError("schema migration " + std::to_string(version + 1) + " \"" + m.name + "\" failed on the store " +
                       description_ + " (" + e.what() + "): its schema is not what its version " +
                       std::to_string(version) + " says; " + other_build);
    }
    s->exec("UPDATE schema_version SET version = $1", {version + 1});
    s->exec("INSERT INTO schema_migrations (version, name) VALUES ($1, $2)", {version + 1, m.name});
  }
  tx.commit();
}

// ---- meshes -------------------------------------------------------------------------------

void JobStore::put_mesh(const StoredMesh& m) {
  if (!keeps_meshes_) return;
  auto s = db_->session();
  s->exec(
      "INSERT INTO meshes (id, name, format, size_bytes, bytes, created) VALUES ($1, $2, $3, $4, $5, $6) "
      "ON CONFLICT (id) DO NOTHING",
      {m.id, m.name, m.format, static_cast<int64_t>(m.bytes.size()), sql_blob(m.bytes), now_unix()});
}

std::optional<StoredMesh> JobStore::get_mesh(const std::string& id) {
  if (!keeps_meshes_) return std::nullopt;
  auto s = db_->session();
  auto rows = s->exec("SELECT name, format, bytes FROM meshes WHERE id = $1", {id}).rows;
  if (rows.empty()) return std::nullopt;
  StoredMesh m;
  m.id = id;
  m.name = sql_string(rows[0][0]);
  m.format = sql_string(rows[0][1]);
  m.bytes = sql_string(rows[0][2]);
  m.size_bytes = m.bytes.size();
  return m;
}

bool JobStore::has_mesh(const std::string& id) {
  if (!keeps_meshes_) return false;
  auto s = db_->session();
  return !s->exec("SELECT 1 FROM meshes WHERE id = $1", {id}).rows.empty();
}

std::vector<StoredMesh> JobStore::list_meshes() {
  std::vector<StoredMesh> out;
  if (!keeps_meshes_) return out;
  auto s = db_->session();
  for (const auto& r : s->exec("SELECT id, name, format, size_bytes FROM meshes ORDER BY created").rows) {
    out.push_back(
        {sql_string(r[0]), sql_string(r[1]), sql_string(r[2]), static_cast<uint64_t>(sql_int(r[3])), {}});
  }
  return out;
}

bool JobStore::delete_mesh(const std::string& id) {
  if (!keeps_meshes_) return false;
  auto s = db_->session();
  return s->exec("DELETE FROM meshes WHERE id = $1", {id}).affected > 0;
}

// ---- jobs ---------------------------------------------------------------------------------

std::optional<JobRecord> JobStore::get_job_in(SqlSession& s, const std::string& id, bool for_update) {
  std::string sql = std::string("SELECT ") + kJobColumns + " FROM jobs WHERE id = $1";
  if (for_update && db_->dialect() == SqlDialect::postgresql) sql += " FOR UPDATE";
  auto rows = s.exec(sql, {id}).rows;
  if (rows.empty()) return std::nullopt;
  return job_from_row(rows[0]);
}

std::pair<JobRecord, bool> JobStore::insert_job(const JobRecord& job, v1::JobEvent queued, int max_client_jobs) {
  if (!job.request_id.empty()) {
    if (auto existing = find_request(job.request_id)) return {*existing, false};
  }
  queued.set_job_id(job.id);
  queued.set_sequence(1);
  try {
    auto s = db_->session();
    SqlTransaction tx(*s, db_->dialect());
    if (max_client_jobs > 0 && !job.client.empty()) {
      // Replicas submitting for one client take turns here (SQLite: one connection already).
      if (db_->dialect() == SqlDialect::postgresql) s->exec("SELECT pg_advisory_xact_lock(4242, hashtext($1))", {job.client});
      const int64_t held = sql_int(s->exec("SELECT COUNT(*) FROM jobs WHERE client = $1 AND state IN ($2, $3)",
                                           {job.client, static_cast<int>(v1::JOB_STATE_QUEUED),
                                            static_cast<int>(v1::JOB_STATE_RUNNING)})
                                       .rows.at(0)
                                       .at(0));
      if (held >= max_client_jobs) throw ClientQuotaExceeded(held);
    }
    auto rows =
        s->exec(
             "INSERT INTO jobs (id, request_id, mesh_id, spec, state, created, last_sequence, seq_reserved, client) "
             "VALUES ($1, $2, $3, $4, $5, $6, 1, 1, $7) RETURNING number",
             {job.id, sql_text_or_null(job.request_id), job.mesh_id, sql_blob(job.spec.SerializeAsString()),
              static_cast<int>(v1::JOB_STATE_QUEUED), job.created, sql_text_or_null(job.client)})
            .rows;
    s->exec("INSERT INTO events (job_id, sequence, progress, body) VALUES ($1, 1, 0, $2)",
            {job.id, sql_blob(queued.SerializeAsString())});
    tx.commit();
    JobRecord stored = job;
    stored.number = sql_int(rows.at(0).at(0));
    stored.state = v1::JOB_STATE_QUEUED;
    stored.last_sequence = stored.seq_reserved = 1;
    return {stored, true};
  } catch (const StoreError&) {
    // A twin with the same request id won the race on another connection or replica.
    if (!job.request_id.empty()) {
      if (auto existing = find_request(job.request_id)) return {*existing, false};
    }
    throw;
  }
}

std::optional<JobRecord> JobStore::find_request(const std::string& request_id) {
  auto s = db_->session();
  auto rows =
      s->exec(std::string("SELECT ") + kJobColumns + " FROM jobs WHERE request_id = $1", {request_id}).rows;
  if (rows.empty()) return std::nullopt;
  return job_from_row(rows[0]);
}

std::optional<JobRecord> JobStore::get_job(const std::string& id) {
  auto s = db_->session();
  return get_job_in(*s, id, false);
}

bool JobStore::expired(const std::string& id) {
  auto s = db_->session();
  return !s->exec("SELECT 1 FROM expired_jobs WHERE id = $1", {id}).rows.empty();
}

std::vector<JobRecord> JobStore::list_jobs(const std::string& mesh_id) {
  auto s = db_->session();
  std::vector<SqlRow> rows;
  if (mesh_id.empty()) {
    rows = s->exec(std::string("SELECT ") + kJobColumns + " FROM jobs ORDER BY number").rows;
  } else {
    rows = s->exec(std::string("SELECT ") + kJobColumns + " FROM jobs WHERE mesh_id = $1 ORDER BY number",
                   {mesh_id})
               .rows;
  }
  std::vector<JobRecord> out;
  out.reserve(rows.size());
  for (const auto& r : rows) out.push_back(job_from_row(r));
  return out;
}

int64_t JobStore::count_queued() {
  auto s = db_->session();
  return sql_int(s->exec("SELECT COUNT(*) FROM jobs WHERE state = $1 AND owner IS NULL",
                         {static_cast<int>(v1::JOB_STATE_QUEUED)})
                     .rows.at(0)
                     .at(0));
}

std::map<v1::JobState, int64_t> JobStore::count_by_state() {
  auto s = db_->session();
  std::map<v1::JobState, int64_t> out;
  for (const auto& row : s->exec("SELECT state, COUNT(*) FROM jobs GROUP BY state", {}).rows) {
    out[static_cast<v1::JobState>(sql_int(row.at(0)))] = sql_int(row.at(1));
  }
  return out;
}

int JobStore::queue_position(int64_t number) {
  auto s = db_->session();
  return static_cast<int>(sql_int(s->exec("SELECT COUNT(*) FROM jobs WHERE state = $1 AND number <= $2",
                                          {static_cast<int>(v1::JOB_STATE_QUEUED), number})
                                      .rows.at(0)
                                      .at(0)));
}

std::optional<JobRecord> JobStore::claim(const std::string& owner, double now, double lease_seconds) {
  auto s = db_->session();
  SqlTransaction tx(*s, db_->dialect());
  std::string sql =
      std::string("SELECT ") + kJobColumns +
      " FROM jobs WHERE state IN (1, 2) AND (owner IS NULL OR lease_until < $1) ORDER BY number LIMIT 1";
  if (db_->dialect() == SqlDialect::postgresql) sql += " FOR UPDATE SKIP LOCKED";
  auto rows = s->exec(sql, {now}).rows;
  if (rows.empty()) return std::nullopt;
  JobRecord job = job_from_row(rows[0]);
  job.seq_reserved = std::max(job.seq_reserved, job.last_sequence);
  job.owner = owner;
  job.lease_until = now + lease_seconds;
  s->exec("UPDATE jobs SET owner = $1, lease_until = $2, seq_reserved = $3 WHERE id = $4",
          {owner, job.lease_until, job.seq_reserved, job.id});
  tx.commit();
  return job;
}

JobStore::Heartbeat JobStore::heartbeat(const std::string& owner, const std::vector<std::string>& ids,
                                        double now, double lease_seconds) {
  Heartbeat beat;
  if (ids.empty()) return beat;
  auto s = db_->session();
  SqlTransaction tx(*s, db_->dialect());
  for (const auto& id : ids) {
    if (s->exec("UPDATE jobs SET lease_until = $1 WHERE id = $2 AND owner = $3",
                {now + lease_seconds, id, owner})
            .affected == 0) {
      beat.lost.push_back(id);
    }
  }
  for (const auto& r :
       s->exec("SELECT id FROM jobs WHERE owner = $1 AND cancel_requested <> 0", {owner}).rows) {
    beat.cancel.push_back(sql_string(r[0]));
  }
  tx.commit();
  return beat;
}

bool JobStore::reserve_sequences(const std::string& id, const std::string& owner, uint64_t upto) {
  auto s = db_->session();
  return s->exec("UPDATE jobs SET seq_reserved = $1 WHERE id = $2 AND owner = $3 AND seq_reserved < $1",
                 {upto, id, owner})
                 .affected > 0 ||
         !s->exec("SELECT 1 FROM jobs WHERE id = $1 AND owner = $2", {id, owner}).rows.empty();
}

JobStore::Append JobStore::append_event(const std::string& id, const std::string& owner,
                                        const v1::JobEvent& event, bool wait,
                                        const std::vector<ProgressPoint>& history) {
  auto s = wait ? db_->session() : db_->try_session();
  if (!s) return Append::busy;
  SqlTransaction tx(*s, db_->dialect());
  const auto seq = static_cast<int64_t>(event.sequence());
  int64_t changed = 0;
  if (event.has_progress()) {
    v1::Progress summary = event.progress();
    summary.clear_best_path();
    changed = s->exec(
                   "UPDATE jobs SET progress = $1, last_sequence = CASE WHEN last_sequence < $2 THEN $2 ELSE "
                   "last_sequence END WHERE id = $3 AND owner = $4",
                   {sql_blob(summary.SerializeAsString()), seq, id, owner})
                  .affected;
    if (changed) {
      s->exec("DELETE FROM events WHERE job_id = $1 AND progress <> 0", {id});
      add_history(*s, id, history);
    }
  } else if (event.has_state()) {
    changed = s->exec(
                   "UPDATE jobs SET state = $1, started = CASE WHEN started = 0 THEN $2 ELSE started END, "
                   "last_sequence = CASE WHEN last_sequence < $3 THEN $3 ELSE last_sequence END "
                   "WHERE id = $4 AND owner = $5",
                   {static_cast<int>(event.state().state()), event.time_unix(), seq, id, owner})
                  .affected;
  }
  if (changed == 0) return Append::lost;
  s->exec(
      "INSERT INTO events (job_id, sequence, progress, body) VALUES ($1, $2, $3, $4) ON CONFLICT DO NOTHING",
      {id, seq, event.has_progress() ? 1 : 0, sql_blob(event.SerializeAsString())});
  tx.commit();
  return Append::stored;
}

bool JobStore::write_as_owner(const std::string& id, const std::string& owner,
                              const std::function<void(SqlSession&)>& write) {
  auto s = db_->session();
  SqlTransaction tx(*s, db_->dialect());
  if (s->exec("SELECT 1 FROM jobs WHERE id = $1 AND owner = $2", {id, owner}).rows.empty()) return false;
  write(*s);
  tx.commit();
  return true;
}

bool JobStore::put_checkpoint(const std::string& id, const std::string& owner, int generation,
                              const std::string& bytes, const std::vector<ProgressPoint>& history) {
  return write_as_owner(id, owner, [&](SqlSession& s) {
    s.exec(
        "INSERT INTO checkpoints (job_id, generation, saved, body) VALUES ($1, $2, $3, $4) "
        "ON CONFLICT (job_id) DO UPDATE SET generation = excluded.generation, saved = excluded.saved, "
        "body = excluded.body",
        {id, generation, now_unix(), sql_blob(bytes)});
    s.exec("DELETE FROM trial_journal WHERE job_id = $1 AND last_generation <= $2", {id, generation});
    add_history(s, id, history);
  });
}

bool JobStore::append_journal(const std::string& id, const std::string& owner, const JournalEntry& entry) {
  return write_as_owner(id, owner, [&](SqlSession& s) {
    s.exec(
        "INSERT INTO trial_journal (job_id, first_generation, last_generation, energies) "
        "VALUES ($1, $2, $3, $4) "
        "ON CONFLICT (job_id, first_generation) DO UPDATE SET last_generation = excluded.last_generation, "
        "energies = excluded.energies",
        {id, entry.first_generation, entry.last_generation, sql_blob(entry.energies)});
  });
}

std::vector<JournalEntry> JobStore::journal_after(const std::string& id, int generation) {
  auto s = db_->session();
  std::vector<JournalEntry> entries;
  for (const auto& r : s->exec("SELECT first_generation, last_generation, energies FROM trial_journal "
                               "WHERE job_id = $1 AND last_generation > $2 ORDER BY first_generation",
                               {id, generation})
                           .rows) {
    entries.push_back({static_cast<int>(sql_int(r[0])), static_cast<int>(sql_int(r[1])), sql_string(r[2])});
  }
  return entries;
}

std::optional<v1::JobResult> JobStore::get_result(const std::string& id) {
  auto s = db_->session();
  return read_result(*s, id);
}

std::string JobStore::get_checkpoint(const std::string& id) {
  auto s = db_->session();
  auto rows = s->exec("SELECT body FROM checkpoints WHERE job_id = $1", {id}).rows;
  return rows.empty() ? std::string() : sql_string(rows[0][0]);
}

bool JobStore::finish(const std::string& id, const std::string& owner, const v1::JobResult* result,
                      const std::vector<v1::JobEvent>& events, const std::vector<ProgressPoint>& history) {
  auto s = db_->session();
  SqlTransaction tx(*s, db_->dialect());
  auto job = get_job_in(*s, id, true);
  if (!job || job->owner != owner || terminal(job->state)) return false;
  const v1::JobEvent& last = events.back();  // the terminal state event
  s->exec(
      "UPDATE jobs SET state = $1, finished = $2, error_code = $3, error_message = $4, has_result = $5, "
      "last_sequence = $6, owner = NULL, lease_until = 0, started = CASE WHEN started = 0 THEN $2 ELSE "
      "started END, spec = $8 "
      "WHERE id = $7",
      {static_cast<int>(last.state().state()), last.time_unix(), last.state().error_code(),
       last.state().state() == v1::JOB_STATE_SUCCEEDED ? std::string() : last.state().message(),
       result ? 1 : 0, static_cast<int64_t>(last.sequence()), id, sql_blob(finished_spec_blob(job->spec))});
  if (result) {
    s->exec("INSERT INTO results (job_id, body) VALUES ($1, $2) ON CONFLICT (job_id) DO NOTHING",
            {id, sql_blob(result->SerializeAsString())});
  }
  for (const auto& e : events) {
    if (e.has_progress()) {
      v1::Progress summary = e.progress();
      summary.clear_best_path();
      s->exec("DELETE FROM events WHERE job_id = $1 AND progress <> 0", {id});
      s->exec("UPDATE jobs SET progress = $1 WHERE id = $2", {sql_blob(summary.SerializeAsString()), id});
    }
    // The result event's payload is the results row: stored once (events_after puts it back).
    std::string body;
    if (e.has_result()) {
      v1::JobEvent marker = e;
      marker.mutable_result()->Clear();
      body = marker.SerializeAsString();
    } else {
      body = e.SerializeAsString();
    }
    s->exec(
        "INSERT INTO events (job_id, sequence, progress, body) VALUES ($1, $2, $3, $4) ON CONFLICT DO "
        "NOTHING",
        {id, static_cast<int64_t>(e.sequence()), e.has_progress() ? 1 : 0, sql_blob(body)});
  }
  add_history(*s, id, history);
  s->exec("DELETE FROM checkpoints WHERE job_id = $1", {id});
  s->exec("DELETE FROM trial_journal WHERE job_id = $1", {id});
  tx.commit();
  return true;
}

// Adds points (a resumed run repeats generations with the same figures: the newer wins), then
// drops the stored points the stride of the latest generation no longer keeps.
void JobStore::add_history(SqlSession& s, const std::string& id, std::vector<ProgressPoint> points) {
  if (points.empty()) return;
  std::sort(points.begin(), points.end(),
            [](const ProgressPoint& a, const ProgressPoint& b) { return a.generation < b.generation; });
  // One row per generation in a statement (PostgreSQL refuses to update a row twice in one).
  points.erase(std::unique(points.begin(), points.end(),
                           [](const ProgressPoint& a, const ProgressPoint& b) {
                             return a.generation == b.generation;
                           }),
               points.end());
  const int latest = points.back().generation;
  const int stride = progress_history_stride(latest);
  thin_progress_history(points, latest);  // what the stride keeps, with the first and the latest
  // One statement per 200 points (a fast job stores hundreds of generations per progress write).
  std::string sql;
  std::vector<SqlParam> params;
  auto flush = [&] {
    if (params.empty()) return;
    s.exec("INSERT INTO progress_history (job_id, generation, best_energy, mean_energy) VALUES " + sql +
               " ON CONFLICT (job_id, generation) DO UPDATE SET best_energy = excluded.best_energy, "
               "mean_energy = excluded.mean_energy",
           params);
    sql.clear();
    params.clear();
  };
  for (const ProgressPoint& p : points) {
    if (!std::isfinite(p.best_energy)) continue;  // no agent decoded yet
    const size_t k = params.size();
    sql += (k ? ",($" : "($") + std::to_string(k + 1) + ",$" + std::to_string(k + 2) + ",$" +
           std::to_string(k + 3) + ",$" + std::to_string(k + 4) + ")";
    params.insert(params.end(),
                  {SqlParam(id), SqlParam(p.generation), SqlParam(p.best_energy),
                   std::isfinite(p.mean_energy) ? SqlParam(p.mean_energy) : SqlParam(std::monostate{})});
    if (params.size() >= 4 * 200) flush();
  }
  flush();
  s.exec(
      "DELETE FROM progress_history WHERE job_id = $1 AND generation % $2 <> 0 AND generation < $3 AND "
      "generation > (SELECT MIN(generation) FROM progress_history WHERE job_id = $1)",
      {id, stride, latest});
}

std::vector<ProgressPoint> JobStore::progress_history(const std::string& id) {
  auto s = db_->session();
  std::vector<ProgressPoint> out;
  for (const auto& r :
       s->exec("SELECT generation, best_energy, mean_energy FROM progress_history WHERE job_id = "
               "$1 ORDER BY generation",
               {id})
           .rows) {
    out.push_back({static_cast<int>(sql_int(r[0])), sql_double(r[1]),
                   sql_null(r[2]) ? std::numeric_limits<double>::quiet_NaN() : sql_double(r[2])});
  }
  return out;
}

void JobStore::release(const std::string& id, const std::string& owner) {
  auto s = db_->session();
  s->exec("UPDATE jobs SET owner = NULL, lease_until = 0 WHERE id = $1 AND owner = $2", {id, owner});
}

int JobStore::release_all(const std::string& owner) {
  auto s = db_->session();
  SqlTransaction tx(*s, db_->dialect());
  const int64_t held = sql_int(s->exec("SELECT COUNT(*) FROM jobs WHERE owner = $1", {owner}).rows[0][0]);
  s->exec("UPDATE jobs SET owner = NULL, lease_until = 0 WHERE owner = $1", {owner});
  tx.commit();
  return static_cast<int>(held);
}

CancelOutcome JobStore::cancel(const std::string& id, v1::JobEvent event) {
  auto s = db_->session();
  SqlTransaction tx(*s, db_->dialect());
  auto job = get_job_in(*s, id, true);
  if (!job || terminal(job->state)) return CancelOutcome::already_final;
  if (job->state == v1::JOB_STATE_QUEUED && job->owner.empty()) {
    const uint64_t seq = std::max(job->last_sequence, job->seq_reserved) + 1;
    event.set_job_id(id);
    event.set_sequence(seq);
    s->exec(
        "UPDATE jobs SET state = $1, finished = $2, error_code = $3, error_message = $4, last_sequence = $5, "
        "seq_reserved = $5, spec = $7 WHERE id = $6",
        {static_cast<int>(v1::JOB_STATE_CANCELLED), event.time_unix(), kCancelledCode,
         event.state().message(), static_cast<int64_t>(seq), id, sql_blob(finished_spec_blob(job->spec))});
    s->exec("INSERT INTO events (job_id, sequence, progress, body) VALUES ($1, $2, 0, $3)",
            {id, static_cast<int64_t>(seq), sql_blob(event.SerializeAsString())});
    tx.commit();
    return CancelOutcome::cancelled_queued;
  }
  s->exec("UPDATE jobs SET cancel_requested = 1 WHERE id = $1", {id});
  tx.commit();
  return CancelOutcome::requested;
}

std::vector<v1::JobEvent> JobStore::events_after(const std::string& id, uint64_t after) {
  auto s = db_->session();
  std::vector<v1::JobEvent> out;
  for (const auto& r :
       s->exec("SELECT body FROM events WHERE job_id = $1 AND sequence > $2 ORDER BY sequence",
               {id, static_cast<int64_t>(after)})
           .rows) {
    v1::JobEvent e;
    if (!e.ParseFromString(sql_string(r[0]))) throw StoreError("job " + id + ": a stored event is damaged");
    if (e.has_result() && e.result().ByteSizeLong() == 0) {  // stored without its payload (finish)
      auto result = read_result(*s, id);
      if (!result) throw StoreError("job " + id + ": the stored result is missing");
      *e.mutable_result() = std::move(*result);
    }
    out.push_back(std::move(e));
  }
  return out;
}

int JobStore::expire(double before, int64_t keep_at_most) {
  auto s = db_->session();
  SqlTransaction tx(*s, db_->dialect());
  auto rows =
      s->exec("SELECT id FROM jobs WHERE state IN (3, 4, 5) AND finished < $1 ORDER BY number LIMIT 1000",
              {before})
          .rows;
  // Past the cap, the oldest finished jobs go too, TTL or not.
  const int64_t finished = sql_int(s->exec("SELECT COUNT(*) FROM jobs WHERE state IN (3, 4, 5)").rows[0][0]);
  const int64_t over = finished - static_cast<int64_t>(rows.size()) - std::max<int64_t>(keep_at_most, 0);
  if (over > 0) {
    auto oldest =
        s->exec(
             "SELECT id FROM jobs WHERE state IN (3, 4, 5) AND finished >= $1 ORDER BY finished, number "
             "LIMIT $2",
             {before, std::min<int64_t>(over, 1000)})
            .rows;
    rows.insert(rows.end(), oldest.begin(), oldest.end());
  }
  const double now = now_unix();
  for (const auto& r : rows) {
    const std::string id = sql_string(r[0]);
    s->exec("DELETE FROM events WHERE job_id = $1", {id});
    s->exec("DELETE FROM results WHERE job_id = $1", {id});
    s->exec("DELETE FROM checkpoints WHERE job_id = $1", {id});
    s->exec("DELETE FROM trial_journal WHERE job_id = $1", {id});
    s->exec("DELETE FROM progress_history WHERE job_id = $1", {id});
    s->exec("DELETE FROM jobs WHERE id = $1", {id});
    s->exec("INSERT INTO expired_jobs (id, expired) VALUES ($1, $2) ON CONFLICT DO NOTHING", {id, now});
  }
  // Tombstones only sharpen NOT_FOUND messages; a month of them is plenty.
  s->exec("DELETE FROM expired_jobs WHERE expired < $1", {now - 30 * 86400.0});
  tx.commit();
  return static_cast<int>(rows.size());
}

}  // namespace depath::service
