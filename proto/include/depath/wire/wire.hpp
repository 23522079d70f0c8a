// Conversions between the core's types and the depath.v1 protobuf messages, shared by the
// server (depathd) and the network client (depath upload/submit/run/...).
#pragma once

#include "depath/v1/job.pb.h"
#include "depath/v1/mesh.pb.h"

#include "depath/util/error.hpp"
#include "depath/solve/job.hpp"
#include "depath/mesh/mesh.hpp"
#include "depath/solve/solve.hpp"

#include <grpcpp/support/status.h>
#include <nlohmann/json.hpp>
#include <openssl/evp.h>

#include <memory>
#include <string>
#include <string_view>

namespace depath::wire {

namespace v1 = ::depath::v1;

// ---- jobs -------------------------------------------------------------------------------

/// The core's job from its message. Throws Error(invalid_argument) for enum values this
/// build does not know. Range checks are left to depath::validate_job.
JobSpec job_from_proto(const v1::JobSpec& spec);
/// The message of a core job on mesh `mesh_id` (every DE option is set explicitly).
v1::JobSpec job_to_proto(const JobSpec& job, const std::string& mesh_id);

const char* state_name(v1::JobState state);  ///< "queued", "running", ...
bool is_terminal(v1::JobState state);

// ---- paths and results --------------------------------------------------------------------

/// Fills `out` with the path's points, crossings, faces and the positions of every vertex
/// the crossings refer to.
void path_to_proto(const Mesh& mesh, const SurfacePath& path, v1::Path* out);
/// The path's crossings and faces (positions come from the mesh the caller holds).
SurfacePath path_from_proto(const v1::Path& path);

void result_to_proto(const Mesh& mesh, const SolveResult& result, v1::JobResult* out);
/// Everything but the mesh: pair it with the job's mesh (or with path_mesh()).
SolveResult result_from_proto(const v1::JobResult& result);
void progress_to_proto(const Mesh& mesh, const Progress& progress, v1::Progress* out);

/// A stand-in mesh for writing a result when the mesh file is not at hand: it has the
/// path's vertices at their true ids and positions (from Path.vertices), so that
/// depath::write_result / result_to_json give the same points and crossings as with the
/// real mesh. Only good for writing that path.
Mesh path_mesh(const v1::Path& path);

/// Writes a result received from a server like `depath solve --out` does (format by the
/// extension), through depath::write_result. With `mesh` null, uses path_mesh().
void write_result_message(const std::string& out_path, const v1::JobResult& result, const Mesh* mesh);
/// result_to_json for a received result (same rule for `mesh`).
nlohmann::json result_message_to_json(const v1::JobResult& result, const Mesh* mesh);

// ---- status codes ---------------------------------------------------------------------------

grpc::StatusCode status_code(ErrorCode code);
inline grpc::Status to_status(const Error& e) { return {status_code(e.code()), e.what()}; }
/// Short name of a status code ("NOT_FOUND", ...).
const char* status_code_name(grpc::StatusCode code);

// ---- mesh ids -----------------------------------------------------------------------------

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

/// Fills a MeshInfo's counts, bounding box and warnings from a parsed mesh.
void mesh_info_from_mesh(const Mesh& mesh, v1::MeshInfo* out);
/// Approximate bytes a parsed mesh occupies in memory.
uint64_t mesh_memory_bytes(const Mesh& mesh);

}  // namespace depath::wire
