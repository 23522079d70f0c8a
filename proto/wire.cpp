#include "depath/wire/wire.hpp"

#include "depath/io/result_writer.hpp"
#include "depath/mesh/surface_path.hpp"

#include <algorithm>
#include <map>
#include <stdexcept>

namespace depath::wire {

namespace {

void set_vec(const Vec3& v, v1::Vec3* out) {
  out->set_x(v.x());
  out->set_y(v.y());
  out->set_z(v.z());
}
Vec3 get_vec(const v1::Vec3& v) { return {v.x(), v.y(), v.z()}; }

v1::Method method_to_proto(Method m) {
  switch (m) {
    case Method::de: return v1::METHOD_DE;
    case Method::fmm: return v1::METHOD_FMM;
    case Method::descent: return v1::METHOD_DESCENT;
  }
  return v1::METHOD_UNSPECIFIED;
}

Method method_from_proto(int m) {
  switch (m) {
    case v1::METHOD_UNSPECIFIED:
    case v1::METHOD_DE: return Method::de;
    case v1::METHOD_FMM: return Method::fmm;
    case v1::METHOD_DESCENT: return Method::descent;
    default: throw Error(ErrorCode::invalid_argument, "unknown method value " + std::to_string(m));
  }
}

}  // namespace

JobSpec job_from_proto(const v1::JobSpec& spec) {
  JobSpec job;
  job.source = spec.source();
  job.target = spec.target();
  const auto& e = spec.energy();
  switch (e.kind()) {
    case v1::ENERGY_KIND_UNSPECIFIED:
    case v1::ENERGY_KIND_GEODESIC: job.energy.kind = EnergyKind::geodesic; break;
    case v1::ENERGY_KIND_VECTOR_FIELD: job.energy.kind = EnergyKind::vector_field; break;
    case v1::ENERGY_KIND_CONSTANT_SLOPE: job.energy.kind = EnergyKind::constant_slope; break;
    default: throw Error(ErrorCode::invalid_argument, "unknown energy kind value " + std::to_string(e.kind()));
  }
  job.energy.density.assign(e.density().begin(), e.density().end());
  job.energy.field.reserve(e.field_size());
  for (const auto& v : e.field()) job.energy.field.push_back(get_vec(v));
  job.energy.field_from_height = e.field_from_height();
  job.energy.rotate_degrees = e.rotate_degrees();
  job.energy.slope = e.slope();
  switch (e.up()) {
    case v1::AXIS_X: job.energy.up_axis = 0; break;
    case v1::AXIS_Y: job.energy.up_axis = 1; break;
    case v1::AXIS_UNSPECIFIED:
    case v1::AXIS_Z: job.energy.up_axis = 2; break;
    default: throw Error(ErrorCode::invalid_argument, "unknown up axis value " + std::to_string(e.up()));
  }
  job.energy.smoothness = e.smoothness();
  job.method = method_from_proto(spec.method());
  job.refine = spec.refine();
  const auto& de = spec.de();
  if (de.has_population()) job.de.population = de.population();
  if (de.has_generations()) job.de.generations = de.generations();
  if (de.has_stall()) job.de.stall = de.stall();
  if (de.has_f()) job.de.F = de.f();
  if (de.has_cr()) job.de.CR = de.cr();
  if (de.has_strategy()) job.de.strategy = de.strategy();
  job.de.seed_with_problem = de.seed_with_problem();
  if (spec.has_seed()) job.seed = spec.seed();
  if (spec.path_every() < 0) {
    throw Error(ErrorCode::invalid_argument,
                "path_every must be >= 0 (got " + std::to_string(spec.path_every()) + ")");
  }
  job.path_every = spec.path_every();
  return job;
}

v1::JobSpec job_to_proto(const JobSpec& job, const std::string& mesh_id) {
  v1::JobSpec spec;
  spec.set_mesh_id(mesh_id);
  spec.set_source(job.source);
  spec.set_target(job.target);
  auto* e = spec.mutable_energy();
  switch (job.energy.kind) {
    case EnergyKind::geodesic: e->set_kind(v1::ENERGY_KIND_GEODESIC); break;
    case EnergyKind::vector_field: e->set_kind(v1::ENERGY_KIND_VECTOR_FIELD); break;
    case EnergyKind::constant_slope: e->set_kind(v1::ENERGY_KIND_CONSTANT_SLOPE); break;
  }
  e->mutable_density()->Add(job.energy.density.begin(), job.energy.density.end());
  for (const auto& v : job.energy.field) set_vec(v, e->add_field());
  e->set_field_from_height(job.energy.field_from_height);
  e->set_rotate_degrees(job.energy.rotate_degrees);
  e->set_slope(job.energy.slope);
  e->set_up(job.energy.up_axis == 0 ? v1::AXIS_X : job.energy.up_axis == 1 ? v1::AXIS_Y : v1::AXIS_Z);
  e->set_smoothness(job.energy.smoothness);
  spec.set_method(method_to_proto(job.method));
  spec.set_refine(job.refine);
  auto* de = spec.mutable_de();
  de->set_population(job.de.population);
  de->set_generations(job.de.generations);
  de->set_stall(job.de.stall);
  de->set_f(job.de.F);
  de->set_cr(job.de.CR);
  de->set_strategy(job.de.strategy);
  de->set_seed_with_problem(job.de.seed_with_problem);
  spec.set_seed(job.seed);
  spec.set_path_every(job.path_every);
  return spec;
}

const char* state_name(v1::JobState state) {
  switch (state) {
    case v1::JOB_STATE_QUEUED: return "queued";
    case v1::JOB_STATE_RUNNING: return "running";
    case v1::JOB_STATE_SUCCEEDED: return "succeeded";
    case v1::JOB_STATE_FAILED: return "failed";
    case v1::JOB_STATE_CANCELLED: return "cancelled";
    default: return "unspecified";
  }
}

bool is_terminal(v1::JobState state) {
  return state == v1::JOB_STATE_SUCCEEDED || state == v1::JOB_STATE_FAILED || state == v1::JOB_STATE_CANCELLED;
}

void path_to_proto(const Mesh& mesh, const SurfacePath& path, v1::Path* out) {
  out->Clear();
  std::vector<int> ids;
  ids.reserve(path.points.size() * 2);
  for (const auto& p : path.points) {
    set_vec(p.position(mesh), out->add_points());
    auto* c = out->add_crossings();
    c->set_v0(p.v0);
    c->set_v1(p.is_vertex() ? -1 : p.v1);
    c->set_t(p.is_vertex() ? 0.0 : p.t);
    ids.push_back(p.v0);
    if (!p.is_vertex()) ids.push_back(p.v1);
  }
  out->mutable_segment_faces()->Add(path.segment_faces.begin(), path.segment_faces.end());
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  for (int id : ids) {
    if (id < 0 || id >= mesh.num_vertices()) continue;
    auto* v = out->add_vertices();
    v->set_id(id);
    set_vec(mesh.position(id), v->mutable_position());
  }
}

SurfacePath path_from_proto(const v1::Path& path) {
  SurfacePath out;
  out.points.reserve(path.crossings_size());
  for (const auto& c : path.crossings()) {
    out.points.push_back(c.v1() < 0 ? SurfacePoint::at_vertex(c.v0()) : SurfacePoint::on_edge(c.v0(), c.v1(), c.t()));
  }
  out.segment_faces.assign(path.segment_faces().begin(), path.segment_faces().end());
  return out;
}

void result_to_proto(const Mesh& mesh, const SolveResult& r, v1::JobResult* out) {
  path_to_proto(mesh, r.path, out->mutable_path());
  out->set_energy(r.energy);
  out->set_length(r.length);
  out->set_method(method_to_proto(r.method));
  out->set_refined(r.refined);
  out->set_generations(r.generations);
  out->set_evaluations(r.evaluations);
  out->set_seconds(r.seconds);
  out->set_fmm_energy(r.fmm_energy);
  for (const auto& m : r.metrics) {
    auto* pm = out->add_metrics();
    pm->set_name(m.name);
    pm->set_value(m.value);
  }
  out->set_stop_reason(r.stop_reason);
}

SolveResult result_from_proto(const v1::JobResult& r) {
  SolveResult out;
  out.path = path_from_proto(r.path());
  out.energy = r.energy();
  out.length = r.length();
  out.method = method_from_proto(r.method());
  out.refined = r.refined();
  out.generations = r.generations();
  out.evaluations = r.evaluations();
  out.seconds = r.seconds();
  out.fmm_energy = r.fmm_energy();
  for (const auto& m : r.metrics()) out.metrics.push_back({m.name(), m.value()});
  out.stop_reason = r.stop_reason();
  return out;
}

void progress_to_proto(const Mesh& mesh, const Progress& p, v1::Progress* out) {
  out->set_generation(p.generation);
  out->set_max_generations(p.max_generations);
  out->set_best_energy(p.best_energy);
  out->set_mean_energy(p.mean_energy);
  out->set_evaluations(p.evaluations);
  out->set_improvements(p.improvements);
  out->set_elapsed_seconds(p.elapsed_seconds);
  if (p.best_path) path_to_proto(mesh, *p.best_path, out->mutable_best_path());
}

Mesh path_mesh(const v1::Path& path) {
  // Vertices keep their true ids; ids the path does not use sit at the first point. Three
  // extra vertices at the end carry the one face a Mesh needs.
  int max_id = -1;
  for (const auto& v : path.vertices()) max_id = std::max(max_id, v.id());
  for (const auto& c : path.crossings()) max_id = std::max({max_id, c.v0(), c.v1()});
  if (path.crossings_size() == 0 || max_id < 0) {
    throw Error(ErrorCode::invalid_argument, "the result has an empty path");
  }
  if (path.vertices_size() == 0) {
    throw Error(ErrorCode::invalid_argument,
                "the result carries no vertex positions; pass the mesh file to write it");
  }
  const Vec3 filler = path.points_size() > 0 ? get_vec(path.points(0)) : Vec3::Zero();
  std::vector<Vec3> positions(static_cast<size_t>(max_id) + 4, filler);
  for (const auto& v : path.vertices()) {
    if (v.id() >= 0) positions[v.id()] = get_vec(v.position());
  }
  const int a = max_id + 1;
  positions[a] = filler;
  positions[a + 1] = filler + Vec3(1, 0, 0);
  positions[a + 2] = filler + Vec3(0, 1, 0);
  return Mesh(std::move(positions), {{a, a + 1, a + 2}});
}

namespace {
SolveResult result_for_writing(const v1::JobResult& result, const Mesh& mesh, bool stand_in) {
  SolveResult r = result_from_proto(result);
  for (const auto& p : r.path.points) {
    if (p.v0 < 0 || p.v0 >= mesh.num_vertices() || (!p.is_vertex() && p.v1 >= mesh.num_vertices())) {
      throw Error(ErrorCode::invalid_argument, "the result's path refers to vertex ids outside the mesh");
    }
  }
  // The stand-in mesh has a single face: point every segment at it.
  if (stand_in) r.path.segment_faces.assign(r.path.num_segments(), mesh.num_faces() - 1);
  return r;
}
}  // namespace

void write_result_message(const std::string& out_path, const v1::JobResult& result, const Mesh* mesh) {
  if (mesh) {
    write_result(out_path, *mesh, result_for_writing(result, *mesh, false));
  } else {
    const Mesh stand_in = path_mesh(result.path());
    write_result(out_path, stand_in, result_for_writing(result, stand_in, true));
  }
}

nlohmann::json result_message_to_json(const v1::JobResult& result, const Mesh* mesh) {
  if (mesh) return result_to_json(*mesh, result_for_writing(result, *mesh, false));
  const Mesh stand_in = path_mesh(result.path());
  return result_to_json(stand_in, result_for_writing(result, stand_in, true));
}

grpc::StatusCode status_code(ErrorCode code) {
  switch (code) {
    case ErrorCode::invalid_argument: return grpc::StatusCode::INVALID_ARGUMENT;
    case ErrorCode::not_found: return grpc::StatusCode::NOT_FOUND;
    case ErrorCode::failed_precondition: return grpc::StatusCode::FAILED_PRECONDITION;
    case ErrorCode::resource_exhausted: return grpc::StatusCode::RESOURCE_EXHAUSTED;
    case ErrorCode::cancelled: return grpc::StatusCode::CANCELLED;
    case ErrorCode::unavailable: return grpc::StatusCode::UNAVAILABLE;
    case ErrorCode::internal: return grpc::StatusCode::INTERNAL;
  }
  return grpc::StatusCode::INTERNAL;
}

const char* status_code_name(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::OK: return "OK";
    case grpc::StatusCode::CANCELLED: return "CANCELLED";
    case grpc::StatusCode::UNKNOWN: return "UNKNOWN";
    case grpc::StatusCode::INVALID_ARGUMENT: return "INVALID_ARGUMENT";
    case grpc::StatusCode::DEADLINE_EXCEEDED: return "DEADLINE_EXCEEDED";
    case grpc::StatusCode::NOT_FOUND: return "NOT_FOUND";
    case grpc::StatusCode::ALREADY_EXISTS: return "ALREADY_EXISTS";
    case grpc::StatusCode::PERMISSION_DENIED: return "PERMISSION_DENIED";
    case grpc::StatusCode::UNAUTHENTICATED: return "UNAUTHENTICATED";
    case grpc::StatusCode::RESOURCE_EXHAUSTED: return "RESOURCE_EXHAUSTED";
    case grpc::StatusCode::FAILED_PRECONDITION: return "FAILED_PRECONDITION";
    case grpc::StatusCode::ABORTED: return "ABORTED";
    case grpc::StatusCode::OUT_OF_RANGE: return "OUT_OF_RANGE";
    case grpc::StatusCode::UNIMPLEMENTED: return "UNIMPLEMENTED";
    case grpc::StatusCode::INTERNAL: return "INTERNAL";
    case grpc::StatusCode::UNAVAILABLE: return "UNAVAILABLE";
    case grpc::StatusCode::DATA_LOSS: return "DATA_LOSS";
    default: return "UNKNOWN";
  }
}

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
  // Per face: indices 12, neighbours 12, edge lengths 24, angles 24, normal 24, area 8.
  const uint64_t v = static_cast<uint64_t>(mesh.num_vertices());
  const uint64_t f = static_cast<uint64_t>(mesh.num_faces());
  return 512 + v * 84 + f * 104;
}

}  // namespace depath::wire
