// SPDX-License-Identifier: MIT
#include "depath/wire/mesh.hpp"

#include "depath/util/error.hpp"
#include "vec.hpp"

namespace depath::wire {

Sha256::Sha256() : ctx_(EVP_MD_CTX_new()) {
  if (!ctx_ || EVP_DigestInit_ex(ctx_, EVP_sha256(), nullptr) != 1) {
    throw Error(ErrorCode::internal, "cannot initialise SHA-256 (OpenSSL)");
  }
}
Sha256::~Sha256() { EVP_MD_CTX_free(ctx_); }
void Sha256::update(std::string_view bytes) {
  if (EVP_DigestUpdate(ctx_, bytes.data(), bytes.size()) != 1) throw Error(ErrorCode::internal, "SHA-256 update failed");
}
std::string Sha256::hex() {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  if (EVP_DigestFinal_ex(ctx_, digest, &len) != 1) throw Error(ErrorCode::internal, "SHA-256 final failed");
  static const char* hexdigits = "0123456789abcdef";
  std::string out;
  out.reserve(len * 2);
  for (unsigned i = 0; i < len; ++i) {
    out.push_back(hexdigits[digest[i] >> 4]);
    out.push_back(hexdigits[digest[i] & 15]);
  }
  return out;
}
std::string sha256_hex(std::string_view bytes) {
  Sha256 h;
  h.update(bytes);
  return h.hex();
}

bool is_mesh_id(std::string_view id) {
  if (id.size() != 64) return false;
  for (char c : id) {
    if (!((c >= '0' && c <= '9') || (c >= 'a' && c <= 'f'))) return false;
  }
  return true;
}

void mesh_info_from_mesh(const Mesh& mesh, v1::MeshInfo* out) {
  out->set_num_vertices(mesh.num_vertices());
  out->set_num_faces(mesh.num_faces());
  out->set_num_boundary_edges(mesh.num_boundary_edges());
  out->set_num_components(mesh.num_components());
  set_vec(mesh.bounding_box().min, out->mutable_bounding_box()->mutable_min());
  set_vec(mesh.bounding_box().max, out->mutable_bounding_box()->mutable_max());
  out->mutable_warnings()->Clear();
  for (const auto& w : mesh.warnings()) out->add_warnings(w);
  out->set_memory_bytes(mesh_memory_bytes(mesh));
}

uint64_t mesh_memory_bytes(const Mesh& mesh) {
  // Per vertex: position 24, CSR offsets 8, component 4, ~6 faces + ~6 neighbours 48.
  // Per face: indices 12, neighbours 12, edge lengths 24, angles 24, layout 24, normal 24,
  // area 8.
  const uint64_t v = static_cast<uint64_t>(mesh.num_vertices());
  const uint64_t f = static_cast<uint64_t>(mesh.num_faces());
  return 512 + v * 84 + f * 128;
}

}  // namespace depath::wire
