// SPDX-License-Identifier: MIT
// What the HTTP routes share: the service they call, the token check, and errors as
// {"error":{"code","message"}} with the HTTP status of the gRPC code the same operation gives.
#pragma once

#include "service_context.hpp"  // first: httplib.h pulls in <resolv.h>, whose `_res` macro breaks Eigen

#include <grpcpp/support/status.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <string>

namespace depath::service::http {

struct HttpContext {
  ServiceContext& service;
  /// Set when the listener stops: open event streams end (clients resume with Last-Event-ID).
  std::atomic<bool> stopping{false};
  std::atomic<int> event_streams{0};
  int max_event_streams = 1;  ///< HTTP threads minus a few kept free for other requests
};

/// INVALID_ARGUMENT 400, UNAUTHENTICATED 401, PERMISSION_DENIED 403, NOT_FOUND 404,
/// ALREADY_EXISTS and FAILED_PRECONDITION 409, RESOURCE_EXHAUSTED 429, UNAVAILABLE 503,
/// anything else 500.
int http_status(grpc::StatusCode code);

/// Writes the error body and status.
void send_error(httplib::Response& res, const grpc::Status& status);

/// Writes a JSON body (200 unless `status` says otherwise).
void send_json(httplib::Response& res, const nlohmann::json& body, int status = 200);

/// The token check of the gRPC side (ServiceContext::authorize) on the request's
/// `Authorization` header, or on `?access_token=` for clients that cannot set headers
/// (EventSource). On failure writes the 401 and returns false.
bool authorized(HttpContext& ctx, const httplib::Request& req, httplib::Response& res);

/// current_exception_status() (service_error.hpp), out of line; call inside a catch block.
grpc::Status current_status();

/// Runs a /v1 handler: the token check (and, when `admit`, UNAVAILABLE while shutting down),
/// then `fn`; any exception becomes the error response of its status.
template <class Fn>
void api_call(HttpContext& ctx, const httplib::Request& req, httplib::Response& res, bool admit, Fn&& fn) {
  if (!authorized(ctx, req, res)) return;
  if (admit && ctx.service.shutting_down.load()) {
    send_error(res, {grpc::StatusCode::UNAVAILABLE, "server is shutting down"});
    return;
  }
  try {
    fn();
  } catch (...) {
    send_error(res, current_status());
  }
}

}  // namespace depath::service::http
