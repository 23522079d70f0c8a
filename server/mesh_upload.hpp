// SPDX-License-Identifier: MIT
// The steps of a mesh upload shared by gRPC's UploadMesh and HTTP's POST /v1/meshes: the
// format check, the size limit and the storing itself (hash, bounded parse, store, log,
// metrics), so that both transports accept and refuse exactly the same files.
#pragma once

#include "service_context.hpp"

#include "depath/v1/mesh.pb.h"

#include <grpcpp/support/status.h>

#include <cstdint>
#include <string>

namespace depath::service {

/// The upload's format: `format` when given, else the extension of `name`; lower-cased.
/// Throws ServiceError(INVALID_ARGUMENT) unless it is obj, off, ply or stl.
std::string upload_format(const std::string& name, const std::string& format);

/// RESOURCE_EXHAUSTED naming --max-upload-bytes, for an upload of `bytes` (or more).
grpc::Status upload_too_big(const ServerOptions& options, uint64_t bytes);

/// Stores a complete upload: refuses it when empty or over the limit, else hashes it (the
/// mesh id), parses it within the parse limits (MeshStore::add), logs and counts it under
/// `transport`. Slow: call it on ctx.blocking. Throws like MeshStore::add / ServiceError.
v1::MeshInfo store_upload(ServiceContext& ctx, const std::string& name, const std::string& format,
                          const std::string& bytes, const std::string& transport, const std::string& peer);

}  // namespace depath::service
