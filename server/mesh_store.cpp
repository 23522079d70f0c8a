// SPDX-License-Identifier: MIT
#include "mesh_store.hpp"

#include "depath/io/mesh_reader.hpp"
#include "depath/util/error.hpp"
#include "depath/wire/wire.hpp"
#include "service_error.hpp"

namespace depath::service {

namespace {
ServiceError not_found(const std::string& id) {
  return ServiceError(
      grpc::StatusCode::NOT_FOUND,
      "mesh " + id + " not found (unknown, deleted or evicted from the cache): upload it again");
}
}  // namespace

MeshLease::~MeshLease() { store_->release(record_); }

const FastMarchingStencils& MeshLease::stencils() {
  if (!stencils_) stencils_ = store_->stencils_of(*record_);
  return *stencils_;
}

MeshStore::MeshStore(uint64_t budget_bytes, JobStore& store, Log& log, ParseLimits parse)
    : budget_(budget_bytes), store_(store), log_(log), parse_limits_(parse) {}

void MeshStore::touch_locked(Record& r) { lru_.splice(lru_.begin(), lru_, r.lru_it); }

v1::MeshInfo MeshStore::info_locked(const Record& r) const {
  v1::MeshInfo info = r.info;
  info.set_id(r.id);
  info.set_name(r.name);
  info.set_format(r.format);
  info.set_size_bytes(r.size_bytes);
  info.set_memory_bytes(r.memory_bytes);
  info.set_jobs_using(r.pins);
  info.set_cached(true);
  return info;
}

std::optional<v1::MeshInfo> MeshStore::find_cached(const std::string& id) {
  std::lock_guard lock(mutex_);
  auto it = records_.find(id);
  if (it == records_.end()) return std::nullopt;
  touch_locked(*it->second);
  return info_locked(*it->second);
}

bool MeshStore::must_reload(const std::string& id) {
  {
    std::lock_guard lock(mutex_);
    if (records_.count(id)) return false;
  }
  return is_mesh_id(id) && store_.has_mesh(id);  // one indexed query, outside the lock
}

namespace {
std::shared_ptr<MeshRecord> parse_record(const std::string& id, const std::string& name,
                                         const std::string& format, const std::string& bytes,
                                         const MeshReadLimits& limits) {
  auto r = std::make_shared<MeshRecord>();
  r->id = id;
  r->name = name;
  r->format = format;
  r->size_bytes = bytes.size();
  r->mesh = std::make_shared<const Mesh>(load_mesh_from_bytes(bytes, format, name, limits));
  wire::mesh_info_from_mesh(*r->mesh, &r->info);
  r->memory_bytes = wire::mesh_memory_bytes(*r->mesh);
  return r;
}
}  // namespace

std::shared_ptr<MeshRecord> MeshStore::parse_bounded(const std::string& id, const std::string& name,
                                                     const std::string& format, const std::string& bytes) {
  const auto budget = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(std::min(parse_limits_.budget_seconds, 1e7)));  // no overflow
  {
    std::unique_lock lock(parse_mutex_);
    if (!parse_slot_freed_.wait_for(lock, budget,
                                    [&] { return parses_running_ < parse_limits_.max_concurrent; }))
      throw Error(ErrorCode::resource_exhausted,
                  "mesh " + name + " not parsed: all " + std::to_string(parse_limits_.max_concurrent) +
                      " parse slots (--max-concurrent-parses) stayed busy for the parse budget of " +
                      std::to_string(parse_limits_.budget_seconds) +
                      " s (--parse-timeout-seconds); try again later");
    ++parses_running_;
  }
  struct SlotRelease {
    MeshStore* store;
    ~SlotRelease() {
      {
        std::lock_guard lock(store->parse_mutex_);
        --store->parses_running_;
      }
      store->parse_slot_freed_.notify_one();
    }
  } release{this};
  MeshReadLimits limits;
  limits.deadline = std::chrono::steady_clock::now() + budget;
  try {
    return parse_record(id, name, format, bytes, limits);
  } catch (const Error& e) {
    if (e.code() != ErrorCode::resource_exhausted) throw;
    throw Error(ErrorCode::resource_exhausted, std::string(e.what()) + " (" +
                                                   std::to_string(parse_limits_.budget_seconds) +
                                                   " s, --parse-timeout-seconds)");
  }
}

