// SPDX-License-Identifier: MIT
#include "http/json_api.hpp"

#include "depath/io/result_writer.hpp"
#include "depath/mesh/tangent_fields.hpp"
#include "depath/util/error.hpp"
#include "depath/wire/wire.hpp"
#include "http/job_json.hpp"
#include "mesh_upload.hpp"
#include "service_error.hpp"
#include "upload_budget.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <future>
#include <sstream>

namespace depath::service::http {

using nlohmann::json;

namespace {

json mesh_json(const v1::MeshInfo& info) {
  return {{"mesh_id", info.id()},
          {"vertices", info.num_vertices()},
          {"faces", info.num_faces()},
          {"boundary_edges", info.num_boundary_edges()},
          {"components", info.num_components()},
          {"already_present", info.already_present()}};
}

void append_float(std::string& out, double v) {
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, static_cast<float>(v));
  out.append(buf, r.ptr);
}

const char* content_type_of(const std::string& format) {
  if (format == "json") return "application/json; charset=utf-8";
  if (format == "csv") return "text/csv";
  return "text/plain";  // OBJ and PLY polylines are text
}

// Parsing a mesh is slow: it runs on the same bounded queue as gRPC uploads. Its error comes
// back as a status, not as the exception object: one shared by two threads is freed by
// whichever lets go last, through libstdc++'s reference count, which TSan cannot see.
v1::MeshInfo upload_on_queue(HttpContext& ctx, const std::string& name, const std::string& format,
                             const std::string& bytes, const std::string& peer) {
  struct Outcome {
    v1::MeshInfo info;
    grpc::Status status;
  };
  auto task = std::make_shared<std::packaged_task<Outcome()>>([&] {
    Outcome out;
    try {
      out.info = store_upload(ctx.service, name, format, bytes, "http", peer);
    } catch (...) {
      out.status = current_exception_status();
    }
    return out;
  });
  auto done = task->get_future();
  ctx.service.blocking.post([task] { (*task)(); });
  Outcome out = done.get();
  throw_if_error(out.status);
  return std::move(out.info);
}

// Reads the request body whatever its Content-Type (httplib would cap form-encoded bodies at
// 8 KiB), up to `limit` bytes: more is RESOURCE_EXHAUSTED naming `flag`. With `memory`, each
// chunk is covered by it first (an upload's room in --max-upload-memory-bytes).
std::string read_body(const httplib::ContentReader& reader, uint64_t limit, const char* flag,
                      UploadBudget::Hold* memory = nullptr) {
  std::string body;
  bool over = false;
  grpc::Status refused;
  reader([&](const char* data, size_t n) {
    if (body.size() + n > limit) {
      over = true;
      return false;
    }
    if (memory) refused = memory->cover(body.size() + n);
    if (!refused.ok()) return false;
    body.append(data, n);
    return true;
  });
  throw_if_error(refused);
  if (over) {
    throw ServiceError(grpc::StatusCode::RESOURCE_EXHAUSTED, "request body over " + std::to_string(limit) +
                                                                 " bytes (" + flag + ")");
  }
  return body;
}

// A refused request may leave its body unread: close the connection rather than read the
// rest as the next request.
void close_on_error(httplib::Response& res) {
  if (res.status >= 400) res.set_header("Connection", "close");
}

}  // namespace

std::string geometry_json(const Mesh& mesh) {
  std::string out;
  out.reserve(static_cast<size_t>(mesh.num_vertices()) * 30 + static_cast<size_t>(mesh.num_faces()) * 20 + 32);
  out += "{\"vertices\":[";
  bool first = true;
  for (const auto& p : mesh.positions()) {
    for (int k = 0; k < 3; ++k) {
      if (!first) out += ',';
      first = false;
      append_float(out, p[k]);
    }
  }
  out += "],\"faces\":[";
  first = true;
  for (const auto& f : mesh.faces()) {
    for (int k = 0; k < 3; ++k) {
      if (!first) out += ',';
      first = false;
      out += std::to_string(f[k]);
    }
  }
  out += "]}";
  return out;
}

