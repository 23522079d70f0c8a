// SPDX-License-Identifier: MIT
// Runs a unary RPC body on the callback API: admission/auth, exceptions -> status, Finish.
// unary() runs it on gRPC's callback thread; unary_blocking() on the blocking queue, for
// bodies that may parse a mesh (gRPC's few callback threads also answer health and every
// other call, so they must never wait on a parse).
#pragma once

#include "grpc_handoff.hpp"
#include "service_context.hpp"
#include "service_error.hpp"

#include <grpcpp/grpcpp.h>

#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

namespace depath::service {

namespace detail {
/// Runs `fn` (given the caller's identity if it takes one); any exception becomes its status.
template <class Fn>
grpc::Status run_unary_body(Fn& fn, const std::string& client) {
  try {
    if constexpr (std::is_invocable_v<Fn&, const std::string&>) fn(client);
    else fn();
  } catch (...) {
    return current_exception_status();
  }
  return grpc::Status::OK;
}

/// The reactor of a unary call finished from another thread. Unlike DefaultReactor, its
/// OnDone tells TSan (grpc_handoff.hpp) that gRPC's clean-up of the call, which destroys the
/// reply on gRPC's thread right after OnDone, comes after the reply was written.
class FinishedElsewhere final : public grpc::ServerUnaryReactor {
 public:
  void finish(const grpc::Status& status) { finish_from_our_thread(*this, status); }
  void OnCancel() override { grpc_reaction(this); }  // the task still finishes the call
  void OnDone() override {
    grpc_reaction(this);
    delete this;
  }
};

inline grpc::Status check_call(ServiceContext& ctx, grpc::CallbackServerContext* context, std::string_view method,
                               bool admit, std::string* client) {
  return admit ? ctx.admit(context, method, client) : ctx.authenticate(context, method, client);
}
}  // namespace detail

/// `method` names the call in logs. `admit`: also refuse new work while shutting down (UNAVAILABLE); otherwise only check
/// the token. `fn` may take the caller's identity (AccessGuard::check). Any exception thrown by `fn` becomes the matching status.
template <class Fn>
grpc::ServerUnaryReactor* unary(ServiceContext& ctx, grpc::CallbackServerContext* context, std::string_view method,
                                bool admit, Fn&& fn) {
  auto* reactor = context->DefaultReactor();
  std::string client;
  grpc::Status status = detail::check_call(ctx, context, method, admit, &client);
  if (status.ok()) status = detail::run_unary_body(fn, client);
  reactor->Finish(status);
  return reactor;
}

/// As unary(), but `fn` runs later on ctx.blocking, which finishes the call. The call holds
/// one of ServiceContext::park()'s places while it waits (RESOURCE_EXHAUSTED when none is
/// left), so the parked calls are bounded like uploads. `fn` is moved to the queue: it must
/// capture by value (the handler's pointer arguments — request, reply, context — stay valid
/// until the call is finished; the handler's locals do not).
template <class Fn>
grpc::ServerUnaryReactor* unary_blocking(ServiceContext& ctx, grpc::CallbackServerContext* context,
                                         std::string_view method, bool admit, Fn fn) {
  auto* reactor = new detail::FinishedElsewhere;
  std::string client;
  grpc::Status status = detail::check_call(ctx, context, method, admit, &client);
  if (status.ok()) status = ctx.park();
  if (!status.ok()) {
    reactor->finish(status);
    return reactor;
  }
  ctx.blocking.post([&ctx, reactor, client = std::move(client), fn = std::move(fn)]() mutable {
    const grpc::Status s = detail::run_unary_body(fn, client);
    ctx.unpark();
    reactor->finish(s);
  });
  return reactor;
}

}  // namespace depath::service
