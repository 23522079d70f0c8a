// SPDX-License-Identifier: MIT
// The metrics registry's exposition text (exact, including escaping and cumulative buckets),
// the route labels of HTTP metrics, and the HTTP listener over TLS with a real certificate
// made by openssl (the hook the gRPC side's --tls-cert/--tls-key are to reuse).
#include "service_test_support.hpp"

#include "http/http_server.hpp"
#include "metrics/registry.hpp"

#include <httplib.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace depath::test {
namespace {

TEST(HttpMetrics, ExpositionTextIsExact) {
  service::MetricsRegistry r;
  r.declare("t_requests_total", service::MetricsRegistry::Type::counter, "Requests\nby path \\ kind");
  r.declare("t_seconds", service::MetricsRegistry::Type::histogram, "Durations", {0.5, 1});
  r.declare("t_depth", service::MetricsRegistry::Type::gauge, "Depth");
  r.inc("t_requests_total", {{"path", "a\"b\\c\nd"}}, 2);
  r.inc("t_requests_total", {{"path", "a\"b\\c\nd"}});
  r.observe("t_seconds", {}, 0.25);
  r.observe("t_seconds", {}, 0.5);  // le is inclusive
  r.observe("t_seconds", {}, 3);
  r.add_collector([](service::MetricsRegistry& m) { m.set("t_depth", {}, 0.1); });
  EXPECT_EQ(r.exposition(),
            "# HELP t_depth Depth\n"
            "# TYPE t_depth gauge\n"
            "t_depth 0.1\n"
            "# HELP t_requests_total Requests\\nby path \\\\ kind\n"
            "# TYPE t_requests_total counter\n"
            "t_requests_total{path=\"a\\\"b\\\\c\\nd\"} 3\n"
            "# HELP t_seconds Durations\n"
            "# TYPE t_seconds histogram\n"
            "t_seconds_bucket{le=\"0.5\"} 2\n"
            "t_seconds_bucket{le=\"1\"} 2\n"
            "t_seconds_bucket{le=\"+Inf\"} 3\n"
            "t_seconds_sum 3.75\n"
            "t_seconds_count 3\n");
  EXPECT_EQ(r.value("t_requests_total", {{"path", "a\"b\\c\nd"}}), 3);
  EXPECT_THROW(r.inc("t_undeclared"), std::logic_error);
  EXPECT_THROW(r.observe("t_depth", {}, 1), std::logic_error);
}

TEST(HttpMetrics, RouteLabelsAreBounded) {
  EXPECT_EQ(service::http_route_label("GET", "/v1/jobs/job-1234/events"), "GET /v1/jobs/{id}/events");
  EXPECT_EQ(service::http_route_label("GET", "/v1/jobs/job-1234/result.csv"), "GET /v1/jobs/{id}/result");
  EXPECT_EQ(service::http_route_label("GET", "/v1/jobs/job-1234/progress"), "GET /v1/jobs/{id}/progress");
  EXPECT_EQ(service::http_route_label("GET", "/v1/jobs/job-1234/field"), "GET /v1/jobs/{id}/field");
  EXPECT_EQ(service::http_route_label("POST", "/v1/meshes"), "POST /v1/meshes");
  EXPECT_EQ(service::http_route_label("GET", "/v1/whatever/x/y"), "GET /v1/other");
  EXPECT_EQ(service::http_route_label("GET", "/assets/index-abc.js"), "GET /assets/*");
  EXPECT_EQ(service::http_route_label("PROPFIND", "/etc/passwd"), "OTHER other");
}

TEST(HttpListener, ServesHttpsWithTheGivenCertificate) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("depath-http-tls-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string cert = (dir / "cert.pem").string(), key = (dir / "key.pem").string();
  const std::string cmd = "openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=localhost "
                          "-addext subjectAltName=IP:127.0.0.1 -keyout " + key + " -out " + cert + " 2>/dev/null";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << "openssl could not make a certificate";

  service::ServerOptions o = quiet_options();
  o.store = "memory";
  o.http_listen = "127.0.0.1:0";
  o.tls_cert = cert;  // the gRPC side's flags serve HTTPS too
  o.tls_key = key;
  service::Server server(o);
  ASSERT_GT(server.http_port(), 0);

  httplib::SSLClient tls("127.0.0.1", server.http_port());
  tls.set_ca_cert_path(cert.c_str());
  tls.enable_server_certificate_verification(true);
  auto res = tls.Get("/healthz");
  ASSERT_TRUE(res) << httplib::to_string(res.error());
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(res->body, "ok\n");

  httplib::Client plain("127.0.0.1", server.http_port());  // plaintext to a TLS port: no answer
  plain.set_read_timeout(2 * time_scale(), 0);
  EXPECT_FALSE(plain.Get("/healthz"));

  o.tls_key = (dir / "missing.pem").string();  // a key that cannot be read: a clear error at start
  try {
    service::Server bad(o);
    ADD_FAILURE() << "started with an unreadable TLS key";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("missing.pem"), std::string::npos) << e.what();
  }
  server.shutdown();
  fs::remove_all(dir);
}

TEST(HttpListener, APortInUseIsRefused) {
  service::ServerOptions o = quiet_options();
  o.store = "memory";
  o.http_listen = "127.0.0.1:0";
  service::Server first(o);
  ASSERT_GT(first.http_port(), 0);
  o.http_listen = "127.0.0.1:" + std::to_string(first.http_port());
  expect_server_refused(o, "cannot listen for HTTP", "the HTTP port of another server, " + o.http_listen);
}

TEST(HttpListener, RefusesBadAddresses) {
  service::ServerOptions o = quiet_options();
  o.store = "memory";
  for (const char* address : {"8080", "127.0.0.1:", "127.0.0.1:99999", "127.0.0.1:http"}) {
    o.http_listen = address;
    expect_server_refused(o, "--http-listen", std::string("--http-listen ") + address);
  }
}

}  // namespace
}  // namespace depath::test
