// SPDX-License-Identifier: MIT
// depath.v1.JobService on gRPC's callback API: watchers are reactors, not threads.
#pragma once

#include "depath/v1/job.grpc.pb.h"
#include "service_context.hpp"

namespace depath::service {

class JobServiceImpl final : public v1::JobService::CallbackService {
 public:
  explicit JobServiceImpl(ServiceContext& ctx) : ctx_(ctx) {}

  grpc::ServerUnaryReactor* SubmitJob(grpc::CallbackServerContext* context, const v1::SubmitJobRequest* request,
                                      v1::SubmitJobResponse* reply) override;
  grpc::ServerWriteReactor<v1::JobEvent>* WatchJob(grpc::CallbackServerContext* context,
                                                   const v1::WatchJobRequest* request) override;
  grpc::ServerUnaryReactor* GetJob(grpc::CallbackServerContext* context, const v1::GetJobRequest* request,
                                   v1::JobInfo* reply) override;
  grpc::ServerUnaryReactor* GetResult(grpc::CallbackServerContext* context, const v1::GetResultRequest* request,
                                      v1::JobResult* reply) override;
  grpc::ServerUnaryReactor* ListJobs(grpc::CallbackServerContext* context, const v1::ListJobsRequest* request,
                                     v1::ListJobsResponse* reply) override;
  grpc::ServerUnaryReactor* CancelJob(grpc::CallbackServerContext* context, const v1::CancelJobRequest* request,
                                      v1::JobInfo* reply) override;
  grpc::ServerWriteReactor<v1::JobEvent>* Solve(grpc::CallbackServerContext* context,
                                                const v1::SubmitJobRequest* request) override;

 private:
  ServiceContext& ctx_;
};

}  // namespace depath::service
