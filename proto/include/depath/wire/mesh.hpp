// SPDX-License-Identifier: MIT
// Meshes on the wire: mesh ids (SHA-256 of the file's bytes) and depath.v1.MeshInfo.
//
// Guarantees: the id of a file is the lowercase hex SHA-256 of its bytes, computed the same
// way by the server (on upload) and the client (to skip an upload the server already has);
// is_mesh_id is the one check of that form, shared by both.
#pragma once

#include "depath/mesh/mesh.hpp"
#include "depath/v1/mesh.pb.h"

#include <openssl/evp.h>

#include <cstdint>
#include <string>
#include <string_view>

namespace depath::wire {

namespace v1 = ::depath::v1;

/// Incremental SHA-256 (OpenSSL); hex() gives the lowercase hex digest, the mesh id.
class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;
  void update(std::string_view bytes);
  std::string hex();  ///< finishes the digest; call once

 private:
  EVP_MD_CTX* ctx_;
};
std::string sha256_hex(std::string_view bytes);

/// True for a 64-character lowercase hex string (the form of a mesh id).
bool is_mesh_id(std::string_view id);

/// Fills a MeshInfo's counts, bounding box and warnings from a parsed mesh.
void mesh_info_from_mesh(const Mesh& mesh, v1::MeshInfo* out);
/// Approximate bytes a parsed mesh occupies in memory.
uint64_t mesh_memory_bytes(const Mesh& mesh);

}  // namespace depath::wire
