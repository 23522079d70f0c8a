// SPDX-License-Identifier: MIT
#include "remote_client.hpp"

#include "depath/wire/wire.hpp"

#include <grpcpp/create_channel.h>
#include <grpcpp/security/credentials.h>
#include <grpcpp/support/channel_arguments.h>

#include <arpa/inet.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <random>
#include <thread>

namespace depath::cli {

namespace {

ErrorCode error_code_of(grpc::StatusCode code) {
  switch (code) {
    case grpc::StatusCode::INVALID_ARGUMENT:
    case grpc::StatusCode::ALREADY_EXISTS:
    case grpc::StatusCode::UNAUTHENTICATED:
    case grpc::StatusCode::PERMISSION_DENIED:
    case grpc::StatusCode::OUT_OF_RANGE: return ErrorCode::invalid_argument;
    case grpc::StatusCode::NOT_FOUND: return ErrorCode::not_found;
    case grpc::StatusCode::FAILED_PRECONDITION: return ErrorCode::failed_precondition;
    case grpc::StatusCode::RESOURCE_EXHAUSTED: return ErrorCode::resource_exhausted;
    case grpc::StatusCode::CANCELLED: return ErrorCode::cancelled;
    case grpc::StatusCode::UNAVAILABLE:
    case grpc::StatusCode::DEADLINE_EXCEEDED: return ErrorCode::unavailable;
    default: return ErrorCode::internal;
  }
}

bool retryable(grpc::StatusCode code) {
  return code == grpc::StatusCode::UNAVAILABLE || code == grpc::StatusCode::DEADLINE_EXCEEDED ||
         code == grpc::StatusCode::UNKNOWN || code == grpc::StatusCode::INTERNAL;
}

constexpr size_t kChunkBytes = 1 << 20;
/// Deadline of an upload, and of a mesh lookup once connected (the server may parse the mesh).
constexpr double kMeshLookupSeconds = 600;

/// The wall-clock time `seconds` from now (gRPC deadlines are system_clock time points).
std::chrono::system_clock::time_point from_now(double seconds) {
  return std::chrono::system_clock::now() + std::chrono::duration_cast<std::chrono::system_clock::duration>(
                                                std::chrono::duration<double>(seconds));
}

/// "//authority/rest" -> "rest"; anything else unchanged.
std::string strip_authority(const std::string& s) {
  if (s.rfind("//", 0) != 0) return s;
  const size_t slash = s.find('/', 2);
  return slash == std::string::npos ? std::string() : s.substr(slash + 1);
}

/// Host and port of a dns: target.
std::pair<std::string, std::string> dns_host_port(const std::string& target) {
  const std::string name = strip_authority(target.substr(4));
  std::string host = name;
  std::string port = "443";  // gRPC's default for dns: targets
  if (!name.empty() && name[0] == '[') {
    const size_t close = name.find(']');
    if (close == std::string::npos) throw Error(ErrorCode::invalid_argument, "bad server address '" + target + "'");
    host = name.substr(1, close - 1);
    if (close + 1 < name.size() && name[close + 1] == ':') port = name.substr(close + 2);
  } else if (const size_t colon = name.rfind(':'); colon != std::string::npos && name.find(':') == colon) {
    host = name.substr(0, colon);
    port = name.substr(colon + 1);
  }
  if (host.empty()) throw Error(ErrorCode::invalid_argument, "bad server address '" + target + "'");
  return {host, port};
}

std::vector<std::string> resolve_dns(const std::string& target) {
  const auto [host, port] = dns_host_port(target);
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (const int rc = ::getaddrinfo(host.c_str(), port.c_str(), &hints, &found); rc != 0) {
    throw Error(ErrorCode::unavailable, "cannot resolve '" + host + "' (" + target + "): " + ::gai_strerror(rc));
  }
  std::vector<std::string> out;
  for (const addrinfo* a = found; a; a = a->ai_next) {
    char ip[INET6_ADDRSTRLEN] = "";
    std::string address;
    if (a->ai_family == AF_INET) {
      const auto* sin = reinterpret_cast<const sockaddr_in*>(a->ai_addr);
      ::inet_ntop(AF_INET, &sin->sin_addr, ip, sizeof ip);
      address = "ipv4:" + std::string(ip) + ":" + std::to_string(ntohs(sin->sin_port));
    } else if (a->ai_family == AF_INET6) {
      const auto* sin6 = reinterpret_cast<const sockaddr_in6*>(a->ai_addr);
      ::inet_ntop(AF_INET6, &sin6->sin6_addr, ip, sizeof ip);
      address = "ipv6:[" + std::string(ip) + "]:" + std::to_string(ntohs(sin6->sin6_port));
    } else {
      continue;
    }
    if (std::find(out.begin(), out.end(), address) == out.end()) out.push_back(address);
  }
  ::freeaddrinfo(found);
  if (out.empty()) throw Error(ErrorCode::unavailable, "'" + host + "' (" + target + ") has no addresses");
  return out;
}

bool is_address_list(const std::string& target) {
  return (target.rfind("ipv4:", 0) == 0 || target.rfind("ipv6:", 0) == 0) && target.find(',') != std::string::npos;
}
constexpr double kReconnectSeconds = 60;

}  // namespace

RemoteError::RemoteError(grpc::StatusCode code, const std::string& message)
    : Error(error_code_of(code), message), status_code_(code) {}

void add_remote_options(CLI::App& cmd, RemoteOptions& o) {
  if (const char* env = std::getenv("DEPATH_SERVER"); env && *env) o.server = env;
  if (const char* env = std::getenv("DEPATH_TOKEN"); env && *env) o.token = env;
  cmd.add_option("--server", o.server,
                 "Server address host:port; or several replicas sharing one store: dns:///host:port (all its "
                 "addresses) or ipv4:a:port,b:port, calls spread over them (env DEPATH_SERVER)")
      ->capture_default_str();
  auto* token = cmd.add_option("--token", o.token,
                               "Auth token sent as 'authorization: Bearer TOKEN' (env DEPATH_TOKEN; visible in `ps`: "
                               "prefer --token-file or the environment)");
  cmd.add_option("--token-file", o.token_file, "Read the auth token from this file's first line")
      ->envname("DEPATH_TOKEN_FILE")
      ->excludes(token);
  cmd.add_flag("--tls", o.tls, "Connect with TLS, checking the server against the system's trusted roots");
  cmd.add_option("--tls-ca", o.tls_ca, "Connect with TLS; PEM CA that signed the server's certificate (env DEPATH_TLS_CA)")
      ->envname("DEPATH_TLS_CA");
  cmd.add_option("--tls-cert", o.tls_cert,
                 "PEM client certificate for servers that require mutual TLS (with --tls-key; env DEPATH_TLS_CERT)")
      ->envname("DEPATH_TLS_CERT");
  cmd.add_option("--tls-key", o.tls_key, "PEM private key of --tls-cert (env DEPATH_TLS_KEY)")->envname("DEPATH_TLS_KEY");
  cmd.add_option("--tls-server-name", o.tls_server_name,
                 "Name to check the server's certificate against (default: the host of --server)");
  cmd.add_option("--connect-timeout", o.connect_timeout_seconds, "Seconds to wait for the server")
      ->capture_default_str();
}

std::string read_file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorCode::invalid_argument, "cannot open '" + path + "'");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw Error(ErrorCode::invalid_argument, "cannot read '" + path + "'");
  return bytes;
}

