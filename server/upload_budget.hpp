// SPDX-License-Identifier: MIT
// The memory that mesh uploads being received and mesh parses in flight may hold together
// (depathd --max-upload-memory-bytes). gRPC's UploadMesh, HTTP's POST /v1/meshes and the
// reloads of stored meshes take their room here, estimated from the file's byte count.
//
// Inputs: the budget; per upload or reload its format and (growing) byte count.
// Outputs: a Hold on the estimated memory, or RESOURCE_EXHAUSTED naming the flag and the figures.
// Guarantees: the holds together never exceed the budget; a Hold gives its room back when it
// is reset or destroyed, whatever ended the upload. An upload is refused at once rather than
// waiting (it holds a transport stream meanwhile, and two half-received uploads each waiting
// for the other's room would stall both): the client tries again. Only reloads, which hold no
// room while they wait, wait (up to a deadline) for it.
#pragma once

#include <grpcpp/support/status.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>

namespace depath::service {

class UploadBudget {
 public:
  explicit UploadBudget(uint64_t budget_bytes) : budget_(budget_bytes) {}

  /// Estimated peak memory of receiving and parsing a `file_bytes`-byte mesh of `format`: the
  /// file's bytes plus the parse's growth, file_bytes x (1 + parse_ratio(format)). Saturates.
  static uint64_t estimate(uint64_t file_bytes, const std::string& format);
  /// The parse's peak growth per file byte (measured figures in upload_budget.cpp).
  static uint64_t parse_ratio(const std::string& format);

  /// Room for one upload or reload; empty (holding nothing) until cover() succeeds.
  class Hold {
   public:
    Hold() = default;
    Hold(Hold&& other) noexcept { *this = std::move(other); }
    Hold& operator=(Hold&& other) noexcept;
    ~Hold() { reset(); }
    /// Grows the room to estimate(file_bytes) if it holds less, without waiting: OK, or
    /// RESOURCE_EXHAUSTED (the room held is then unchanged). Never shrinks.
    grpc::Status cover(uint64_t file_bytes);
    /// Gives the room back.
    void reset();
    uint64_t held_bytes() const { return held_; }

   private:
    friend class UploadBudget;
    Hold(UploadBudget* budget, std::string format, std::string what)
        : budget_(budget), format_(std::move(format)), what_(std::move(what)) {}
    UploadBudget* budget_ = nullptr;
    std::string format_, what_;
    uint64_t held_ = 0;
  };

  /// An empty hold for a mesh of `format`; `what` ("mesh upload", "reload of mesh ID") names it
  /// in refusals.
  Hold hold(const std::string& format, const std::string& what = "mesh upload") {
    return Hold(this, format, what);
  }

  /// A hold covering a `file_bytes`-byte mesh, waiting until `deadline` for room: throws
  /// ServiceError(RESOURCE_EXHAUSTED) at once when it exceeds the whole budget, else at the deadline.
  Hold reserve_waiting(const std::string& format, uint64_t file_bytes, const std::string& what,
                       std::chrono::steady_clock::time_point deadline);

  uint64_t budget_bytes() const { return budget_; }
  /// The room held now by all holds.
  uint64_t held_bytes();

 private:
  /// Grows a hold of `held` bytes to `need` if the budget has room; false if not.
  bool take(uint64_t need, uint64_t held);
  /// The RESOURCE_EXHAUSTED a hold gets when take() refuses it, with the figures.
  grpc::Status refusal(const Hold& hold, uint64_t file_bytes, uint64_t need);
  void give_back(uint64_t bytes);

  const uint64_t budget_;
  std::mutex mutex_;
  std::condition_variable freed_;
  uint64_t held_ = 0;
};

}  // namespace depath::service
