// SPDX-License-Identifier: MIT
// Runs a unary RPC body on the callback API: admission/auth, exceptions -> status, Finish.
#pragma once

#include "service_context.hpp"
#include "service_error.hpp"

#include <grpcpp/grpcpp.h>

#include <string>
#include <string_view>
#include <type_traits>

namespace depath::service {

/// `method` names the call in logs. `admit`: also refuse new work while shutting down (UNAVAILABLE); otherwise only check
/// the token. `fn` may take the caller's identity (AccessGuard::check). Any exception thrown by `fn` becomes the matching status.
template <class Fn>
grpc::ServerUnaryReactor* unary(ServiceContext& ctx, grpc::CallbackServerContext* context, std::string_view method,
                                bool admit, Fn&& fn) {
  auto* reactor = context->DefaultReactor();
  std::string client;
  grpc::Status status = admit ? ctx.admit(context, method, &client) : ctx.authenticate(context, method, &client);
  if (status.ok()) {
    try {
      if constexpr (std::is_invocable_v<Fn, const std::string&>) fn(client);
      else fn();
    } catch (...) {
      status = current_exception_status();
    }
  }
  reactor->Finish(status);
  return reactor;
}

}  // namespace depath::service
