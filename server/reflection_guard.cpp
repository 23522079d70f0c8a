// SPDX-License-Identifier: MIT
#include "reflection_guard.hpp"

#include <grpcpp/server_context.h>
#include <grpcpp/support/byte_buffer.h>
#include <grpcpp/support/interceptor.h>
#include <grpcpp/support/slice.h>

#include <string_view>

namespace depath::service {

namespace {

using grpc::experimental::InterceptionHookPoints;

class ReflectionInterceptor final : public grpc::experimental::Interceptor {
 public:
  ReflectionInterceptor(AccessGuard& access, grpc::experimental::ServerRpcInfo* info)
      : access_(access), info_(info) {}

  void Intercept(grpc::experimental::InterceptorBatchMethods* methods) override {
    if (methods->QueryInterceptionHookPoint(InterceptionHookPoints::POST_RECV_INITIAL_METADATA)) {
      denied_ = access_.check("ServerReflectionInfo", *methods->GetRecvInitialMetadata(),
                              info_->server_context()->peer());  // the identity is not needed here
    }
    if (!denied_.ok()) {
      if (methods->QueryInterceptionHookPoint(InterceptionHookPoints::PRE_SEND_MESSAGE)) {
        if (grpc::ByteBuffer* out = methods->GetSerializedSendMessage()) {
          grpc::Slice empty("", 0);
          *out = grpc::ByteBuffer(&empty, 1);  // an empty (all defaults) response
        }
      }
      if (methods->QueryInterceptionHookPoint(InterceptionHookPoints::PRE_SEND_STATUS)) {
        methods->ModifySendStatus(denied_);
      }
    }
    methods->Proceed();
  }

 private:
  AccessGuard& access_;
  grpc::experimental::ServerRpcInfo* info_;
  grpc::Status denied_;  // OK until the metadata says otherwise
};

class ReflectionGuardFactory final : public grpc::experimental::ServerInterceptorFactoryInterface {
 public:
  explicit ReflectionGuardFactory(AccessGuard& access) : access_(access) {}
  grpc::experimental::Interceptor* CreateServerInterceptor(grpc::experimental::ServerRpcInfo* info) override {
    const std::string_view method = info->method() ? info->method() : "";
    if (!access_.auth_required() || method.rfind("/grpc.reflection.", 0) != 0) return nullptr;
    return new ReflectionInterceptor(access_, info);
  }

 private:
  AccessGuard& access_;
};

}  // namespace

std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface> reflection_guard(AccessGuard& access) {
  return std::make_unique<ReflectionGuardFactory>(access);
}

}  // namespace depath::service