std::vector<std::string> replica_targets(const std::string& target) {
  if (target.rfind("dns:", 0) == 0) return resolve_dns(target);
  if (!is_address_list(target)) return {};
  const std::string scheme = target.substr(0, 5);
  const std::string list = strip_authority(target.substr(5));
  std::vector<std::string> out;
  size_t start = 0;
  for (;;) {
    const size_t comma = list.find(',', start);
    const std::string part = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (!part.empty() && std::find(out.begin(), out.end(), scheme + part) == out.end()) out.push_back(scheme + part);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

std::vector<RemoteOptions> replica_options(const RemoteOptions& options) {
  const std::vector<std::string> targets = replica_targets(options.server);
  if (targets.empty()) return {options};
  std::vector<RemoteOptions> out;
  for (const auto& t : targets) {
    out.push_back(options);
    out.back().server = t;
    // The certificate names the host, not the address it resolved to.
    if (uses_tls(options) && options.tls_server_name.empty() && options.server.rfind("dns:", 0) == 0) {
      out.back().tls_server_name = dns_host_port(options.server).first;
    }
  }
  return out;
}

bool uses_tls(const RemoteOptions& o) {
  return o.tls || !o.tls_ca.empty() || !o.tls_cert.empty() || !o.tls_key.empty();
}

namespace {
std::string read_flag_file(const std::string& flag, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorCode::invalid_argument, flag + " '" + path + "': cannot open the file");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.empty()) throw Error(ErrorCode::invalid_argument, flag + " '" + path + "': the file is empty");
  return bytes;
}

std::string read_token_file(const std::string& path) {
  const std::string text = read_flag_file("--token-file", path);
  const std::string line = text.substr(0, text.find('\n'));
  const size_t first = line.find_first_not_of(" \t\r");
  if (first == std::string::npos) throw Error(ErrorCode::invalid_argument, "--token-file '" + path + "': first line is empty");
  return line.substr(first, line.find_last_not_of(" \t\r") - first + 1);
}

std::shared_ptr<grpc::ChannelCredentials> channel_credentials(const RemoteOptions& o) {
  if (!uses_tls(o)) return grpc::InsecureChannelCredentials();
  if (o.tls_cert.empty() != o.tls_key.empty()) {
    throw Error(ErrorCode::invalid_argument, "--tls-cert and --tls-key go together (give both or neither)");
  }
  grpc::SslCredentialsOptions ssl;
  if (!o.tls_ca.empty()) ssl.pem_root_certs = read_flag_file("--tls-ca", o.tls_ca);  // empty: system roots
  if (!o.tls_cert.empty()) {
    ssl.pem_cert_chain = read_flag_file("--tls-cert", o.tls_cert);
    ssl.pem_private_key = read_flag_file("--tls-key", o.tls_key);
  }
  return grpc::SslCredentials(ssl);
}
}  // namespace

