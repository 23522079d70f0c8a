// SPDX-License-Identifier: MIT
#include "http/http_common.hpp"

#include "depath/wire/wire.hpp"
#include "service_error.hpp"

namespace depath::service::http {

int http_status(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::OK: return 200;
    case grpc::StatusCode::INVALID_ARGUMENT: return 400;
    case grpc::StatusCode::UNAUTHENTICATED: return 401;
    case grpc::StatusCode::PERMISSION_DENIED: return 403;
    case grpc::StatusCode::NOT_FOUND: return 404;
    case grpc::StatusCode::ALREADY_EXISTS:
    case grpc::StatusCode::FAILED_PRECONDITION: return 409;
    case grpc::StatusCode::RESOURCE_EXHAUSTED: return 429;
    case grpc::StatusCode::UNAVAILABLE: return 503;
    default: return 500;
  }
}

void send_json(httplib::Response& res, const nlohmann::json& body, int status) {
  res.status = status;
  res.set_content(body.dump(), "application/json; charset=utf-8");  // not brotli: see static_files.cpp
}

void send_error(httplib::Response& res, const grpc::Status& status) {
  send_json(res,
            {{"error",
              {{"code", wire::status_code_name(status.error_code())}, {"message", status.error_message()}}}},
            http_status(status.error_code()));
  if (status.error_code() == grpc::StatusCode::UNAUTHENTICATED) res.set_header("WWW-Authenticate", "Bearer");
}

bool authorized(HttpContext& ctx, const httplib::Request& req, httplib::Response& res, std::string* client) {
  // The peer in gRPC's form, so failed attempts and request rates share their buckets.
  const std::string peer = (req.remote_addr.find(':') == std::string::npos ? "ipv4:" + req.remote_addr
                                                                            : "ipv6:[" + req.remote_addr + "]") +
                           ":" + std::to_string(req.remote_port);
  const std::string method = "HTTP " + req.method + " " + req.path;  // names the call in auth logs
  grpc::Status s;
  if (req.has_header("Authorization")) {
    const std::string value = req.get_header_value("Authorization");
    s = ctx.service.authorize(method, &value, peer, client);
  } else if (req.has_param("access_token")) {
    const std::string value = "Bearer " + req.get_param_value("access_token");
    s = ctx.service.authorize(method, &value, peer, client);
  } else {
    s = ctx.service.authorize(method, nullptr, peer, client);
  }
  if (s.ok()) return true;
  if (s.error_code() == grpc::StatusCode::UNAUTHENTICATED) ctx.service.metrics.auth_failure("http");
  send_error(res, s);
  return false;
}

grpc::Status current_status() { return current_exception_status(); }

}  // namespace depath::service::http
