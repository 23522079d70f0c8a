// SPDX-License-Identifier: MIT
// Errors of the service layer that have no core ErrorCode (ALREADY_EXISTS, UNAUTHENTICATED),
// and the one place that turns any exception into a gRPC status.
#pragma once

#include "depath/util/error.hpp"
#include "depath/wire/wire.hpp"

#include <grpcpp/support/status.h>

#include <exception>
#include <stdexcept>
#include <string>

namespace depath::service {

class ServiceError : public std::runtime_error {
 public:
  ServiceError(grpc::StatusCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  grpc::StatusCode code() const { return code_; }

 private:
  grpc::StatusCode code_;
};

/// Throws a failed status as a ServiceError (its code and message); an OK status passes.
inline void throw_if_error(const grpc::Status& status) {
  if (!status.ok()) throw ServiceError(status.error_code(), status.error_message());
}

/// Status for the exception being handled (call inside a catch block).
inline grpc::Status current_exception_status() {
  try {
    throw;
  } catch (const ServiceError& e) {
    return {e.code(), e.what()};
  } catch (const Error& e) {
    return wire::to_status(e);
  } catch (const std::bad_alloc&) {
    return {grpc::StatusCode::RESOURCE_EXHAUSTED, "out of memory"};
  } catch (const std::exception& e) {
    return {grpc::StatusCode::INTERNAL, std::string("internal error: ") + e.what()};
  } catch (...) {
    return {grpc::StatusCode::INTERNAL, "internal error"};
  }
}

}  // namespace depath::service