RemoteClient::RemoteClient(const RemoteOptions& options) : options_(options) {
  if (!options_.token_file.empty()) options_.token = read_token_file(options_.token_file);
  grpc::ChannelArguments args;
  if (!options.tls_server_name.empty()) args.SetSslTargetNameOverride(options.tls_server_name);
  args.SetMaxReceiveMessageSize(-1);
  args.SetMaxSendMessageSize(-1);
  // Notice a dead connection during a long watch.
  args.SetInt(GRPC_ARG_KEEPALIVE_TIME_MS, 30000);
  args.SetInt(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, 10000);
  if (options.server.rfind("dns:", 0) == 0 || is_address_list(options.server)) {
    // Fail at once, naming the name, rather than after --connect-timeout of silent retries.
    if (options.server.rfind("dns:", 0) == 0) (void)replica_targets(options.server);
    args.SetLoadBalancingPolicyName("round_robin");
  }
  channel_ = grpc::CreateCustomChannel(options.server, channel_credentials(options), args);
  meshes_ = v1::MeshService::NewStub(channel_);
  jobs_ = v1::JobService::NewStub(channel_);
}

std::unique_ptr<grpc::ClientContext> RemoteClient::context(double timeout_seconds) const {
  auto ctx = std::make_unique<grpc::ClientContext>();
  if (!options_.token.empty()) ctx->AddMetadata("authorization", "Bearer " + options_.token);
  if (timeout_seconds > 0) ctx->set_deadline(from_now(timeout_seconds));
  ctx->set_wait_for_ready(false);
  return ctx;
}

void RemoteClient::check(const grpc::Status& status, const std::string& doing) const {
  if (status.ok()) return;
  std::string message = doing + ": " + wire::status_code_name(status.error_code()) + ": " + status.error_message();
  if (status.error_code() == grpc::StatusCode::UNAVAILABLE && status.error_message().find("shutting down") == std::string::npos) {
    message = doing + ": cannot reach the server at " + options_.server + " (" + status.error_message() + ")";
  } else if (status.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED) {
    message = doing + ": no answer from the server at " + options_.server + " in time (is it running? --connect-timeout)";
  }
  throw RemoteError(status.error_code(), message);
}

v1::MeshInfo RemoteClient::upload(const std::string& path, const std::string& format) {
  const std::string bytes = read_file_bytes(path);
  auto ctx = context(kMeshLookupSeconds);
  ctx->set_wait_for_ready(true);
  v1::MeshInfo info;
  auto writer = meshes_->UploadMesh(ctx.get(), &info);
  v1::UploadMeshRequest request;
  auto* header = request.mutable_header();
  header->set_file_name(std::filesystem::path(path).filename().string());
  header->set_size_bytes(bytes.size());
  header->set_format(format);
  bool ok = writer->Write(request);
  for (size_t offset = 0; ok && offset < bytes.size(); offset += kChunkBytes) {
    request.Clear();
    request.set_chunk(bytes.substr(offset, kChunkBytes));
    ok = writer->Write(request);
  }
  if (ok) writer->WritesDone();
  check(writer->Finish(), "uploading " + path);
  return info;
}

