// SPDX-License-Identifier: MIT
#include "upload_budget.hpp"

#include <limits>

#include "service_error.hpp"

namespace depath::service {

// Peak growth of the resident memory while depath parses a mesh already in memory
// (load_mesh_from_bytes plus its MeshInfo, as MeshStore does), per byte of the file. Measured
// with bench/parse_memory (one parse per process, VmHWM) on the meshes of /work/shared/data
// (armadillo, bunny, bimba, camelhead: 11k-43k vertices) converted to each format by the
// writers of depath, and on a 1.44M-vertex grid (151 MB as OBJ):
//   OBJ / OFF / ascii PLY  4.9 - 5.7   (17-digit coordinates, as `depath generate` writes)
//   binary PLY (float64)   10.3 - 10.8
//   binary STL             5.2 - 5.4
// The growth is about 515 bytes per vertex whatever the format: denser files grow more per byte.
// Compact hostile files, which the estimate does not cover, measured 10.6 (OBJ with integer
// coordinates), 10.9 (OFF, the same), 19.9 (binary PLY, float32 + uint16 indices) and 32.4
// (binary PLY triangle strips): those may exceed their estimate by up to 3x, still a bound.
uint64_t UploadBudget::parse_ratio(const std::string& format) {
  if (format == "ply") return 11;  // binary PLY is the densest real format; ascii PLY is over-estimated 2x
  return 6;                        // obj, off, stl
}

uint64_t UploadBudget::estimate(uint64_t file_bytes, const std::string& format) {
  const uint64_t factor = 1 + parse_ratio(format);
  if (file_bytes > std::numeric_limits<uint64_t>::max() / factor) return std::numeric_limits<uint64_t>::max();
  return file_bytes * factor;
}

UploadBudget::Hold& UploadBudget::Hold::operator=(Hold&& other) noexcept {
  if (this != &other) {
    reset();
    budget_ = other.budget_;
    format_ = std::move(other.format_);
    what_ = std::move(other.what_);
    held_ = other.held_;
    other.held_ = 0;
  }
  return *this;
}

grpc::Status UploadBudget::Hold::cover(uint64_t file_bytes) {
  if (!budget_) return grpc::Status::OK;  // an empty default Hold: no budget to account against
  const uint64_t need = estimate(file_bytes, format_);
  if (need <= held_) return grpc::Status::OK;
  if (!budget_->take(need, held_)) return budget_->refusal(*this, file_bytes, need);
  held_ = need;
  return grpc::Status::OK;
}

void UploadBudget::Hold::reset() {
  if (budget_ && held_ > 0) budget_->give_back(held_);
  held_ = 0;
}

bool UploadBudget::take(uint64_t need, uint64_t held) {
  if (need > budget_) return false;
  std::lock_guard lock(mutex_);
  if (held_ - held + need > budget_) return false;
  held_ += need - held;
  return true;
}

// Built only when refusing: cover() runs for every chunk of an upload.
grpc::Status UploadBudget::refusal(const Hold& hold, uint64_t file_bytes, uint64_t need) {
  const std::string figures = hold.what_ + " of " + std::to_string(file_bytes) + " bytes (" + hold.format_ +
                              ") needs an estimated " + std::to_string(need) +
                              " bytes of memory to receive and parse (the file's bytes x " +
                              std::to_string(1 + parse_ratio(hold.format_)) + ")";
  if (need > budget_) {
    return {grpc::StatusCode::RESOURCE_EXHAUSTED, figures + ", more than the server's whole budget of " +
                                                      std::to_string(budget_) +
                                                      " bytes (--max-upload-memory-bytes): it cannot be "
                                                      "accepted; send a smaller mesh or raise the flag"};
  }
  return {grpc::StatusCode::RESOURCE_EXHAUSTED, figures + "; uploads and parses in flight hold " +
                                                    std::to_string(held_bytes() - hold.held_) + " of the " +
                                                    std::to_string(budget_) +
                                                    " bytes (--max-upload-memory-bytes); try again shortly"};
}

void UploadBudget::give_back(uint64_t bytes) {
  {
    std::lock_guard lock(mutex_);
    held_ -= bytes;
  }
  freed_.notify_all();
}

UploadBudget::Hold UploadBudget::reserve_waiting(const std::string& format, uint64_t file_bytes,
                                                 const std::string& what,
                                                 std::chrono::steady_clock::time_point deadline) {
  Hold h = hold(format, what);
  const uint64_t need = estimate(file_bytes, format);
  for (;;) {
    const grpc::Status s = h.cover(file_bytes);
    if (s.ok()) return h;
    if (need > budget_ || std::chrono::steady_clock::now() >= deadline) throw_if_error(s);
    std::unique_lock lock(mutex_);
    freed_.wait_until(lock, deadline, [&] { return held_ + need <= budget_; });
  }
}

uint64_t UploadBudget::held_bytes() {
  std::lock_guard lock(mutex_);
  return held_;
}

}  // namespace depath::service
