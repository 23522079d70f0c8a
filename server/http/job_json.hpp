// SPDX-License-Identifier: MIT
// The JSON shapes of the HTTP face (README "HTTP face"): job summaries and details, job specs
// (flat: mesh_id, source, target, energy, method, population, generations, seed, ...), progress,
// results (the JSON `depath solve --out x.json` writes, plus elapsed_seconds) and events.
//
// Inputs: the messages the job service gives (JobInfo, JobResult, JobEvent), or a client's
// JSON spec. Outputs: nlohmann::json values, or a SubmitJobRequest. Guarantees: a spec's
// names and enum words are those of `depath solve` (energy geodesic|vector_field|
// constant_slope, method de|fmm|descent, up x|y|z); an unknown field, a value of the wrong
// type or an unknown word is Error(invalid_argument) naming it; range checks are left to the
// job service (the same validate_job as gRPC submits).
#pragma once

#include "depath/v1/job.pb.h"

#include <nlohmann/json.hpp>

namespace depath::service::http {

/// {"id","state","mesh_id","energy","method","generation","generations","best_energy","created_at"}
nlohmann::json job_summary(const v1::JobInfo& info);

/// {"id","state","spec","progress"|null,"result"|null,"error"|null, ...} (`result` may be null).
nlohmann::json job_detail(const v1::JobInfo& info, const v1::JobResult* result);

nlohmann::json spec_json(const v1::JobSpec& spec);
/// A client's spec (with optional "client_request_id"). Throws Error(invalid_argument).
v1::SubmitJobRequest submit_request_from_json(const nlohmann::json& body);

nlohmann::json progress_json(const v1::Progress& progress);
nlohmann::json result_json(const v1::JobResult& result);

/// The SSE event name of a job event: "state", "progress", "path" (a progress event that
/// carries the best path so far) or "result".
const char* event_name(const v1::JobEvent& event);
/// The data of an SSE event: {"sequence","time","job_id", ...the kind's fields}.
nlohmann::json event_json(const v1::JobEvent& event);

}  // namespace depath::service::http