std::shared_ptr<MeshRecord> MeshStore::insert_locked(std::shared_ptr<Record> record) {
  auto it = records_.find(record->id);
  if (it != records_.end()) {  // someone else inserted it meanwhile
    touch_locked(*it->second);
    return it->second;
  }
  lru_.push_front(record->id);
  record->lru_it = lru_.begin();
  record->in_cache = true;
  bytes_ += record->memory_bytes;
  records_.emplace(record->id, record);
  evict_locked(record->id);
  return record;
}

void MeshStore::drop_stencils_locked() {
  for (auto it = lru_.rbegin(); bytes_ > budget_ && it != lru_.rend(); ++it) {
    Record& r = *records_.at(*it);
    if (r.pins > 0 || !r.stencils) continue;
    const uint64_t freed = r.stencils->memory_bytes();
    r.stencils.reset();
    r.memory_bytes -= freed;
    bytes_ -= freed;
  }
}

void MeshStore::evict_locked(const std::string& keep) {
  drop_stencils_locked();
  auto it = lru_.end();
  while (bytes_ > budget_ && it != lru_.begin()) {
    --it;
    auto rec_it = records_.find(*it);
    Record& r = *rec_it->second;
    if (r.pins > 0 || r.id == keep) continue;
    log_.info("mesh.evicted", {{"mesh", r.id},
                               {"memory_bytes", r.memory_bytes},
                               {"cache_bytes", bytes_},
                               {"budget_bytes", budget_}});
    bytes_ -= r.memory_bytes;
    ++stats_.evictions;
    r.in_cache = false;
    it = lru_.erase(it);
    records_.erase(rec_it);
  }
}

v1::MeshInfo MeshStore::add(const std::string& id, const std::string& name, const std::string& format,
                            const std::string& bytes) {
  if (auto found = find_cached(id)) {
    found->set_already_present(true);
    return *found;
  }
  auto record = parse_bounded(id, name, format, bytes);  // slow part, outside the lock
  store_.put_mesh({id, name, format, bytes.size(), bytes});
  std::lock_guard lock(mutex_);
  auto stored = insert_locked(std::move(record));
  return info_locked(*stored);
}

std::shared_ptr<MeshRecord> MeshStore::load_from_store(const std::string& id) {
  if (!store_.keeps_meshes() || !is_mesh_id(id)) return nullptr;
  auto stored = store_.get_mesh(id);
  if (!stored) return nullptr;
  UploadBudget::Hold memory;
  if (parse_limits_.memory) {
    const auto wait = std::chrono::duration<double>(std::min(parse_limits_.budget_seconds, 1e7));
    memory = parse_limits_.memory->reserve_waiting(
        stored->format, stored->bytes.size(), "reload of mesh " + id,
        std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(wait));
  }
  auto record = parse_bounded(id, stored->name, stored->format, stored->bytes);
  log_.info("mesh.reloaded", {{"mesh", id}, {"store", store_.description()}});
  return record;
}

std::shared_ptr<MeshRecord> MeshStore::lookup_or_load(const std::string& id) {
  std::promise<Loaded> promise;
  {
    std::unique_lock lock(mutex_);
    auto it = records_.find(id);
    if (it != records_.end()) {
      ++stats_.hits;
      touch_locked(*it->second);
      return it->second;
    }
    ++stats_.misses;
    auto loading = loading_.find(id);
    if (loading != loading_.end()) {
      auto pending = loading->second;
      lock.unlock();
      const Loaded& loaded = pending.get();  // another request's parse of the same mesh
      throw_if_error(loaded.status);
      return loaded.record;
    }
    loading_.emplace(id, promise.get_future().share());
  }
  std::shared_ptr<Record> stored;
  try {
    auto record = load_from_store(id);
    if (!record) throw not_found(id);
    std::lock_guard lock(mutex_);
    stored = insert_locked(std::move(record));
    loading_.erase(id);
  } catch (...) {
    {
      std::lock_guard lock(mutex_);
      loading_.erase(id);
    }
    promise.set_value({nullptr, current_exception_status()});
    throw;
  }
  promise.set_value({stored, grpc::Status::OK});
  return stored;
}

