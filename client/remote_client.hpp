// SPDX-License-Identifier: MIT
// The network client's plumbing: a channel to depathd (host:port, or a multi-replica target:
// dns:///host:port or ipv4:a:p,b:p, calls spread over the replicas of a shared store), calls
// with the auth token, mesh upload, job watching that resumes after a dropped connection, and
// gRPC statuses turned into depath::Error messages.
#pragma once

#include "depath/util/error.hpp"
#include "depath/v1/job.grpc.pb.h"
#include "depath/v1/mesh.grpc.pb.h"

#include <grpcpp/channel.h>
#include <grpcpp/client_context.h>
#include <CLI/CLI.hpp>

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace depath::cli {

/// Flags every network subcommand takes.
struct RemoteOptions {
  std::string server = "localhost:50051";  ///< host:port, or dns:///host:port / ipv4:a:p,b:p (several replicas)
  std::string token;                       ///< sent as `authorization: Bearer TOKEN`
  std::string token_file;                  ///< or the token read from this file (its first line)
  bool tls = false;                        ///< TLS even without the files below (system roots)
  std::string tls_ca;                      ///< PEM CA bundle that signed the server's certificate
  std::string tls_cert;                    ///< PEM client certificate (mutual TLS), with tls_key
  std::string tls_key;
  std::string tls_server_name;             ///< name checked in the server's certificate (default: the host)
  double connect_timeout_seconds = 10;
  bool json = false;
};

void add_remote_options(CLI::App& cmd, RemoteOptions& options);

/// Whether the options ask for TLS (--tls or any --tls-* file).
bool uses_tls(const RemoteOptions& options);

/// The single-address targets behind a multi-replica target, one per replica:
/// `dns:///host:port` / `dns:host:port` / `dns://authority/host:port` are resolved here
/// (getaddrinfo, all A/AAAA records) into `ipv4:1.2.3.4:port` / `ipv6:[::1]:port`, and a
/// comma-separated `ipv4:a:p,b:p` / `ipv6:...` list is split. Any other target (host:port,
/// a single ipv4:/ipv6: address, unix:) returns an empty vector: it is used as it is.
/// Throws Error(unavailable) when a dns name does not resolve.
std::vector<std::string> replica_targets(const std::string& target);

/// `options` for each replica (`server` replaced), or just `options` for a single-address target.
std::vector<RemoteOptions> replica_options(const RemoteOptions& options);

/// Thrown for a failed call: the gRPC code and the server's message.
class RemoteError : public Error {
 public:
  RemoteError(grpc::StatusCode code, const std::string& message);
  grpc::StatusCode status_code() const { return status_code_; }

 private:
  grpc::StatusCode status_code_;
};

class RemoteClient {
 public:
  /// Reads --token-file and the TLS files; throws Error(invalid_argument) naming the flag
  /// when one cannot be read (or only one of --tls-cert / --tls-key is given).
  explicit RemoteClient(const RemoteOptions& options);

  /// A context with the token and, if > 0, a deadline.
  std::unique_ptr<grpc::ClientContext> context(double timeout_seconds = 0) const;
  /// Throws RemoteError (message prefixed with what was being done) unless ok.
  void check(const grpc::Status& status, const std::string& doing) const;

  v1::MeshService::Stub& meshes() { return *meshes_; }
  v1::JobService::Stub& jobs() { return *jobs_; }
  const std::shared_ptr<grpc::Channel>& channel() const { return channel_; }
  const RemoteOptions& options() const { return options_; }

  /// Uploads a mesh file in 1 MiB chunks (always sends the bytes). `format` ("obj", "off",
  /// "ply", "stl") goes in the header; empty: the server takes it from the file name.
  v1::MeshInfo upload(const std::string& path, const std::string& format = "");
  /// The server's info for the file's mesh id, uploading the file only if the server lacks
  /// it. `uploaded` tells whether bytes were sent.
  v1::MeshInfo ensure_mesh(const std::string& path, bool* uploaded = nullptr, const std::string& format = "");

  /// Streams the job's events after `after_sequence` to `on_event` until the terminal
  /// state; reconnects (with backoff) after UNAVAILABLE / dropped connections and resumes
  /// from the last sequence seen. Returns the terminal state event's job event.
  /// `cancel_requested`, if set, is polled: once true, CancelJob is sent (once).
  v1::JobEvent watch(const std::string& job_id, uint64_t after_sequence,
                     const std::function<void(const v1::JobEvent&)>& on_event,
                     const std::atomic<bool>* cancel_requested = nullptr);

 private:
  RemoteOptions options_;
  std::shared_ptr<grpc::Channel> channel_;
  std::unique_ptr<v1::MeshService::Stub> meshes_;
  std::unique_ptr<v1::JobService::Stub> jobs_;
};

/// Reads a whole file; Error(invalid_argument) naming it when it cannot be read.
std::string read_file_bytes(const std::string& path);

}  // namespace depath::cli
