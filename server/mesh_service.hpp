// SPDX-License-Identifier: MIT
// depath.v1.MeshService on gRPC's callback API.
#pragma once

#include "depath/v1/mesh.grpc.pb.h"
#include "service_context.hpp"

namespace depath::service {

class MeshServiceImpl final : public v1::MeshService::CallbackService {
 public:
  explicit MeshServiceImpl(ServiceContext& ctx) : ctx_(ctx) {}

  grpc::ServerReadReactor<v1::UploadMeshRequest>* UploadMesh(grpc::CallbackServerContext* context,
                                                              v1::MeshInfo* reply) override;
  grpc::ServerUnaryReactor* GetMesh(grpc::CallbackServerContext* context, const v1::GetMeshRequest* request,
                                    v1::MeshInfo* reply) override;
  grpc::ServerUnaryReactor* ListMeshes(grpc::CallbackServerContext* context, const v1::ListMeshesRequest* request,
                                       v1::ListMeshesResponse* reply) override;
  grpc::ServerUnaryReactor* DeleteMesh(grpc::CallbackServerContext* context, const v1::DeleteMeshRequest* request,
                                       v1::DeleteMeshResponse* reply) override;

 private:
  ServiceContext& ctx_;
};

}  // namespace depath::service
