// SPDX-License-Identifier: MIT
// Puts gRPC server reflection (a gRPC-provided service, registered by its plugin) behind the
// same token check as depath's own services when authentication is on.
#pragma once

#include <grpcpp/support/server_interceptor.h>

#include <memory>

#include "access_guard.hpp"

namespace depath::service {

/// An interceptor factory for the server builder. For reflection calls (/grpc.reflection.*)
/// without a valid token (AccessGuard::check), every response message is replaced by an empty
/// one and the call ends with the check's status (UNAUTHENTICATED / RESOURCE_EXHAUSTED): the
/// caller learns nothing about the services. Other methods are not intercepted.
std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface> reflection_guard(AccessGuard& access);

}  // namespace depath::service
