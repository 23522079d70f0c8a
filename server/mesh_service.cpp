// SPDX-License-Identifier: MIT
#include "mesh_service.hpp"

#include "depath/util/error.hpp"
#include "depath/wire/wire.hpp"
#include "grpc_handoff.hpp"
#include "mesh_upload.hpp"
#include "service_error.hpp"
#include "unary_call.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <mutex>

namespace depath::service {

namespace {

/// Reads the header and chunks, hashing and buffering them; then parses on the blocking
/// queue (not on a gRPC thread) and finishes with the mesh's info. grpc_handoff /
/// grpc_reaction (grpc_handoff.hpp) show TSan gRPC's own ordering of the reactions.
class UploadReactor final : public grpc::ServerReadReactor<v1::UploadMeshRequest> {
 public:
  UploadReactor(ServiceContext& ctx, grpc::CallbackServerContext* context, v1::MeshInfo* reply)
      : ctx_(ctx), reply_(reply), peer_(context->peer()) {
    grpc::Status s = ctx_.admit(context, "UploadMesh");
    if (s.ok()) s = take_upload_slot();
    if (s.ok()) StartRead(&request_);
    else Finish(s);
    grpc_handoff(this);  // gRPC starts those operations once the handler has returned
  }

  void OnReadDone(bool ok) override {
    grpc_reaction(this);
    if (!ok) {  // client finished sending (or went away)
      complete();
      return;
    }
    if (request_.has_header()) {
      if (have_header_) return fail({grpc::StatusCode::INVALID_ARGUMENT, "upload has a second header"});
      have_header_ = true;
      const auto& h = request_.header();
      name_ = h.file_name().empty() ? "upload" : h.file_name();
      try {
        format_ = upload_format(name_, h.format());
      } catch (const ServiceError& e) {
        return fail({e.code(), e.what()});
      }
      if (h.size_bytes() > ctx_.options.max_upload_bytes) return fail(too_big(h.size_bytes()));
      memory_ = ctx_.upload_memory.hold(format_);
      if (grpc::Status s = memory_.cover(h.size_bytes()); !s.ok()) return fail(s);  // the declared size, at once
      if (h.size_bytes() > 0) bytes_.reserve(h.size_bytes());
    } else if (request_.part_case() == v1::UploadMeshRequest::kChunk) {
      if (!have_header_) {
        return fail({grpc::StatusCode::INVALID_ARGUMENT, "upload must start with a header (file name and format)"});
      }
      const std::string& chunk = request_.chunk();
      if (bytes_.size() + chunk.size() > ctx_.options.max_upload_bytes) {
        return fail(too_big(bytes_.size() + chunk.size()));
      }
      if (grpc::Status s = memory_.cover(bytes_.size() + chunk.size()); !s.ok()) return fail(s);
      bytes_.append(chunk);
    }
    grpc_handoff(this);
    StartRead(&request_);
  }

  void OnDone() override {
    grpc_reaction(this);
    release_upload_slot();
    delete this;
  }

 private:
  /// One of --max-concurrent-uploads, held until the stream is done (its bytes are freed).
  grpc::Status take_upload_slot() {
    const int limit = ctx_.options.max_concurrent_uploads;
    if (ctx_.uploads.fetch_add(1) >= limit) {
      ctx_.uploads.fetch_sub(1);
      return {grpc::StatusCode::RESOURCE_EXHAUSTED,
              std::to_string(limit) + " mesh uploads are already in flight, the server's limit "
              "(--max-concurrent-uploads); try again shortly"};
    }
    holds_slot_ = true;
    return grpc::Status::OK;
  }

  /// Before Finish (the client may start its next upload as soon as it has the answer), or at
  /// OnDone for a stream that ended otherwise. Once.
  void release_upload_slot() {
    if (holds_slot_.exchange(false)) ctx_.uploads.fetch_sub(1);
  }

  grpc::Status too_big(uint64_t n) const { return upload_too_big(ctx_.options, n); }

  void fail(const grpc::Status& s) {
    ctx_.log.info("mesh.upload_refused", {{"peer", peer_}, {"code", wire::status_code_name(s.error_code())},
                                          {"reason", s.error_message()}});
    std::string().swap(bytes_);  // no parse runs: the bytes and their room go now
    memory_.reset();
    release_upload_slot();
    grpc_handoff(this);
    Finish(s);
  }

  void complete() {
    if (!have_header_) return fail({grpc::StatusCode::INVALID_ARGUMENT, "upload must start with a header (file name and format)"});
    if (bytes_.empty()) return fail({grpc::StatusCode::INVALID_ARGUMENT, "upload of '" + name_ + "' has no bytes"});
    ctx_.blocking.post([this] {
      grpc::Status status;
      try {
        *reply_ = store_upload(ctx_, name_, format_, bytes_, "grpc", peer_);
      } catch (...) {
        status = current_exception_status();
      }
      std::string().swap(bytes_);
      memory_.reset();
      release_upload_slot();
      finish_from_our_thread(*this, status);
    });
  }

  ServiceContext& ctx_;
  v1::MeshInfo* reply_;
  std::string peer_;
  v1::UploadMeshRequest request_;
  bool have_header_ = false;
  std::atomic<bool> holds_slot_{false};
  std::string name_, format_, bytes_;
  UploadBudget::Hold memory_;  ///< room of bytes_ and their parse (--max-upload-memory-bytes)
};

}  // namespace

grpc::ServerReadReactor<v1::UploadMeshRequest>* MeshServiceImpl::UploadMesh(grpc::CallbackServerContext* context,
                                                                            v1::MeshInfo* reply) {
  return new UploadReactor(ctx_, context, reply);
}

grpc::ServerUnaryReactor* MeshServiceImpl::GetMesh(grpc::CallbackServerContext* context,
                                                   const v1::GetMeshRequest* request, v1::MeshInfo* reply) {
  auto body = [this, request, reply] { *reply = ctx_.meshes.get(request->id()); };
  // A reload (a mesh evicted, or stored before a restart) is parsed off gRPC's threads.
  if (ctx_.meshes.must_reload(request->id())) return unary_blocking(ctx_, context, "GetMesh", false, std::move(body));
  return unary(ctx_, context, "GetMesh", false, body);
}

grpc::ServerUnaryReactor* MeshServiceImpl::ListMeshes(grpc::CallbackServerContext* context,
                                                      const v1::ListMeshesRequest*, v1::ListMeshesResponse* reply) {
  return unary(ctx_, context, "ListMeshes", false, [&] { *reply = ctx_.meshes.list(); });
}

grpc::ServerUnaryReactor* MeshServiceImpl::DeleteMesh(grpc::CallbackServerContext* context,
                                                      const v1::DeleteMeshRequest* request, v1::DeleteMeshResponse*) {
  return unary(ctx_, context, "DeleteMesh", false, [&] { ctx_.meshes.remove(request->id()); });
}

}  // namespace depath::service
