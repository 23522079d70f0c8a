// SPDX-License-Identifier: MIT
#include "http/ops_routes.hpp"

namespace depath::service::http {

void add_ops_routes(httplib::Server& server, HttpContext& ctx) {
  server.Get("/healthz", [](const httplib::Request&, httplib::Response& res) { res.set_content("ok\n", "text/plain"); });
  server.Get("/readyz", [&ctx](const httplib::Request&, httplib::Response& res) {
    if (ctx.service.shutting_down.load() || ctx.stopping.load()) {
      res.status = 503;
      res.set_content("shutting down\n", "text/plain");
    } else if (!ctx.service.jobs.store_reachable()) {
      res.status = 503;
      res.set_content("store unreachable\n", "text/plain");
    } else {
      res.set_content("ready\n", "text/plain");
    }
  });
  server.Get("/metrics", [&ctx](const httplib::Request&, httplib::Response& res) {
    res.set_content(ctx.service.metrics.exposition(), "text/plain; version=0.0.4; charset=utf-8");
  });
}

}  // namespace depath::service::http
