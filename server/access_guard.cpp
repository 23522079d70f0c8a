// SPDX-License-Identifier: MIT
#include "access_guard.hpp"

#include <openssl/crypto.h>
#include <openssl/sha.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace depath::service {

namespace {
constexpr size_t kMaxTrackedKeys = 4096;
constexpr std::string_view kBearer = "Bearer ";

std::string format_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}
}  // namespace

double& RateLimiter::level(const std::string& key, Clock::time_point now) {
  if (buckets_.size() >= kMaxTrackedKeys && buckets_.find(key) == buckets_.end()) {
    for (auto it = buckets_.begin(); it != buckets_.end();) {
      const double refilled =
          it->second.tokens + rate_ * std::chrono::duration<double>(now - it->second.at).count();
      it = refilled >= burst_ ? buckets_.erase(it) : std::next(it);
    }
  }
  auto [it, fresh] = buckets_.try_emplace(key, Bucket{burst_, now});
  Bucket& b = it->second;
  if (!fresh) {
    b.tokens = std::min(burst_, b.tokens + rate_ * std::chrono::duration<double>(now - b.at).count());
    b.at = now;
  }
  return b.tokens;
}

bool RateLimiter::available(const std::string& key, Clock::time_point now) { return level(key, now) >= 1.0; }

bool RateLimiter::take(const std::string& key, Clock::time_point now) {
  double& tokens = level(key, now);
  if (tokens < 1.0) return false;
  tokens -= 1.0;
  return true;
}

double RateLimiter::wait_seconds(const std::string& key, Clock::time_point now) {
  const double tokens = level(key, now);
  return tokens >= 1.0 || rate_ <= 0 ? 0.0 : (1.0 - tokens) / rate_;
}

AccessGuard::AccessGuard(const ServerOptions& options, Log& log)
    : options_(options),
      log_(log),
      failures_(options.auth_failure_rate, std::max(1.0, options.auth_failure_burst)),
      requests_(options.max_requests_per_second_per_client,
                std::max(1.0, options.max_requests_per_second_per_client)) {
  for (const auto& t : options.auth_tokens) token_digests_.push_back(digest(t));
}

AccessGuard::Digest AccessGuard::digest(std::string_view bytes) {
  Digest d;
  SHA256(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), d.data());
  return d;
}

int AccessGuard::match(std::string_view token) const {
  // Equal-length digests compared with CRYPTO_memcmp against every token: the time taken
  // depends neither on how much of a token was right nor on which one matched.
  const Digest got = digest(token);
  int found = -1;
  for (size_t i = 0; i < token_digests_.size(); ++i) {
    const int differs = CRYPTO_memcmp(got.data(), token_digests_[i].data(), got.size());
    const int hit = static_cast<int>(differs == 0) & static_cast<int>(found < 0);
    found = hit ? static_cast<int>(i) : found;
  }
  return found;
}

std::string AccessGuard::peer_host(const std::string& peer) {
  if (peer.rfind("ipv4:", 0) != 0 && peer.rfind("ipv6:", 0) != 0) return peer;  // unix: etc.
  std::string host = peer.substr(5);
  if (!host.empty() && host.front() == '[') {
    const auto close = host.find(']');
    return close == std::string::npos ? host : host.substr(1, close - 1);
  }
  const auto colon = host.rfind(':');
  if (colon != std::string::npos) host.resize(colon);
  return host;
}

std::string AccessGuard::certificate_name(const grpc::ServerContextBase& ctx) {
  const auto auth = ctx.auth_context();
  if (!auth || !auth->IsPeerAuthenticated()) return {};
  const auto names = auth->FindPropertyValues("x509_common_name");
  return names.empty() ? std::string() : std::string(names.front().data(), names.front().size());
}

grpc::Status AccessGuard::check(std::string_view method, const Metadata& metadata, const std::string& peer,
                                std::string* client, const std::string& certificate_name) {
  const auto now = RateLimiter::Clock::now();
  const std::string host = peer_host(peer);
  std::string who = certificate_name.empty() ? "peer " + host : "certificate " + certificate_name;
  if (auth_required()) {
    {
      std::lock_guard lock(mutex_);
      if (!failures_.available(host, now)) {
        return {grpc::StatusCode::RESOURCE_EXHAUSTED,
                "too many failed authentication attempts from " + host + " (--auth-failure-burst " +
                    format_number(options_.auth_failure_burst) + ", then --auth-failure-rate " +
                    format_number(options_.auth_failure_rate) + " per second); retry in " +
                    format_number(std::ceil(failures_.wait_seconds(host, now))) + " s"};
      }
    }
    auto it = metadata.find("authorization");
    std::string_view value =
        it == metadata.end() ? std::string_view{} : std::string_view(it->second.data(), it->second.size());
    const bool bearer = value.substr(0, kBearer.size()) == kBearer;
    const int index = bearer ? match(value.substr(kBearer.size())) : -1;
    if (index < 0) {
      const char* reason = it == metadata.end() ? "missing 'authorization: Bearer TOKEN' metadata"
                           : bearer             ? "invalid token in 'authorization' metadata"
                                                : "'authorization' metadata is not 'Bearer TOKEN'";
      bool now_blocked;
      {
        std::lock_guard lock(mutex_);
        failures_.take(host, now);
        now_blocked = !failures_.available(host, now);
      }
      log_.warn("auth.failed", {{"method", std::string(method)}, {"peer", peer}, {"reason", reason}});
      if (now_blocked)
        log_.warn("auth.peer_limited", {{"peer", host}, {"rate_per_second", options_.auth_failure_rate}});
      return {grpc::StatusCode::UNAUTHENTICATED, std::string(reason) + " (server requires a token)"};
    }
    who = "token #" + std::to_string(index + 1);
  }
  if (options_.max_requests_per_second_per_client > 0) {
    std::lock_guard lock(mutex_);
    if (!requests_.take(who, now)) {
      return {grpc::StatusCode::RESOURCE_EXHAUSTED,
              "client " + who + " exceeds " + format_number(options_.max_requests_per_second_per_client) +
                  " requests per second (--max-requests-per-second-per-client); slow down"};
    }
  }
  if (client) *client = std::move(who);
  return grpc::Status::OK;
}

}  // namespace depath::service
