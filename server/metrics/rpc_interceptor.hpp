// SPDX-License-Identifier: MIT
// A gRPC server interceptor that counts every finished call by method and status code
// (depath_rpcs_total) and the calls refused as UNAUTHENTICATED (depath_auth_failures_total),
// for all services alike (ours, health, reflection), unary and streaming.
#pragma once

#include "metrics/service_metrics.hpp"

#include <grpcpp/support/server_interceptor.h>

#include <memory>
#include <vector>

namespace depath::service {

/// The interceptor factories to hand to ServerBuilder::experimental().SetInterceptorCreators.
std::vector<std::unique_ptr<grpc::experimental::ServerInterceptorFactoryInterface>> rpc_metrics_interceptors(
    ServiceMetrics& metrics);

}  // namespace depath::service
