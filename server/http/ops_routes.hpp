// SPDX-License-Identifier: MIT
// The operator's routes, open without a token (probes and Prometheus do not carry one):
//   /healthz  200 "ok" while the listener serves (liveness)
//   /readyz   200 when the store answers and the server is not shutting down, else 503
//             with the reason (readiness: take the replica out of a load balancer)
//   /metrics  the Prometheus text exposition (Content-Type text/plain; version=0.0.4)
#pragma once

#include "http/http_common.hpp"

namespace depath::service::http {

void add_ops_routes(httplib::Server& server, HttpContext& ctx);

}  // namespace depath::service::http
