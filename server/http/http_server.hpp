// SPDX-License-Identifier: MIT
// The HTTP listener of depathd (--http-listen): cpp-httplib serving the operator's routes
// (ops_routes.hpp), the /v1 JSON API (json_api.hpp) and its event streams
// (event_stream.hpp), and the web page (static_files.hpp). Every answer is counted in
// depath_http_requests_total by route (a fixed set of patterns) and status.
//
// TLS: with --tls-cert/--tls-key it serves HTTPS with the gRPC side's certificate (and, with
// --tls-client-ca, requires client certificates; httplib::SSLServer, Debian's build has OpenSSL). Limits: --http-threads workers; bodies up to the larger
// of --max-upload-bytes and --max-message-bytes (413 beyond); 5 s read/write timeouts.
#pragma once

#include "service_context.hpp"

#include <memory>
#include <thread>

namespace depath::service {

class HttpServer {
 public:
  /// Binds options.http_listen (HOST:PORT; port 0 picks one) and starts serving on a thread.
  /// Throws Error(invalid_argument) for a bad address, a port it cannot bind, a bad web root
  /// or unusable TLS files.
  explicit HttpServer(ServiceContext& ctx);
  ~HttpServer();  ///< stop()
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  int port() const { return port_; }
  /// Ends the event streams (after the events they have) and stops listening. Idempotent.
  void stop();

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  int port_ = 0;
  std::thread thread_;
};

/// A short, bounded label of a request path for metrics ("/v1/jobs/{id}", "/assets/*", ...).
std::string http_route_label(const std::string& method, const std::string& path);

}  // namespace depath::service
