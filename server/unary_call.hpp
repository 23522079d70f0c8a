// SPDX-License-Identifier: MIT
// Runs a unary RPC body on the callback API: admission/auth, exceptions -> status, Finish.
#pragma once

#include "service_context.hpp"
#include "service_error.hpp"

#include <grpcpp/grpcpp.h>

namespace depath::service {

/// `admit`: also refuse new work while shutting down (UNAVAILABLE); otherwise only check
/// the token. Any exception thrown by `fn` becomes the matching status.
template <class Fn>
grpc::ServerUnaryReactor* unary(ServiceContext& ctx, grpc::CallbackServerContext* context, bool admit, Fn&& fn) {
  auto* reactor = context->DefaultReactor();
  grpc::Status status = admit ? ctx.admit(context) : ctx.authenticate(context);
  if (status.ok()) {
    try {
      fn();
    } catch (...) {
      status = current_exception_status();
    }
  }
  reactor->Finish(status);
  return reactor;
}

}  // namespace depath::service
