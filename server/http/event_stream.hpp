// SPDX-License-Identifier: MIT
// GET /v1/jobs/{id}/events: a job's events as Server-Sent Events, mirroring WatchJob.
//
// Each event is `id: SEQUENCE`, `event: state|progress|path|result` ("path" is a progress
// event that carries the best path so far), `data: {json}` (http/job_json.hpp). A client
// resumes after the last id it saw with the `Last-Event-ID` header (EventSource does this by
// itself) or `?after=N`; like WatchJob it then misses no state change and no result, and
// progress is coalesced to the latest (a slow client never slows the job). The stream ends
// after the terminal state event; while idle a comment line (`: keep-alive`) goes out every
// 15 s. Each open stream holds one HTTP thread: beyond --http-threads minus 4 streams,
// 503 UNAVAILABLE. When the listener stops, streams end after the events they have (the
// client resumes elsewhere or later).
#pragma once

#include "http/http_common.hpp"

namespace depath::service::http {

void add_event_stream(httplib::Server& server, HttpContext& ctx);

}  // namespace depath::service::http
