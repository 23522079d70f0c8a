// SPDX-License-Identifier: MIT
// The durable state of depathd: meshes, jobs (spec, state, lease), their numbered events,
// results, DE checkpoints with the journal of trial energies since each, and per-generation
// progress histories, in SQLite (default, one process) or
// PostgreSQL (shared by replicas), or in an in-process SQLite database for `--store memory`.
//
// open_job_store(uri): "memory", "sqlite:PATH", "postgresql://..." (or "postgres://...").
// The schema is versioned (table schema_version) and migrated at open; a store written by
// a newer depathd, an unreachable server or an unwritable file throw StoreError naming it.
//
// Ownership of work: a job is run by the replica that holds its lease (owner +
// lease_until); every write a runner makes (events, checkpoint, journal, finish) is conditional on
// still holding it, so a job taken over after its lease expired never completes twice.
// Event sequences are assigned by the owner; it reserves them in blocks (seq_reserved) so
// a replica taking a job over continues above every number the previous owner may have
// shown a watcher.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "depath/v1/job.pb.h"
#include "store/sql_database.hpp"

namespace depath::service {

struct StoredMesh {
  std::string id, name, format;
  uint64_t size_bytes = 0;
  std::string bytes;  ///< empty in listings
};

struct JobRecord {
  int64_t number = 0;  ///< submission order
  std::string id, request_id, mesh_id;
  std::string client;  ///< who submitted it (AccessGuard's identity), for --max-jobs-per-client; set at insert only
  v1::JobSpec spec;
  v1::JobState state = v1::JOB_STATE_QUEUED;
  double created = 0, started = 0, finished = 0;
  int error_code = 0;
  std::string error_message;
  std::optional<v1::Progress> progress;  ///< latest, without a path
  std::string owner;
  double lease_until = 0;
  bool cancel_requested = false;
  uint64_t last_sequence = 0;  ///< highest stored event sequence
  uint64_t seq_reserved = 0;   ///< highest sequence an owner may have used
  bool has_result = false;
};

/// One generation of a job's convergence (what the chart of a job's page draws).
struct ProgressPoint {
  int generation = 0;
  double best_energy = 0;
  double mean_energy = 0;  ///< NaN when some agents had no finite energy (stored as NULL)
};

/// Consecutive generations of a running job's journal: their trials' energies, as the
/// solver reported them (encoded by the job manager), one write's worth.
struct JournalEntry {
  int first_generation = 0;
  int last_generation = 0;
  std::string energies;
};

/// A job's progress history keeps at most about this many points: every generation while
/// there are fewer, then every 2nd, 4th, ... (the stride doubles as the job goes on), always
/// with the first and the latest generation. Bounded whatever --generations allows.
constexpr int kProgressHistoryPoints = 1000;
/// The stride of the history once `latest` generations are done (a power of two).
int progress_history_stride(int latest);
/// Removes from `points` (ascending generations) those a history at `latest` drops: not a
/// multiple of the stride, neither the first nor the last.
void thin_progress_history(std::vector<ProgressPoint>& points, int latest);

/// insert_job refused the job: its client already has `held` jobs queued or running.
class ClientQuotaExceeded : public std::runtime_error {
 public:
  explicit ClientQuotaExceeded(int64_t held) : std::runtime_error("client job quota"), held(held) {}
  int64_t held;
};

enum class CancelOutcome { cancelled_queued, requested, already_final };

class JobStore {
 public:
  JobStore(std::unique_ptr<SqlDatabase> db, std::string description, bool durable, bool keeps_meshes);

  /// "memory", "sqlite:PATH" or "postgresql://...". Throws StoreError.
  static std::unique_ptr<JobStore> open(const std::string& uri);

  bool durable() const { return durable_; }
  /// Other processes may change it (PostgreSQL): poll for their jobs and events.
  bool shared() const { return db_->dialect() == SqlDialect::postgresql; }
  bool keeps_meshes() const { return keeps_meshes_; }
  const std::string& description() const { return description_; }

  // Meshes (no-ops / nothing found when !keeps_meshes()).
  void put_mesh(const StoredMesh& mesh);
  std::optional<StoredMesh> get_mesh(const std::string& id);
  /// Whether get_mesh would find it, without reading the bytes.
  bool has_mesh(const std::string& id);
  std::vector<StoredMesh> list_meshes();
  bool delete_mesh(const std::string& id);

