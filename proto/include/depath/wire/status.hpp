// SPDX-License-Identifier: MIT
// Errors on the wire: the core's ErrorCode <-> gRPC status codes.
//
// Guarantees: every ErrorCode maps to one gRPC code (unknown ones to INTERNAL), so a client
// sees the same code whether the job ran locally or on depathd.
#pragma once

#include "depath/util/error.hpp"

#include <grpcpp/support/status.h>

namespace depath::wire {

grpc::StatusCode status_code(ErrorCode code);
inline grpc::Status to_status(const Error& e) { return {status_code(e.code()), e.what()}; }
/// Short name of a status code ("NOT_FOUND", ...).
const char* status_code_name(grpc::StatusCode code);

}  // namespace depath::wire
