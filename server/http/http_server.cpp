// SPDX-License-Identifier: MIT
#include "http/http_server.hpp"

#include "depath/util/error.hpp"
#include "http/event_stream.hpp"
#include "http/http_common.hpp"
#include "http/json_api.hpp"
#include "http/ops_routes.hpp"
#include "http/static_files.hpp"

#include <algorithm>
#include <chrono>
#include <regex>

namespace depath::service {

namespace {

// HOST:PORT, or [V6HOST]:PORT.
std::pair<std::string, int> split_address(const std::string& address) {
  const auto colon = address.rfind(':');
  auto bad = [&] {
    throw Error(ErrorCode::invalid_argument, "--http-listen '" + address + "' must be HOST:PORT (e.g. 127.0.0.1:8080)");
  };
  if (colon == std::string::npos || colon == 0 || colon + 1 == address.size()) bad();
  std::string host = address.substr(0, colon);
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  const std::string port_text = address.substr(colon + 1);
  if (port_text.size() > 5 || !std::all_of(port_text.begin(), port_text.end(), ::isdigit)) bad();
  const int port = std::stoi(port_text);
  if (port > 65535) bad();
  return {host, port};
}

}  // namespace

std::string http_route_label(const std::string& method, const std::string& path) {
  static const std::vector<std::pair<std::regex, std::string>> routes = {
      {std::regex("/healthz"), "/healthz"},
      {std::regex("/readyz"), "/readyz"},
      {std::regex("/metrics"), "/metrics"},
      {std::regex("/v1/jobs"), "/v1/jobs"},
      {std::regex("/v1/jobs/[^/]+"), "/v1/jobs/{id}"},
      {std::regex("/v1/jobs/[^/]+/events"), "/v1/jobs/{id}/events"},
      {std::regex("/v1/jobs/[^/]+/cancel"), "/v1/jobs/{id}/cancel"},
      {std::regex("/v1/jobs/[^/]+/progress"), "/v1/jobs/{id}/progress"},
      {std::regex("/v1/jobs/[^/]+/field"), "/v1/jobs/{id}/field"},
      {std::regex("/v1/jobs/[^/]+/result\\.[a-z]+"), "/v1/jobs/{id}/result"},
      {std::regex("/v1/meshes"), "/v1/meshes"},
      {std::regex("/v1/meshes/[^/]+"), "/v1/meshes/{id}"},
      {std::regex("/v1/meshes/[^/]+/geometry"), "/v1/meshes/{id}/geometry"},
      {std::regex("/v1/.*"), "/v1/other"},
      {std::regex("/"), "/"},
      {std::regex("/jobs/[^/]+"), "/jobs/{id}"},
      {std::regex("/assets/.*"), "/assets/*"},
  };
  std::string label = "other";
  for (const auto& [re, name] : routes) {
    if (std::regex_match(path, re)) {
      label = name;
      break;
    }
  }
  const bool known = method == "GET" || method == "POST" || method == "HEAD";
  return (known ? method : std::string("OTHER")) + " " + label;
}

struct HttpServer::Impl {
  explicit Impl(ServiceContext& service) : ctx{service} {}
  http::HttpContext ctx;
  std::unique_ptr<httplib::Server> server;
  bool stopped = false;
};

HttpServer::HttpServer(ServiceContext& service) : impl_(std::make_unique<Impl>(service)) {
  const ServerOptions& o = service.options;
  const auto [host, port] = split_address(o.http_listen);
  if (o.http_threads < 2) throw Error(ErrorCode::invalid_argument, "--http-threads must be >= 2");
  const auto web_root = http::find_web_root(o.web_root);

  // The gRPC side's --tls-cert/--tls-key (and --tls-client-ca: client certificates required).
  // httplib reads them once: a renewed certificate reaches HTTP at the next restart.
  if (o.tls_cert.empty() != o.tls_key.empty())
    throw Error(ErrorCode::invalid_argument, "TLS for HTTP needs both --tls-cert and --tls-key");
  if (!o.tls_cert.empty()) {
    auto tls = std::make_unique<httplib::SSLServer>(o.tls_cert.c_str(), o.tls_key.c_str(),
                                                    o.tls_client_ca.empty() ? nullptr : o.tls_client_ca.c_str());
    if (!tls->is_valid())
      throw Error(ErrorCode::invalid_argument, "cannot use the TLS certificate '" + o.tls_cert + "' and key '" +
                                                   o.tls_key + "' for HTTP (unreadable or not matching?)");
    impl_->server = std::move(tls);
  } else {
    impl_->server = std::make_unique<httplib::Server>();
  }
  auto& server = *impl_->server;
  auto& ctx = impl_->ctx;
  const int threads = o.http_threads;
  ctx.max_event_streams = std::max(1, threads - 4);
  server.new_task_queue = [threads] { return new httplib::ThreadPool(static_cast<size_t>(threads)); };
  server.set_payload_max_length(std::max<uint64_t>(o.max_upload_bytes, static_cast<uint64_t>(o.max_message_bytes)));
  // SO_REUSEADDR only: httplib's default adds SO_REUSEPORT, with which a second server (or a
  // gRPC server, which sets it too) could bind the same port and take half the connections.
  server.set_socket_options([](socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, reinterpret_cast<const void*>(&yes), sizeof(yes));
  });
  // Small answers and event frames go out at once (Nagle + delayed ACK cost ~40 ms a request),
  // and a keep-alive connection serves many requests (a page polling, a scraper).
  server.set_tcp_nodelay(true);
  server.set_keep_alive_max_count(1000);
  server.set_read_timeout(5);
  server.set_write_timeout(5);
  server.set_logger([&ctx](const httplib::Request& req, const httplib::Response& res) {
    ctx.service.metrics.http_request(http_route_label(req.method, req.path), res.status);
  });
  server.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
    try {
      std::rethrow_exception(ep);
    } catch (const std::exception& e) {
      http::send_error(res, {grpc::StatusCode::INTERNAL, std::string("internal error: ") + e.what()});
    } catch (...) {
      http::send_error(res, {grpc::StatusCode::INTERNAL, "internal error"});
    }
  });
  server.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;  // a handler's own error body
    if (req.path.rfind("/v1/", 0) == 0 && res.status == 404) {
      http::send_error(res, {grpc::StatusCode::NOT_FOUND, "no such route: " + req.method + " " + req.path});
    } else if (res.status == 413) {
      http::send_error(res, {grpc::StatusCode::RESOURCE_EXHAUSTED,
                             "request body over the limit (--max-upload-bytes / --max-message-bytes)"});
      res.status = 413;
    }
  });

  http::add_ops_routes(server, ctx);
  http::add_event_stream(server, ctx);  // before /v1/jobs/{id}: patterns are tried in order
  http::add_json_api(server, ctx);
  http::add_static_files(server, ctx, web_root);  // last: it has the catch-all file route

  port_ = port == 0 ? server.bind_to_any_port(host) : (server.bind_to_port(host, port) ? port : -1);
  if (port_ <= 0) {
    throw Error(ErrorCode::invalid_argument,
                "cannot listen for HTTP on '" + o.http_listen + "' (address in use or invalid?)");
  }
  thread_ = std::thread([&server] { server.listen_after_bind(); });
  service.log.info("http.started", {{"listen", o.http_listen},
                                    {"port", port_},
                                    {"tls", !o.tls_cert.empty()},
                                    {"web_root", web_root ? web_root->string() : std::string()},
                                    {"threads", threads}});
}

HttpServer::~HttpServer() { stop(); }

void HttpServer::stop() {
  if (!impl_ || impl_->stopped) return;
  impl_->stopped = true;
  impl_->ctx.stopping.store(true);
  // Event streams write what they have and end (they poll `stopping`); give them a moment
  // before the listener closes the connections.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(1);
  while (impl_->ctx.event_streams.load() > 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  impl_->server->stop();
  if (thread_.joinable()) thread_.join();
}

}  // namespace depath::service
