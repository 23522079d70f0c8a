// SPDX-License-Identifier: MIT
#include "metrics/rpc_interceptor.hpp"

#include "depath/wire/wire.hpp"

#include <string>

namespace depath::service {

namespace {

class RpcMetricsInterceptor final : public grpc::experimental::Interceptor {
 public:
  RpcMetricsInterceptor(ServiceMetrics& metrics, const char* method)
      : metrics_(metrics), method_(method ? method : "unknown") {}

  void Intercept(grpc::experimental::InterceptorBatchMethods* methods) override {
    if (methods->QueryInterceptionHookPoint(grpc::experimental::InterceptionHookPoints::PRE_SEND_STATUS)) {
      const grpc::StatusCode code = methods->GetSendStatus().error_code();
      metrics_.rpc(method_, wire::status_code_name(code));
      if (code == grpc::StatusCode::UNAUTHENTICATED) metrics_.auth_failure("grpc");
    }
    methods->Proceed();
  }

 private:
  ServiceMetrics& metrics_;
  std::string method_;
};

class RpcMetricsFactory final : public grpc::experimental::ServerInterceptorFactoryInterface {
 public:
  explicit RpcMetricsFactory(ServiceMetrics& metrics) : metrics_(metrics) {}
  grpc::experimental::Interceptor* CreateServerInterceptor(grpc::experimental::ServerRpcInfo* info) override {
    return new RpcMetricsInterceptor(metrics_, info->method());
  }

 private:
  ServiceMetrics& metrics_;
};

}  // namespace

std::vector<std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface>> rpc_metrics_interceptors(
    ServiceMetrics& metrics) {
  std::vector<std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface>> out;
  out.push_back(std::make_unique<RpcMetricsFactory>(metrics));
  return out;
}

}  // namespace depath::service
