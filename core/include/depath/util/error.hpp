// SPDX-License-Identifier: MIT
// Errors that the core reports to its callers (CLI, server, tests).
//
// One exception type with a code; the server maps each code to a gRPC status
// (proto/include/depath/wire/status.hpp), the CLI to an exit status. Messages name the
// problem (file, field, value) so that a user can fix it.
#pragma once

#include <stdexcept>
#include <string>

namespace depath {

/// Category of a failure; the server maps each to a gRPC status code.
enum class ErrorCode {
  invalid_argument,     ///< bad mesh, bad job spec, out-of-range option
  not_found,            ///< unknown mesh or job
  failed_precondition,  ///< well-formed request that cannot be satisfied (no path s->t)
  resource_exhausted,   ///< a configured limit was hit
  cancelled,            ///< the caller cancelled the work
  unavailable,          ///< shutting down
  internal,             ///< a bug: an invariant did not hold
};

/// Exception thrown by the core; `what()` names the problem in words a user understands.
class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  ErrorCode code() const noexcept { return code_; }

 private:
  ErrorCode code_;
};

/// Short lowercase name of a code ("invalid_argument", ...), used in logs and JSON.
const char* error_code_name(ErrorCode code) noexcept;

}  // namespace depath