  /// Stores a new queued job and its first event (sequence 1). If its request id is taken
  /// already, stores nothing and returns the existing job (second = false). With
  /// `max_client_jobs` > 0 and a job.client, throws ClientQuotaExceeded when that client has
  /// that many jobs queued or running in the store already: counted in the insert's
  /// transaction (on PostgreSQL under a lock per client), so the cap holds across replicas.
  std::pair<JobRecord, bool> insert_job(const JobRecord& job, v1::JobEvent queued, int max_client_jobs = 0);
  std::optional<JobRecord> find_request(const std::string& request_id);
  std::optional<JobRecord> get_job(const std::string& id);
  /// True if the id belonged to a job removed after its TTL.
  bool expired(const std::string& id);
  std::vector<JobRecord> list_jobs(const std::string& mesh_id);
  int64_t count_queued();
  /// Jobs in the store per state (one aggregate query, for /metrics); states with none are absent.
  std::map<v1::JobState, int64_t> count_by_state();
  /// 1-based position among queued jobs (0 if not queued).
  int queue_position(int64_t number);

  /// Takes the oldest queued job, or a running one whose lease expired, for `owner`.
  std::optional<JobRecord> claim(const std::string& owner, double now, double lease_seconds);
  /// Renews the leases of `ids`; returns those whose cancellation was requested and those
  /// no longer held (taken over, finished elsewhere).
  struct Heartbeat {
    std::vector<std::string> cancel, lost;
  };
  Heartbeat heartbeat(const std::string& owner, const std::vector<std::string>& ids, double now,
                      double lease_seconds);
  /// Reserves sequences up to `upto`. False if the lease is lost.
  bool reserve_sequences(const std::string& id, const std::string& owner, uint64_t upto);
  /// Stores a state or result event (or progress: replaces the job's previous progress
  /// row and its JobInfo progress, and adds `history` — the generations since the last
  /// stored progress — to the job's progress history). `state`: the job's new state
  /// (RUNNING sets started). lost: the lease is lost (nothing written); busy: !wait and the
  /// store is busy.
  enum class Append { stored, lost, busy };
  Append append_event(const std::string& id, const std::string& owner, const v1::JobEvent& event,
                      bool wait = true, const std::vector<ProgressPoint>& history = {});
  /// Stores the checkpoint and `history` (the generations up to it not stored yet, so that a
  /// run resumed from it leaves no gap in the progress history). False if the lease is lost.
  bool put_checkpoint(const std::string& id, const std::string& owner, int generation,
                      const std::string& bytes, const std::vector<ProgressPoint>& history = {});
  std::string get_checkpoint(const std::string& id);
  /// Adds generations to the job's journal since its checkpoint, one row (an entry with the
  /// same first generation, from a resumed run, is replaced). False (nothing written) if the
  /// lease is lost. put_checkpoint drops the entries it covers whole, finish and expire the
  /// rest.
  bool append_journal(const std::string& id, const std::string& owner, const JournalEntry& entry);
  /// The journal's entries that reach past `generation`, by first generation.
  std::vector<JournalEntry> journal_after(const std::string& id, int generation);
  std::optional<v1::JobResult> get_result(const std::string& id);
  /// Terminal state, result and final events (the terminal state event last; a progress
  /// event among them replaces the stored one) in one transaction; drops the checkpoint,
  /// the journal and the spec's per-vertex arrays (a finished job keeps only what its result
  /// needs).
  /// False (and nothing written) if the lease is lost.
  /// `history`: the generations not stored yet, added to the progress history.
  bool finish(const std::string& id, const std::string& owner, const v1::JobResult* result,
              const std::vector<v1::JobEvent>& events, const std::vector<ProgressPoint>& history = {});
  /// Gives the job back (stays queued/running) for another replica or a restart.
  void release(const std::string& id, const std::string& owner);
  /// Gives back every job `owner` holds (a named replica's earlier life); returns how many.
  int release_all(const std::string& owner);

  /// Cancels a queued job at once (storing `event`, numbered here) or asks its runner to stop.
  CancelOutcome cancel(const std::string& id, v1::JobEvent event);

  /// Events with a sequence above `after`, in order (progress: only the latest).
  std::vector<v1::JobEvent> events_after(const std::string& id, uint64_t after);

  /// The job's progress history, ascending generations (thinned as kProgressHistoryPoints
  /// says); it survives restarts and stays after the job ends, until the job expires.
  std::vector<ProgressPoint> progress_history(const std::string& id);

  /// Removes terminal jobs finished before `before`, and the oldest terminal jobs past the
  /// newest `keep_at_most`, with their events, results and checkpoints, leaving a
  /// tombstone. Returns how many (at most about 2000 a call).
  int expire(double before, int64_t keep_at_most);

 private:
  void migrate();
  std::optional<JobRecord> get_job_in(SqlSession& s, const std::string& id, bool for_update);
  void add_history(SqlSession& s, const std::string& id, std::vector<ProgressPoint> points);
  // Runs `write` in one transaction while `owner` holds job `id`; false (nothing written)
  // once the job is another owner's or gone.
  bool write_as_owner(const std::string& id, const std::string& owner,
                      const std::function<void(SqlSession&)>& write);

  std::unique_ptr<SqlDatabase> db_;
  std::string description_;
  bool durable_;
  bool keeps_meshes_;
};

/// Current schema version written by this build.
int job_store_schema_version();

}  // namespace depath::service
