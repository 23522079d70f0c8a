// SPDX-License-Identifier: MIT
#include "mesh_upload.hpp"

#include "depath/io/mesh_reader.hpp"
#include "depath/wire/wire.hpp"
#include "service_error.hpp"

#include <algorithm>
#include <cctype>

namespace depath::service {

std::string upload_format(const std::string& name, const std::string& format) {
  std::string f;
  try {
    f = format.empty() ? mesh_format_from_path(name) : format;
  } catch (const std::exception& e) {
    throw ServiceError(grpc::StatusCode::INVALID_ARGUMENT,
                       std::string(e.what()) + " (set the header's format to obj, off, ply or stl)");
  }
  std::transform(f.begin(), f.end(), f.begin(), [](unsigned char c) { return std::tolower(c); });
  if (f != "obj" && f != "off" && f != "ply" && f != "stl") {
    throw ServiceError(grpc::StatusCode::INVALID_ARGUMENT,
                       "unknown mesh format '" + format + "' (expected obj, off, ply or stl)");
  }
  return f;
}

grpc::Status upload_too_big(const ServerOptions& options, uint64_t bytes) {
  return {grpc::StatusCode::RESOURCE_EXHAUSTED,
          "mesh upload of " + std::to_string(bytes) + " bytes (or more) exceeds the server's limit of " +
              std::to_string(options.max_upload_bytes) + " bytes (--max-upload-bytes)"};
}

v1::MeshInfo store_upload(ServiceContext& ctx, const std::string& name, const std::string& format,
                          const std::string& bytes, const std::string& transport, const std::string& peer) {
  try {
    if (bytes.empty())
      throw ServiceError(grpc::StatusCode::INVALID_ARGUMENT, "upload of '" + name + "' has no bytes");
    if (bytes.size() > ctx.options.max_upload_bytes) throw_if_error(upload_too_big(ctx.options, bytes.size()));
    ctx.metrics.upload(bytes.size(), transport);
    const std::string id = wire::sha256_hex(bytes);
    v1::MeshInfo info = ctx.meshes.add(id, name, format, bytes);
    ctx.log.info("mesh.uploaded", {{"mesh", id},
                                   {"name", name},
                                   {"bytes", bytes.size()},
                                   {"vertices", info.num_vertices()},
                                   {"faces", info.num_faces()},
                                   {"already_present", info.already_present()},
                                   {"transport", transport}});
    return info;
  } catch (...) {
    const grpc::Status status = current_exception_status();
    ctx.log.info("mesh.upload_refused", {{"peer", peer}, {"name", name}, {"transport", transport},
                                         {"code", wire::status_code_name(status.error_code())},
                                         {"reason", status.error_message()}});
    throw;
  }
}

}  // namespace depath::service
