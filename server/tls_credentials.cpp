// SPDX-License-Identifier: MIT
#include "tls_credentials.hpp"

#include <grpcpp/security/tls_certificate_provider.h>
#include <grpcpp/security/tls_credentials_options.h>
#include <openssl/bio.h>
#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/x509.h>

#include <cmath>
#include <fstream>
#include <iterator>

#include "depath/util/error.hpp"

namespace depath::service {

namespace {

[[noreturn]] void bad(const std::string& what) { throw Error(ErrorCode::invalid_argument, what); }

std::string read_pem(const std::string& flag, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) bad(flag + " '" + path + "': cannot open the file");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.empty()) bad(flag + " '" + path + "': the file is empty");
  return bytes;
}

std::string openssl_error() {
  const unsigned long e = ERR_get_error();
  ERR_clear_error();
  if (e == 0) return "no PEM data found";
  char buf[256];
  ERR_error_string_n(e, buf, sizeof buf);
  return buf;
}

struct BioDeleter {
  void operator()(BIO* b) const { BIO_free(b); }
};
struct X509Deleter {
  void operator()(X509* x) const { X509_free(x); }
};
struct KeyDeleter {
  void operator()(EVP_PKEY* k) const { EVP_PKEY_free(k); }
};
using BioPtr = std::unique_ptr<BIO, BioDeleter>;
using X509Ptr = std::unique_ptr<X509, X509Deleter>;

BioPtr memory_bio(const std::string& pem) {
  return BioPtr(BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size())));
}

/// The first certificate of a PEM file (the leaf of a chain); throws naming the flag.
X509Ptr first_certificate(const std::string& flag, const std::string& path) {
  const std::string pem = read_pem(flag, path);
  BioPtr bio = memory_bio(pem);
  X509Ptr cert(PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr));
  if (!cert) bad(flag + " '" + path + "' holds no PEM certificate (" + openssl_error() + ")");
  return cert;
}

/// Fails early with a clear message instead of gRPC refusing every handshake later.
void check_files(const ServerOptions& o) {
  if (o.tls_cert.empty() != o.tls_key.empty())
    bad("--tls-cert and --tls-key go together (give both or neither)");
  if (o.tls_cert.empty()) {
    if (!o.tls_client_ca.empty())
      bad("--tls-client-ca needs --tls-cert and --tls-key (mutual TLS is TLS first)");
    return;
  }
  if (!(o.tls_reload_seconds >= 1) || !std::isfinite(o.tls_reload_seconds))
    bad("--tls-reload-seconds must be >= 1");
  const X509Ptr cert = first_certificate("--tls-cert", o.tls_cert);
  const std::string key_pem = read_pem("--tls-key", o.tls_key);
  BioPtr bio = memory_bio(key_pem);
  std::unique_ptr<EVP_PKEY, KeyDeleter> key(PEM_read_bio_PrivateKey(bio.get(), nullptr, nullptr, nullptr));
  if (!key)
    bad("--tls-key '" + o.tls_key + "' holds no unencrypted PEM private key (" + openssl_error() + ")");
  if (X509_check_private_key(cert.get(), key.get()) != 1) {
    ERR_clear_error();
    bad("--tls-key '" + o.tls_key + "' is not the private key of the certificate in --tls-cert '" +
        o.tls_cert + "'");
  }
  if (!o.tls_client_ca.empty()) (void)first_certificate("--tls-client-ca", o.tls_client_ca);
}

}  // namespace

std::shared_ptr<grpc::ServerCredentials> make_server_credentials(const ServerOptions& o) {
  check_files(o);
  if (o.tls_cert.empty()) return grpc::InsecureServerCredentials();
  namespace gx = grpc::experimental;
  const auto interval = static_cast<unsigned>(std::min(o.tls_reload_seconds, 86400.0 * 365));
  auto provider = o.tls_client_ca.empty()
                      ? std::make_shared<gx::FileWatcherCertificateProvider>(o.tls_key, o.tls_cert, interval)
                      : std::make_shared<gx::FileWatcherCertificateProvider>(o.tls_key, o.tls_cert,
                                                                             o.tls_client_ca, interval);
  gx::TlsServerCredentialsOptions options(provider);
  options.watch_identity_key_cert_pairs();
  if (o.tls_client_ca.empty()) {
    options.set_cert_request_type(GRPC_SSL_DONT_REQUEST_CLIENT_CERTIFICATE);
  } else {
    options.watch_root_certs();
    options.set_cert_request_type(GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY);
  }
  return gx::TlsServerCredentials(options);
}

}  // namespace depath::service
