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
#include <type_traits>

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

/// The admission check of the gRPC side (ServiceContext::authorize: tokens, failed-attempt
/// limit, per-client request rate) on the request's `Authorization` header, or on
/// `?access_token=` for clients that cannot set headers (EventSource). On failure writes the
/// error (401 or 429) and returns false; on success `client` (if given) is the caller's
/// identity for per-client quotas.
bool authorized(HttpContext& ctx, const httplib::Request& req, httplib::Response& res,
                std::string* client = nullptr);

/// current_exception_status() (service_error.hpp), out of line; call inside a catch block.
grpc::Status current_status();

/// Runs a /v1 handler: the admission check (and, when `admit`, UNAVAILABLE while shutting
/// down), then `fn` (given the caller's identity if it takes a string); any exception becomes
/// the error response of its status.
template <class Fn>
void api_call(HttpContext& ctx, const httplib::Request& req, httplib::Response& res, bool admit, Fn&& fn) {
  std::string client;
  if (!authorized(ctx, req, res, &client)) return;
  if (admit && ctx.service.shutting_down.load()) {
    send_error(res, {grpc::StatusCode::UNAVAILABLE, "server is shutting down"});
    return;
  }
  try {
    if constexpr (std::is_invocable_v<Fn, const std::string&>) {
      fn(client);
    } else {
      fn();
    }
  } catch (...) {
    send_error(res, current_status());
  }
}

}  // namespace depath::service::http
