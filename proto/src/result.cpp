// SPDX-License-Identifier: MIT
#include "depath/wire/result.hpp"

#include "depath/io/result_writer.hpp"
#include "depath/util/error.hpp"
#include "depath/wire/job.hpp"
#include "vec.hpp"

#include <algorithm>
#include <utility>
#include <vector>

namespace depath::wire {

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

Progress progress_from_proto(const v1::Progress& p) {
  Progress out;
  out.generation = p.generation();
  out.max_generations = p.max_generations();
  out.best_energy = p.best_energy();
  out.mean_energy = p.mean_energy();
  out.evaluations = p.evaluations();
  out.improvements = p.improvements();
  out.elapsed_seconds = p.elapsed_seconds();
  return out;
}

ReceivedResult received_result(const v1::JobResult& message, const Mesh* mesh) {
  ReceivedResult w{result_from_proto(message), {}};
  const auto& path = w.result.path;
  if (mesh) {
    for (const auto& p : path.points) {
      if (p.v0 < 0 || p.v0 >= mesh->num_vertices() || (!p.is_vertex() && p.v1 >= mesh->num_vertices())) {
        throw Error(ErrorCode::invalid_argument, "the result's path refers to vertex ids outside the mesh");
      }
    }
    w.points = path_positions(*mesh, path);
    return w;
  }
  // The server computed these positions on the job's mesh, as path_positions does here.
  if (path.points.empty()) throw Error(ErrorCode::invalid_argument, "the result has an empty path");
  if (message.path().points_size() != static_cast<int>(path.points.size())) {
    throw Error(ErrorCode::invalid_argument,
                "the result carries no point positions; pass the mesh file to write it");
  }
  w.points.reserve(path.points.size());
  for (const auto& p : message.path().points()) w.points.push_back(get_vec(p));
  return w;
}

void write_result_message(const std::string& out_path, const v1::JobResult& result, const Mesh* mesh) {
  const ReceivedResult w = received_result(result, mesh);
  write_result(out_path, w.points, w.result);
}

nlohmann::json result_message_to_json(const v1::JobResult& result, const Mesh* mesh) {
  const ReceivedResult w = received_result(result, mesh);
  return nlohmann::json::parse(result_json(w.points, w.result));
}

}  // namespace depath::wire