v1::MeshInfo MeshStore::get(const std::string& id) {
  auto record = lookup_or_load(id);
  std::lock_guard lock(mutex_);
  return info_locked(*record);
}

v1::ListMeshesResponse MeshStore::list() {
  v1::ListMeshesResponse out;
  std::lock_guard lock(mutex_);
  for (const auto& id : lru_) *out.add_meshes() = info_locked(*records_.at(id));
  for (const auto& m : store_.list_meshes()) {
    if (records_.count(m.id)) continue;
    auto* info = out.add_meshes();
    info->set_id(m.id);
    info->set_name(m.name);
    info->set_format(m.format);
    info->set_size_bytes(m.size_bytes);
    info->set_cached(false);
  }
  out.set_cache_bytes(bytes_);
  out.set_cache_budget_bytes(budget_);
  return out;
}

void MeshStore::remove(const std::string& id) {
  bool found = false;
  {
    std::lock_guard lock(mutex_);
    auto it = records_.find(id);
    if (it != records_.end()) {
      found = true;
      Record& r = *it->second;
      bytes_ -= r.memory_bytes;
      r.in_cache = false;
      lru_.erase(r.lru_it);
      records_.erase(it);
    }
  }
  if (is_mesh_id(id)) found |= store_.delete_mesh(id);
  if (!found) throw not_found(id);
  log_.info("mesh.deleted", {{"mesh", id}});
}

std::shared_ptr<MeshLease> MeshStore::acquire(const std::string& id) {
  auto record = lookup_or_load(id);
  std::lock_guard lock(mutex_);
  ++record->pins;
  return std::shared_ptr<MeshLease>(new MeshLease(this, record));
}

std::shared_ptr<MeshLease> MeshStore::hold_for_queue(const std::string& id) {
  auto record = lookup_or_load(id);
  std::lock_guard lock(mutex_);
  if (record->pins == 0) {
    uint64_t held = 0;
    for (const auto& [other_id, other] : records_) {
      if (other->pins > 0) held += other->memory_bytes;
    }
    if (held + record->memory_bytes > budget_) {
      throw ServiceError(grpc::StatusCode::RESOURCE_EXHAUSTED,
                         "mesh cache budget (--mesh-cache-bytes " + std::to_string(budget_) +
                             ") is taken by the " + std::to_string(held) +
                             " bytes of meshes that queued and running jobs hold; mesh " + id + " needs " +
                             std::to_string(record->memory_bytes) + " more; try again later");
    }
  }
  ++record->pins;
  return std::shared_ptr<MeshLease>(new MeshLease(this, record));
}

void MeshStore::release(const std::shared_ptr<Record>& record) {
  std::lock_guard lock(mutex_);
  --record->pins;
  // A mesh kept over budget only because a job held it may go now.
  if (record->pins == 0 && bytes_ > budget_) evict_locked("");
}

std::shared_ptr<const FastMarchingStencils> MeshStore::stencils_of(Record& record) {
  std::lock_guard build(record.stencil_build);
  {
    std::lock_guard lock(mutex_);
    if (record.stencils) return record.stencils;
  }
  auto built = std::make_shared<const FastMarchingStencils>(*record.mesh);  // slow part, outside the lock
  std::lock_guard lock(mutex_);
  record.stencils = built;
  ++stats_.stencil_builds;
  const uint64_t extra = built->memory_bytes();
  record.memory_bytes += extra;
  if (record.in_cache) {  // an evicted record (kept by its jobs) is no longer counted
    bytes_ += extra;
    // Derived data makes room only by dropping other derived data: a mesh (in a memory
    // store, the only copy of an upload) is never evicted to hold stencils. Over budget
    // while jobs hold these, as with meshes held by jobs.
    drop_stencils_locked();
  }
  return built;
}

uint64_t MeshStore::cached_bytes() {
  std::lock_guard lock(mutex_);
  return bytes_;
}

MeshCacheStats MeshStore::cache_stats() {
  std::lock_guard lock(mutex_);
  MeshCacheStats s = stats_;
  s.bytes = bytes_;
  s.meshes = records_.size();
  return s;
}

}  // namespace depath::service
