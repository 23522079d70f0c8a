// SPDX-License-Identifier: MIT
#include "mesh_service.hpp"

#include "depath/util/error.hpp"
#include "depath/wire/wire.hpp"
#include "grpc_handoff.hpp"
#include "mesh_upload.hpp"
#include "service_error.hpp"
#include "unary_call.hpp"

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
    grpc::Status s = ctx_.admit(context);
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
      if (h.size_bytes() > 0) bytes_.reserve(h.size_bytes());
    } else if (request_.part_case() == v1::UploadMeshRequest::kChunk) {
      if (!have_header_) {
        return fail({grpc::StatusCode::INVALID_ARGUMENT, "upload must start with a header (file name and format)"});
      }
      const std::string& chunk = request_.chunk();
      if (bytes_.size() + chunk.size() > ctx_.options.max_upload_bytes) {
        return fail(too_big(bytes_.size() + chunk.size()));
      }
      bytes_.append(chunk);
    }
    grpc_handoff(this);
    StartRead(&request_);
  }

  void OnDone() override {
    grpc_reaction(this);
    delete this;
  }

 private:
  grpc::Status too_big(uint64_t n) const { return upload_too_big(ctx_.options, n); }

  void fail(const grpc::Status& s) {
    ctx_.log.info("mesh.upload_refused", {{"peer", peer_}, {"code", wire::status_code_name(s.error_code())},
                                          {"reason", s.error_message()}});
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
      grpc_handoff(this);
      Finish(status);
    });
  }

  ServiceContext& ctx_;
  v1::MeshInfo* reply_;
  std::string peer_;
  v1::UploadMeshRequest request_;
  bool have_header_ = false;
  std::string name_, format_, bytes_;
};

}  // namespace

grpc::ServerReadReactor<v1::UploadMeshRequest>* MeshServiceImpl::UploadMesh(grpc::CallbackServerContext* context,
                                                                            v1::MeshInfo* reply) {
  return new UploadReactor(ctx_, context, reply);
}

grpc::ServerUnaryReactor* MeshServiceImpl::GetMesh(grpc::CallbackServerContext* context,
                                                   const v1::GetMeshRequest* request, v1::MeshInfo* reply) {
  return unary(ctx_, context, false, [&] { *reply = ctx_.meshes.get(request->id()); });
}

grpc::ServerUnaryReactor* MeshServiceImpl::ListMeshes(grpc::CallbackServerContext* context,
                                                      const v1::ListMeshesRequest*, v1::ListMeshesResponse* reply) {
  return unary(ctx_, context, false, [&] { *reply = ctx_.meshes.list(); });
}

grpc::ServerUnaryReactor* MeshServiceImpl::DeleteMesh(grpc::CallbackServerContext* context,
                                                      const v1::DeleteMeshRequest* request, v1::DeleteMeshResponse*) {
  return unary(ctx_, context, false, [&] { ctx_.meshes.remove(request->id()); });
}

}  // namespace depath::service