v1::MeshInfo RemoteClient::ensure_mesh(const std::string& path, bool* uploaded, const std::string& format) {
  const std::string id = wire::sha256_hex(read_file_bytes(path));
  // --connect-timeout bounds the wait for the server, not the lookup: a mesh the server stored
  // before a restart is reloaded (parsed) for it, which takes as long as an upload's parse.
  const bool connected = channel_->WaitForConnected(from_now(options_.connect_timeout_seconds));
  auto ctx = context(connected ? kMeshLookupSeconds : options_.connect_timeout_seconds);
  ctx->set_wait_for_ready(true);
  v1::GetMeshRequest request;
  request.set_id(id);
  v1::MeshInfo info;
  grpc::Status status = meshes_->GetMesh(ctx.get(), request, &info);
  if (status.ok()) {
    if (uploaded) *uploaded = false;
    return info;
  }
  if (status.error_code() != grpc::StatusCode::NOT_FOUND) check(status, "looking up mesh " + id);
  if (uploaded) *uploaded = true;
  return upload(path, format);
}

v1::JobEvent RemoteClient::watch(const std::string& job_id, uint64_t after_sequence,
                                 const std::function<void(const v1::JobEvent&)>& on_event,
                                 const std::atomic<bool>* cancel_requested) {
  uint64_t cursor = after_sequence;
  bool reconnecting = false;
  auto give_up_at = std::chrono::steady_clock::now() + std::chrono::duration<double>(kReconnectSeconds);
  double backoff = 0.2;
  std::atomic<bool> done{false};
  std::thread canceller;
  if (cancel_requested) {
    canceller = std::thread([&] {
      while (!done.load()) {
        if (cancel_requested->load()) {
          auto ctx = context(10);
          v1::CancelJobRequest req;
          req.set_job_id(job_id);
          v1::JobInfo info;
          jobs_->CancelJob(ctx.get(), req, &info);  // the watch reports the outcome
          return;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
    });
  }
  struct Joiner {
    std::atomic<bool>& done;
    std::thread& t;
    ~Joiner() {
      done = true;
      if (t.joinable()) t.join();
    }
  } joiner{done, canceller};

  for (;;) {
    auto ctx = context();  // fails fast while the server is unreachable; we retry below
    v1::WatchJobRequest request;
    request.set_job_id(job_id);
    request.set_after_sequence(cursor);
    auto reader = jobs_->WatchJob(ctx.get(), request);
    v1::JobEvent event;
    std::optional<v1::JobEvent> terminal;
    while (reader->Read(&event)) {
      if (reconnecting) {
        std::fprintf(stderr, "depath: reconnected to %s; watching job %s again\n", options_.server.c_str(),
                     job_id.c_str());
        reconnecting = false;
      }
      cursor = event.sequence();
      backoff = 0.2;
      give_up_at = std::chrono::steady_clock::now() + std::chrono::duration<double>(kReconnectSeconds);
      on_event(event);
      if (event.has_state() && wire::is_terminal(event.state().state())) terminal = event;
    }
    const grpc::Status status = reader->Finish();
    if (terminal) return *terminal;
    if (!status.ok() && !retryable(status.error_code())) check(status, "watching job " + job_id);
    if (std::chrono::steady_clock::now() > give_up_at) {
      check(status.ok() ? grpc::Status(grpc::StatusCode::UNAVAILABLE, "stream ended early") : status,
            "watching job " + job_id + " (gave up reconnecting)");
    }
    if (!reconnecting) {  // a restarting server (or a replica going away): say so, keep going
      std::fprintf(stderr, "depath: lost the connection to %s (%s); reconnecting, the job goes on...\n",
                   options_.server.c_str(),
                   status.ok() ? "stream ended" : wire::status_code_name(status.error_code()));
      reconnecting = true;
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(backoff));
    backoff = std::min(2.0, backoff * 2);
  }
}

}  // namespace depath::cli
