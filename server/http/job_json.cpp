// SPDX-License-Identifier: MIT
#include "http/job_json.hpp"

#include "depath/util/error.hpp"
#include "depath/wire/wire.hpp"

#include <grpcpp/support/status.h>

#include <set>

namespace depath::service::http {

using nlohmann::json;

namespace {

const char* up_name(int axis) { return axis == 0 ? "x" : axis == 1 ? "y" : "z"; }

json points_json(const v1::Path& path) {
  json points = json::array();
  for (const auto& p : path.points()) points.push_back({p.x(), p.y(), p.z()});
  return points;
}

json error_json(int code, const std::string& message) {
  if (code == 0) return nullptr;
  return {{"code", wire::status_code_name(static_cast<grpc::StatusCode>(code))}, {"message", message}};
}

[[noreturn]] void bad(const std::string& what) { throw Error(ErrorCode::invalid_argument, "job spec: " + what); }

// Typed reads of a client's JSON that name the field on a type error.
template <class T>
T read(const json& body, const char* key) {
  const json& v = body.at(key);
  if constexpr (std::is_same_v<T, bool>) {
    if (!v.is_boolean()) bad(std::string("'") + key + "' must be true or false");
    return v.get<bool>();
  } else if constexpr (std::is_same_v<T, std::string>) {
    if (!v.is_string()) bad(std::string("'") + key + "' must be a string");
    return v.get<std::string>();
  } else if constexpr (std::is_integral_v<T>) {
    if (!v.is_number_integer()) bad(std::string("'") + key + "' must be an integer");
    if (v.is_number_unsigned()) {
      const auto u = v.get<uint64_t>();
      if (u > static_cast<uint64_t>(std::numeric_limits<T>::max())) bad(std::string("'") + key + "' is too large");
      return static_cast<T>(u);
    }
    const auto i = v.get<int64_t>();
    if (i < static_cast<int64_t>(std::numeric_limits<T>::min()) ||
        (i > 0 && static_cast<uint64_t>(i) > static_cast<uint64_t>(std::numeric_limits<T>::max())))
      bad(std::string("'") + key + "' is out of range");
    return static_cast<T>(i);
  } else {
    if (!v.is_number()) bad(std::string("'") + key + "' must be a number");
    return v.get<double>();
  }
}

template <class T>
void read_if(const json& body, const char* key, T& out) {
  if (body.contains(key) && !body.at(key).is_null()) out = read<T>(body, key);
}

}  // namespace

json job_summary(const v1::JobInfo& info) {
  const JobSpec spec = wire::job_from_proto(info.spec());
  json out = {{"id", info.job_id()},
              {"state", wire::state_name(info.state())},
              {"mesh_id", info.mesh_id()},
              {"energy", energy_kind_name(spec.energy.kind)},
              {"method", method_name(spec.method)},
              {"generation", nullptr},
              {"generations", spec.method == Method::de ? json(spec.de.generations) : json(nullptr)},
              {"best_energy", nullptr},
              {"created_at", info.created_unix()}};
  if (info.has_last_progress()) {
    out["generation"] = info.last_progress().generation();
    if (info.last_progress().max_generations() > 0) out["generations"] = info.last_progress().max_generations();
    out["best_energy"] = info.last_progress().best_energy();
  }
  return out;
}

json job_detail(const v1::JobInfo& info, const v1::JobResult* result) {
  json out = job_summary(info);
  out["spec"] = spec_json(info.spec());
  out["progress"] = info.has_last_progress() ? progress_json(info.last_progress()) : json(nullptr);
  out["result"] = result ? result_json(*result) : json(nullptr);
  out["error"] = error_json(info.error_code(), info.error_message());
  out["started_at"] = info.started_unix() > 0 ? json(info.started_unix()) : json(nullptr);
  out["finished_at"] = info.finished_unix() > 0 ? json(info.finished_unix()) : json(nullptr);
  out["last_sequence"] = info.last_sequence();
  out["queue_position"] = info.queue_position();
  out["client_request_id"] = info.client_request_id();
  return out;
}

json spec_json(const v1::JobSpec& proto) {
  const JobSpec s = wire::job_from_proto(proto);  // defaults resolved as the job runs them
  json out = {{"mesh_id", proto.mesh_id()},
              {"source", s.source},
              {"target", s.target},
              {"energy", energy_kind_name(s.energy.kind)},
              {"method", method_name(s.method)},
              {"refine", s.refine},
              {"population", s.de.population},
              {"generations", s.de.generations},
              {"stall", s.de.stall},
              {"f", s.de.F},
              {"cr", s.de.CR},
              {"strategy", s.de.strategy},
              {"seed_with_problem", s.de.seed_with_problem},
              {"seed", s.seed},
              {"path_every", s.path_every},
              {"field_from_height", s.energy.field_from_height},
              {"rotate_degrees", s.energy.rotate_degrees},
              {"slope", s.energy.slope},
              {"up", up_name(s.energy.up_axis)},
              {"smoothness", s.energy.smoothness}};
  if (!s.energy.density.empty()) out["density"] = s.energy.density;
  if (!s.energy.field.empty()) {
    json field = json::array();
    for (const auto& v : s.energy.field) field.push_back({v.x(), v.y(), v.z()});
    out["field"] = std::move(field);
  }
  return out;
}

v1::SubmitJobRequest submit_request_from_json(const json& body) {
  if (!body.is_object()) bad("the body must be a JSON object");
  static const std::set<std::string> known = {
      "mesh_id", "source", "target", "energy", "method", "refine", "population", "generations", "stall",
      "f", "F", "cr", "CR", "strategy", "seed_with_problem", "seed", "path_every", "density", "field",
      "field_from_height", "rotate_degrees", "slope", "up", "smoothness", "client_request_id"};
  for (const auto& [key, value] : body.items()) {
    if (!known.count(key)) bad("unknown field '" + key + "'");
  }
  if (!body.contains("mesh_id")) bad("'mesh_id' is missing");
  if (!body.contains("source") || !body.contains("target")) bad("'source' and 'target' (vertex ids) are required");
  JobSpec s;
  const std::string mesh_id = read<std::string>(body, "mesh_id");
  s.source = read<int>(body, "source");
  s.target = read<int>(body, "target");
  if (body.contains("energy")) s.energy.kind = parse_energy_kind(read<std::string>(body, "energy"));
  if (body.contains("method")) s.method = parse_method(read<std::string>(body, "method"));
  read_if(body, "refine", s.refine);
  read_if(body, "population", s.de.population);
  read_if(body, "generations", s.de.generations);
  read_if(body, "stall", s.de.stall);
  read_if(body, "f", s.de.F);
  read_if(body, "F", s.de.F);
  read_if(body, "cr", s.de.CR);
  read_if(body, "CR", s.de.CR);
  read_if(body, "strategy", s.de.strategy);
  read_if(body, "seed_with_problem", s.de.seed_with_problem);
  read_if(body, "seed", s.seed);
  read_if(body, "path_every", s.path_every);
  read_if(body, "field_from_height", s.energy.field_from_height);
  read_if(body, "rotate_degrees", s.energy.rotate_degrees);
  read_if(body, "slope", s.energy.slope);
  read_if(body, "smoothness", s.energy.smoothness);
  if (body.contains("up")) {
    const std::string up = read<std::string>(body, "up");
    if (up == "x") s.energy.up_axis = 0;
    else if (up == "y") s.energy.up_axis = 1;
    else if (up == "z") s.energy.up_axis = 2;
    else bad("'up' must be x, y or z (got '" + up + "')");
  }
  if (body.contains("density")) {
    const json& d = body.at("density");
    if (!d.is_array()) bad("'density' must be an array of numbers, one per vertex");
    s.energy.density.reserve(d.size());
    for (const auto& v : d) {
      if (!v.is_number()) bad("'density' must be an array of numbers, one per vertex");
      s.energy.density.push_back(v.get<double>());
    }
  }
  if (body.contains("field")) {
    const json& f = body.at("field");
    if (!f.is_array()) bad("'field' must be an array of [x, y, z], one per vertex");
    s.energy.field.reserve(f.size());
    for (const auto& v : f) {
      if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
        bad("'field' must be an array of [x, y, z], one per vertex");
      s.energy.field.emplace_back(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
    }
  }
  v1::SubmitJobRequest request;
  *request.mutable_spec() = wire::job_to_proto(s, mesh_id);
  if (body.contains("client_request_id")) request.set_client_request_id(read<std::string>(body, "client_request_id"));
  return request;
}

json progress_json(const v1::Progress& p) {
  json out = {{"generation", p.generation()},
              {"generations", p.max_generations()},
              {"best_energy", p.best_energy()},
              {"mean_energy", p.mean_energy()},
              {"evaluations", p.evaluations()},
              {"improvements", p.improvements()},
              {"elapsed_seconds", p.elapsed_seconds()}};
  if (p.has_best_path() && p.best_path().points_size() > 0) out["path"] = {{"points", points_json(p.best_path())}};
  return out;
}

json result_json(const v1::JobResult& result) {
  json out = wire::result_message_to_json(result, nullptr);  // the JSON `depath solve` writes
  out["elapsed_seconds"] = result.seconds();
  return out;
}

const char* event_name(const v1::JobEvent& event) {
  switch (event.kind_case()) {
    case v1::JobEvent::kState: return "state";
    case v1::JobEvent::kProgress:
      return event.progress().has_best_path() && event.progress().best_path().points_size() > 0 ? "path"
                                                                                                : "progress";
    case v1::JobEvent::kResult: return "result";
    default: return "unknown";
  }
}

json event_json(const v1::JobEvent& event) {
  json out = {{"sequence", event.sequence()}, {"time", event.time_unix()}, {"job_id", event.job_id()}};
  switch (event.kind_case()) {
    case v1::JobEvent::kState:
      out["state"] = wire::state_name(event.state().state());
      out["message"] = event.state().message();
      out["error"] = error_json(event.state().error_code(), event.state().message());
      break;
    case v1::JobEvent::kProgress: out.update(progress_json(event.progress())); break;
    case v1::JobEvent::kResult: out["result"] = result_json(event.result()); break;
    default: break;
  }
  return out;
}

}  // namespace depath::service::http
