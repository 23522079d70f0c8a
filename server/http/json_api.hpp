// SPDX-License-Identifier: MIT
// The /v1 JSON routes: a thin layer over the job manager and the mesh store, the same
// operations the gRPC handlers call (no second submit or validation).
//
//   GET  /v1/jobs                          {"jobs":[summary...]} (oldest first, as ListJobs)
//   GET  /v1/jobs/{id}                     detail: spec, progress, result, error
//   GET  /v1/jobs/{id}/result.{json,obj,ply,csv}  the result file, as `depath result --out`
//   POST /v1/jobs                          JSON spec -> {"id","existing"}
//   POST /v1/jobs/{id}/cancel              -> the job's summary
//   POST /v1/meshes?format=obj|off|ply|stl[&name=FILE]   the mesh file's bytes -> {"mesh_id","vertices","faces"}
//   GET  /v1/meshes/{id}                   {"mesh_id","vertices","faces",...}
//   GET  /v1/meshes/{id}/geometry          {"vertices":[x0,y0,z0,...],"faces":[a0,b0,c0,...]}
// (the event stream, /v1/jobs/{id}/events, is in event_stream.hpp)
#pragma once

#include "http/http_common.hpp"

namespace depath::service::http {

void add_json_api(httplib::Server& server, HttpContext& ctx);

/// The geometry body: positions as single-precision shortest decimals (enough for a
/// viewer, half the bytes of doubles), faces as vertex ids.
std::string geometry_json(const Mesh& mesh);
/// A per-vertex field as {"field":[x0,y0,z0,...]} (single-precision decimals, as geometry).
std::string field_json(const std::vector<Vec3>& field);

}  // namespace depath::service::http