std::string field_json(const std::vector<Vec3>& field) {
  std::string out;
  out.reserve(field.size() * 30 + 16);
  out += "{\"field\":[";
  for (size_t v = 0; v < field.size(); ++v) {
    for (int k = 0; k < 3; ++k) {
      if (v + k > 0) out += ',';
      append_float(out, field[v][k]);
    }
  }
  out += "]}";
  return out;
}

void add_json_api(httplib::Server& server, HttpContext& ctx) {
  server.Get("/v1/jobs", [&ctx](const httplib::Request& req, httplib::Response& res) {
    api_call(ctx, req, res, false, [&] {
      v1::ListJobsRequest request;
      if (req.has_param("mesh_id")) request.set_mesh_id(req.get_param_value("mesh_id"));
      json jobs = json::array();
      const v1::ListJobsResponse list = ctx.service.jobs.list(request);
      for (const auto& info : list.jobs()) jobs.push_back(job_summary(info));
      send_json(res, {{"jobs", std::move(jobs)}});
    });
  });

  server.Get(R"(/v1/jobs/([^/]+))", [&ctx](const httplib::Request& req, httplib::Response& res) {
    api_call(ctx, req, res, false, [&] {
      const std::string id = req.matches[1];
      const v1::JobInfo info = ctx.service.jobs.get(id);
      std::optional<v1::JobResult> result;
      if (info.has_result()) result = ctx.service.jobs.result(id);
      send_json(res, job_detail(info, result ? &*result : nullptr));
    });
  });

  server.Get(R"(/v1/jobs/([^/]+)/progress)", [&ctx](const httplib::Request& req, httplib::Response& res) {
    api_call(ctx, req, res, false, [&] {
      const std::string id = req.matches[1];
      json generation = json::array(), best = json::array(), mean = json::array();
      for (const ProgressPoint& p : ctx.service.jobs.progress_history(id)) {
        generation.push_back(p.generation);
        best.push_back(p.best_energy);
        mean.push_back(std::isfinite(p.mean_energy) ? json(p.mean_energy) : json(nullptr));
      }
      send_json(res, {{"job_id", id},
                      {"max_points", kProgressHistoryPoints},
                      {"generation", std::move(generation)},
                      {"best_energy", std::move(best)},
                      {"mean_energy", std::move(mean)}});
    });
  });

  server.Get(R"(/v1/jobs/([^/]+)/field)", [&ctx](const httplib::Request& req, httplib::Response& res) {
    api_call(ctx, req, res, false, [&] {
      const std::string id = req.matches[1];
      const JobRecord job = ctx.service.jobs.record(id);  // not get(): its spec has no field
      JobSpec spec = wire::job_from_proto(job.spec);
      if (spec.energy.kind != EnergyKind::vector_field)
        throw ServiceError(grpc::StatusCode::FAILED_PRECONDITION,
                           "job " + id + " has no field: its energy is " + energy_kind_name(spec.energy.kind));
      if (!spec.energy.field_from_height && spec.energy.field.empty())
        throw ServiceError(grpc::StatusCode::FAILED_PRECONDITION,
                           "job " + id + " is " + wire::state_name(job.state) +
                               ": a finished job keeps its result, not the field it was given");
      // A given field is the answer as it is; only a height field needs the mesh (maybe reloaded).
      const std::vector<Vec3> field =
          spec.energy.field_from_height
              ? height_gradient_field(ctx.service.meshes.acquire(job.mesh_id)->mesh(), spec.energy.up_axis,
                                      spec.energy.rotate_degrees)
              : std::move(spec.energy.field);
      res.set_content(field_json(field), "application/json; charset=utf-8");  // not brotli: see static_files.cpp
    });
  });

  server.Get(R"(/v1/jobs/([^/]+)/result\.(json|obj|ply|csv))",
             [&ctx](const httplib::Request& req, httplib::Response& res) {
               api_call(ctx, req, res, false, [&] {
                 const std::string id = req.matches[1];
                 const std::string format = req.matches[2];
                 const wire::ReceivedResult r = wire::received_result(ctx.service.jobs.result(id), nullptr);
                 std::ostringstream out;
                 write_result(out, format, r.points, r.result);  // the writers of `depath solve --out`
                 res.set_header("Content-Disposition", "attachment; filename=\"" + id + "." + format + "\"");
                 res.set_content(out.str(), content_type_of(format));
               });
             });

  server.Post("/v1/jobs", [&ctx](const httplib::Request& req, httplib::Response& res,
                                 const httplib::ContentReader& reader) {
    api_call(ctx, req, res, true, [&](const std::string& client) {
      const std::string text =
          read_body(reader, static_cast<uint64_t>(ctx.service.options.max_message_bytes), "--max-message-bytes");
      json body;
      try {
        body = json::parse(text);
      } catch (const json::exception& e) {
        throw Error(ErrorCode::invalid_argument, std::string("job spec: the body is not JSON: ") + e.what());
      }
      const v1::SubmitJobRequest request = submit_request_from_json(body);
      try {
        const v1::SubmitJobResponse reply = ctx.service.jobs.submit(request, client);
        send_json(res, {{"id", reply.job_id()}, {"existing", reply.existing()}, {"job", job_summary(reply.job())}});
      } catch (...) {
        const grpc::Status s = current_exception_status();
        ctx.service.log.info("job.refused", {{"peer", req.remote_addr}, {"mesh", request.spec().mesh_id()},
                                             {"transport", "http"},
                                             {"code", wire::status_code_name(s.error_code())},
                                             {"reason", s.error_message()}});
        throw;
      }
    });
    close_on_error(res);
  });

  server.Post(R"(/v1/jobs/([^/]+)/cancel)", [&ctx](const httplib::Request& req, httplib::Response& res) {
    api_call(ctx, req, res, false,
             [&] { send_json(res, job_summary(ctx.service.jobs.cancel(req.matches[1]))); });
  });

  server.Post("/v1/meshes", [&ctx](const httplib::Request& req, httplib::Response& res,
                                   const httplib::ContentReader& reader) {
    api_call(ctx, req, res, true, [&] {
      if (!req.has_param("format") && !req.has_param("name"))
        throw ServiceError(grpc::StatusCode::INVALID_ARGUMENT,
                           "POST /v1/meshes needs ?format=obj|off|ply|stl (or ?name=FILE.EXT)");
      const std::string name = req.has_param("name") ? req.get_param_value("name") : "upload";
      const std::string format = upload_format(name, req.get_param_value("format"));
      // The upload's room (as gRPC's UploadMesh): the declared length at once, then as it arrives.
      UploadBudget::Hold memory = ctx.service.upload_memory.hold(format);
      uint64_t declared = 0;
      if (req.has_header("Content-Length")) {
        declared = std::strtoull(req.get_header_value("Content-Length").c_str(), nullptr, 10);
        if (declared > ctx.service.options.max_upload_bytes) throw_if_error(upload_too_big(ctx.service.options, declared));
      }
      throw_if_error(memory.cover(declared));
      const std::string bytes = read_body(reader, ctx.service.options.max_upload_bytes, "--max-upload-bytes", &memory);
      const v1::MeshInfo info = upload_on_queue(ctx, name, format, bytes, req.remote_addr);
      send_json(res, mesh_json(info));
    });
    close_on_error(res);
  });

  server.Get(R"(/v1/meshes/([^/]+))", [&ctx](const httplib::Request& req, httplib::Response& res) {
    api_call(ctx, req, res, false, [&] { send_json(res, mesh_json(ctx.service.meshes.get(req.matches[1]))); });
  });

  server.Get(R"(/v1/meshes/([^/]+)/geometry)", [&ctx](const httplib::Request& req, httplib::Response& res) {
    api_call(ctx, req, res, false, [&] {
      const auto lease = ctx.service.meshes.acquire(req.matches[1]);
      res.set_content(geometry_json(lease->mesh()), "application/json; charset=utf-8");  // not brotli: see static_files.cpp
    });
  });
}

}  // namespace depath::service::http
