// SPDX-License-Identifier: MIT
// depathd's transport credentials: plaintext, TLS (--tls-cert/--tls-key) or mutual TLS
// (--tls-client-ca: client certificates required and verified against that CA bundle).
#pragma once

#include <grpcpp/security/server_credentials.h>

#include <memory>

#include "options.hpp"

namespace depath::service {

/// Insecure credentials when options.tls_cert is empty; otherwise TLS credentials whose
/// certificate, key and client CA files are re-read every options.tls_reload_seconds, so a
/// rotated certificate is served to new connections without a restart (gRPC keeps the
/// previous pair while the files do not hold a matching one).
/// Throws depath::Error(invalid_argument) naming the flag when a file cannot be read or parsed,
/// the key does not match the certificate, or only one of --tls-cert / --tls-key is given.
std::shared_ptr<grpc::ServerCredentials> make_server_credentials(const ServerOptions& options);

}  // namespace depath::service
