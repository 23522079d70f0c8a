// SPDX-License-Identifier: MIT
// Parsed meshes by id (SHA-256 of their bytes): an LRU cache with a byte budget that never
// evicts a mesh a queued or running job holds, backed by the job store (which keeps the
// bytes and original names when durable; a miss reloads from it, whichever replica
// uploaded the mesh).
#pragma once

#include <grpcpp/support/status.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <future>
#include <list>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>

#include "depath/decode/fast_marching.hpp"
#include "depath/mesh/mesh.hpp"
#include "depath/v1/mesh.pb.h"
#include "depath/wire/mesh.hpp"
#include "log.hpp"
#include "store/job_store.hpp"
#include "upload_budget.hpp"

namespace depath::service {

class MeshStore;

/// One stored mesh (all fields guarded by the store's mutex, except the immutable mesh).
struct MeshRecord {
  std::string id, name, format;
  uint64_t size_bytes = 0;
  uint64_t memory_bytes = 0;  ///< the mesh's, plus its stencils' once built
  std::shared_ptr<const Mesh> mesh;
  /// The mesh's fast-marching stencils, built by the first job that runs on it and kept
  /// for the next ones (null until then, and again after the budget dropped them: they are
  /// derived data, so they go before any mesh does and never push a mesh out).
  std::shared_ptr<const FastMarchingStencils> stencils;
  std::mutex stencil_build;  ///< held while building them: one build per mesh, others wait
  v1::MeshInfo info;         // counts, bounding box, warnings
  int pins = 0;
  bool in_cache = false;
  std::list<std::string>::iterator lru_it;
};

/// A job's hold on a mesh: while it lives the mesh is not evicted.
class MeshLease {
 public:
  ~MeshLease();
  MeshLease(const MeshLease&) = delete;
  MeshLease& operator=(const MeshLease&) = delete;
  const Mesh& mesh() const { return *mesh_; }
  const std::string& id() const { return id_; }
  /// The mesh's fast-marching stencils (built on the first call for this mesh, then kept
  /// with it in the cache and counted in its memory); valid while the lease lives.
  const FastMarchingStencils& stencils();

 private:
  friend class MeshStore;
  MeshLease(MeshStore* store, std::shared_ptr<MeshRecord> record)
      : store_(store), record_(std::move(record)), mesh_(record_->mesh), id_(record_->id) {}
  MeshStore* store_;
  std::shared_ptr<MeshRecord> record_;
  std::shared_ptr<const Mesh> mesh_;
  std::string id_;
  std::shared_ptr<const FastMarchingStencils> stencils_;
};

/// Bounds on parsing (uploads and reloads from the data directory alike).
struct ParseLimits {
  int max_concurrent = 2;      ///< parses at the same time; more wait for a slot
  double budget_seconds = 60;  ///< per parse, and the longest wait for a slot
  /// Where a reload takes room for its parse (waiting up to budget_seconds); null: unbounded.
  /// Uploads take theirs before they reach add().
  UploadBudget* memory = nullptr;
};

/// Counters of the cache since the start (for /metrics).
struct MeshCacheStats {
  uint64_t bytes = 0;           ///< memory of the cached meshes now
  uint64_t meshes = 0;          ///< meshes cached now
  uint64_t hits = 0;            ///< lookups (get, job pins) answered from memory
  uint64_t misses = 0;          ///< lookups that went to the store (reload) or found nothing
  uint64_t evictions = 0;       ///< meshes dropped to stay within the budget
  uint64_t stencil_builds = 0;  ///< fast-marching stencil tables built for jobs
};

class MeshStore {
 public:
  /// `store` keeps the bytes when store.keeps_meshes(); else the cache is all there is.
  /// `parse` bounds concurrent parses and the time of each.
  MeshStore(uint64_t budget_bytes, JobStore& store, Log& log, ParseLimits parse = {});

  /// Info of a cached mesh (marks it recently used), or nullopt. Never reads the disk.
  std::optional<v1::MeshInfo> find_cached(const std::string& id);

  /// True when `id` is not in memory but the store keeps its bytes, so that get() or
  /// acquire() would parse it: callers on latency-sensitive threads run those elsewhere.
  bool must_reload(const std::string& id);

  /// Parses `bytes` (format "obj"/"off"/"ply"/"stl"), stores the mesh under `id` and
  /// persists the bytes in the store. Throws depath::Error(invalid_argument) with
  /// the loader's message for a bad file, Error(resource_exhausted) when no parse slot frees
  /// up or the parse overruns its budget. If the id is already cached, nothing is parsed.
  v1::MeshInfo add(const std::string& id, const std::string& name, const std::string& format,
                   const std::string& bytes);

  /// Info of a mesh, reloading it from the store on a cache miss (concurrent reloads of one
  /// mesh share a single parse). Throws ServiceError(NOT_FOUND).
  v1::MeshInfo get(const std::string& id);

  v1::ListMeshesResponse list();

  /// Removes the mesh from the cache and the store. Throws NOT_FOUND.
  void remove(const std::string& id);

  /// Pins the mesh for a job (reloading it from the store if needed). Throws NOT_FOUND.
  std::shared_ptr<MeshLease> acquire(const std::string& id);

  /// Pins the mesh for a queued job of a store that cannot reload it (memory): refused
  /// with ServiceError(RESOURCE_EXHAUSTED) when the meshes already held plus this one
  /// would pass the budget, so queued jobs cannot grow the cache past it.
  std::shared_ptr<MeshLease> hold_for_queue(const std::string& id);

  uint64_t cached_bytes();
  MeshCacheStats cache_stats();

 private:
  friend class MeshLease;
  using Record = MeshRecord;

  void release(const std::shared_ptr<Record>& record);
  std::shared_ptr<const FastMarchingStencils> stencils_of(Record& record);
  std::shared_ptr<Record> insert_locked(std::shared_ptr<Record> record);
  void evict_locked(const std::string& keep);
  /// Frees the stencils of meshes no job holds, least recently used first, until the cache
  /// is within its budget.
  void drop_stencils_locked();
  v1::MeshInfo info_locked(const Record& r) const;
  void touch_locked(Record& r);
  /// Loads the mesh from the store (outside the lock); nullptr if absent.
  std::shared_ptr<Record> load_from_store(const std::string& id);
  std::shared_ptr<Record> lookup_or_load(const std::string& id);
  /// Parses within the limits: waits for a slot (at most the budget), then parses with a deadline.
  std::shared_ptr<Record> parse_bounded(const std::string& id, const std::string& name,
                                        const std::string& format, const std::string& bytes);

  const uint64_t budget_;
  JobStore& store_;
  Log& log_;
  std::mutex mutex_;
  std::unordered_map<std::string, std::shared_ptr<Record>> records_;
  std::list<std::string> lru_;  // most recent first
  uint64_t bytes_ = 0;
  MeshCacheStats stats_;  // hits, misses, evictions (guarded by mutex_)
  // How a reload ended: the record, or the error as a status (an exception object shared by
  // the waiting threads would be freed through a count TSan cannot see).
  struct Loaded {
    std::shared_ptr<Record> record;
    grpc::Status status;
  };
  // Reloads in flight, so that concurrent requests for one mesh wait for a single parse.
  std::unordered_map<std::string, std::shared_future<Loaded>> loading_;

  const ParseLimits parse_limits_;
  std::mutex parse_mutex_;
  std::condition_variable parse_slot_freed_;
  int parses_running_ = 0;
};

/// True for a 64-character lowercase hex string (the wire layer's one check of a mesh id).
using wire::is_mesh_id;

}  // namespace depath::service
