// SPDX-License-Identifier: MIT
// Who may call depathd and how often: bearer tokens (any of several, compared in constant time),
// a per-peer limit on failed token checks, and a per-client request rate. Every service call
// (and reflection) goes through check(); the standard health service does not.
#pragma once

#include <grpcpp/server_context.h>
#include <grpcpp/support/status.h>
#include <grpcpp/support/string_ref.h>

#include <array>
#include <chrono>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "log.hpp"
#include "options.hpp"

namespace depath::service {

/// Token buckets by key: `burst` at once, refilled at `rate` per second. Keys whose bucket is
/// full again are dropped when the map grows, so its size stays bounded by the active keys.
class RateLimiter {
 public:
  using Clock = std::chrono::steady_clock;
  RateLimiter(double rate, double burst) : rate_(rate), burst_(burst) {}
  /// Whether `key` has a whole token now (without taking it).
  bool available(const std::string& key, Clock::time_point now);
  /// Takes a token if there is one; false when the bucket is empty.
  bool take(const std::string& key, Clock::time_point now);
  /// Seconds until `key` has a whole token again (0 if it has one).
  double wait_seconds(const std::string& key, Clock::time_point now);

 private:
  double& level(const std::string& key, Clock::time_point now);
  struct Bucket {
    double tokens;
    Clock::time_point at;
  };
  double rate_, burst_;
  std::unordered_map<std::string, Bucket> buckets_;
};

class AccessGuard {
 public:
  using Metadata = std::multimap<grpc::string_ref, grpc::string_ref>;

  /// Hashes options.auth_tokens (the tokens themselves are not kept).
  AccessGuard(const ServerOptions& options, Log& log);

  bool auth_required() const { return !token_digests_.empty(); }

  /// Admission of one call of `method` (a name for the logs, e.g. "SubmitJob") from `peer`
  /// (grpc's peer string, "ipv4:1.2.3.4:5678"). With tokens configured: UNAUTHENTICATED for a
  /// missing or wrong token (logged with method and peer, never the token), RESOURCE_EXHAUSTED
  /// while the peer's failed attempts exceed --auth-failure-burst / --auth-failure-rate (then
  /// not even a right token is checked, so guessing gains nothing). Then RESOURCE_EXHAUSTED
  /// past --max-requests-per-second-per-client. On OK, `client` (if given) is the caller's
  /// identity for per-client quotas: "token #N" (its position among the configured tokens) or,
  /// without tokens, "certificate CN" for a client verified by mutual TLS (`certificate_name`,
  /// its certificate's common name), else "peer HOST".
  grpc::Status check(std::string_view method, const Metadata& metadata, const std::string& peer,
                     std::string* client = nullptr, const std::string& certificate_name = {});

  /// The common name of the client certificate mutual TLS verified on this call ("" if none).
  static std::string certificate_name(const grpc::ServerContextBase& ctx);

  /// "1.2.3.4" from "ipv4:1.2.3.4:5678", "::1" from "ipv6:[::1]:5678" (the port varies per connection).
  static std::string peer_host(const std::string& peer);

 private:
  using Digest = std::array<unsigned char, 32>;
  static Digest digest(std::string_view bytes);
  /// Index of the matching token or -1; always compares against every token, in constant time.
  int match(std::string_view token) const;

  const ServerOptions& options_;
  Log& log_;
  std::vector<Digest> token_digests_;
  std::mutex mutex_;
  RateLimiter failures_;  // per peer host
  RateLimiter requests_;  // per client
};

}  // namespace depath::service
