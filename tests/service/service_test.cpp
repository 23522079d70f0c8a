// SPDX-License-Identifier: MIT
// The service through real gRPC on loopback: an in-process server (depath_service) on
// 127.0.0.1:0 and generated stubs, no mocks.
#include "depath/io/mesh_reader.hpp"
#include "depath/io/result_writer.hpp"
#include "depath/solve/solve.hpp"
#include "access_guard.hpp"
#include "event_log.hpp"
#include "mesh_store.hpp"
#include "grpc/health/v1/health.grpc.pb.h"
#include "service_test_support.hpp"
#include "time_scale.hpp"

#include <atomic>
#include <set>
#include <unistd.h>
#include <filesystem>
#include <thread>

namespace depath::test {
namespace {

using grpc::StatusCode;

TEST(ServiceMeshes, UploadGetListDeleteAndDedup) {
  TestServer ts;
  const std::string bytes = grid_obj(8);
  v1::MeshInfo info;
  ASSERT_TRUE(ts.upload(bytes, "grid.obj", &info, 100).ok());
  EXPECT_EQ(info.id(), wire::sha256_hex(bytes));
  EXPECT_EQ(info.num_vertices(), 64);
  EXPECT_EQ(info.num_faces(), 98);
  EXPECT_EQ(info.num_boundary_edges(), 28);
  EXPECT_EQ(info.num_components(), 1);
  EXPECT_EQ(info.format(), "obj");
  EXPECT_FALSE(info.already_present());
  EXPECT_NEAR(info.bounding_box().max().x(), 1.0, 1e-12);

  v1::MeshInfo again;
  ASSERT_TRUE(ts.upload(bytes, "copy.obj", &again, 1 << 20).ok());
  EXPECT_EQ(again.id(), info.id());
  EXPECT_TRUE(again.already_present());

  v1::GetMeshRequest get;
  get.set_id(info.id());
  v1::MeshInfo got;
  {
    auto ctx = ts.context();
    ASSERT_TRUE(ts.meshes().GetMesh(ctx.get(), get, &got).ok());
  }
  EXPECT_EQ(got.num_vertices(), 64);
  v1::ListMeshesResponse list;
  {
    auto ctx = ts.context();
    ASSERT_TRUE(ts.meshes().ListMeshes(ctx.get(), {}, &list).ok());
  }
  ASSERT_EQ(list.meshes_size(), 1);
  EXPECT_GT(list.cache_bytes(), 0u);

  v1::DeleteMeshRequest del;
  del.set_id(info.id());
  v1::DeleteMeshResponse dr;
  {
    auto ctx = ts.context();
    ASSERT_TRUE(ts.meshes().DeleteMesh(ctx.get(), del, &dr).ok());
  }
  auto ctx = ts.context();
  const auto status = ts.meshes().GetMesh(ctx.get(), get, &got);
  EXPECT_EQ(status.error_code(), StatusCode::NOT_FOUND);
  EXPECT_NE(status.error_message().find(info.id()), std::string::npos);
  auto ctx2 = ts.context();
  EXPECT_EQ(ts.meshes().DeleteMesh(ctx2.get(), del, &dr).error_code(), StatusCode::NOT_FOUND);
}

TEST(ServiceMeshes, UploadErrorsNameTheProblem) {
  auto options = quiet_options();
  options.max_upload_bytes = 2000;
  TestServer ts(options);
  v1::MeshInfo info;
  auto s = ts.upload(grid_obj(3), "x.obj", &info, 100, /*header=*/false);
  EXPECT_EQ(s.error_code(), StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(s.error_message().find("header"), std::string::npos) << s.error_message();

  s = ts.upload(grid_obj(3), "mesh.xyz", &info);
  EXPECT_EQ(s.error_code(), StatusCode::INVALID_ARGUMENT) << s.error_message();

  s = ts.upload(grid_obj(3), "mesh.obj", &info, 100, true, "gltf");
  EXPECT_EQ(s.error_code(), StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(s.error_message().find("gltf"), std::string::npos);

  s = ts.upload("OFF\n3 1 0\n0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n", "bad.off", &info);
  EXPECT_EQ(s.error_code(), StatusCode::INVALID_ARGUMENT) << s.error_message();

  s = ts.upload("v 0 0 0\nv 1 0 0\n", "nofaces.obj", &info);
  EXPECT_EQ(s.error_code(), StatusCode::INVALID_ARGUMENT) << s.error_message();

  s = ts.upload("", "empty.obj", &info);
  EXPECT_EQ(s.error_code(), StatusCode::INVALID_ARGUMENT);

  // Oversize: refused while streaming, naming the limit.
  s = ts.upload(grid_obj(20), "big.obj", &info, 500);
  EXPECT_EQ(s.error_code(), StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(s.error_message().find("--max-upload-bytes"), std::string::npos) << s.error_message();
  // ... and from the declared size, before any byte.
  {
    auto ctx = ts.context();
    auto writer = ts.meshes().UploadMesh(ctx.get(), &info);
    v1::UploadMeshRequest req;
    req.mutable_header()->set_file_name("big.obj");
    req.mutable_header()->set_size_bytes(1 << 30);
    writer->Write(req);
    writer->WritesDone();
    EXPECT_EQ(writer->Finish().error_code(), StatusCode::RESOURCE_EXHAUSTED);
  }
}

TEST(ServiceMeshes, LruEvictionSparesMeshesInUseAndDataDirReloads) {
  const auto dir = std::filesystem::temp_directory_path() / ("depath_service_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  auto options = quiet_options();
  options.mesh_cache_bytes = 1;  // every mesh is over budget: only the newest or in-use stay
  options.max_running_jobs = 1;
  options.data_dir = dir.string();
  std::string a_id;
  {
    TestServer ts(options);
    a_id = ts.upload_ok(grid_obj(30), "a.obj");
    const std::string job = ts.submit_ok(long_job(a_id, 0, 899));
    // A queued job holds no mesh (the store reloads it): wait until the job runs and pins a.
    std::vector<v1::JobEvent> events;
    ASSERT_TRUE(ts.watch_until(job, [](const v1::JobEvent& e) { return e.has_progress(); }, &events).ok());
    const std::string b_id = ts.upload_ok(grid_obj(9), "b.obj");
    const std::string c_id = ts.upload_ok(grid_obj(10), "c.obj");
    v1::ListMeshesResponse list;
    {
      auto ctx = ts.context();
      ASSERT_TRUE(ts.meshes().ListMeshes(ctx.get(), {}, &list).ok());
    }
    std::set<std::string> cached;
    for (const auto& m : list.meshes()) {
      if (m.cached()) cached.insert(m.id());
    }
    EXPECT_TRUE(cached.count(a_id)) << "a mesh used by a running job was evicted";
    EXPECT_TRUE(cached.count(c_id));
    EXPECT_FALSE(cached.count(b_id));
    ts.cancel(job);
    events.clear();
    ASSERT_TRUE(ts.watch(job, 0, &events).ok());
  }
  {
    // A restarted server knows the persisted meshes and reloads them on demand.
    TestServer ts(options);
    v1::GetMeshRequest get;
    get.set_id(a_id);
    v1::MeshInfo info;
    auto ctx = ts.context();
    ASSERT_TRUE(ts.meshes().GetMesh(ctx.get(), get, &info).ok());
    EXPECT_EQ(info.num_vertices(), 900);
    EXPECT_TRUE(info.cached());
  }
  {
    // Memory only: an evicted id answers NOT_FOUND.
    options.data_dir.clear();
    TestServer ts(options);
    const std::string x = ts.upload_ok(grid_obj(5), "x.obj");
    ts.upload_ok(grid_obj(6), "y.obj");
    v1::GetMeshRequest get;
    get.set_id(x);
    v1::MeshInfo info;
    auto ctx = ts.context();
    EXPECT_EQ(ts.meshes().GetMesh(ctx.get(), get, &info).error_code(), StatusCode::NOT_FOUND);
    v1::SubmitJobResponse reply;
    EXPECT_EQ(ts.submit(job_spec(x, 0, 3), &reply).error_code(), StatusCode::NOT_FOUND);
  }
  std::filesystem::remove_all(dir);
}

// Queued jobs cannot grow the mesh cache past its budget: on the memory store (which
// cannot reload a mesh) a queued job on a new mesh is refused when the meshes already held
// would not leave it room; on a durable store queued jobs hold no mesh at all, and the
// mesh is reloaded when the job runs.
TEST(ServiceMeshes, QueuedJobsHoldMeshesOnlyWithinTheCacheBudget) {
  const std::string a = grid_obj(20, 0.3), b = grid_obj(20, 0.2);
  uint64_t mesh_bytes = 0;
  {
    TestServer probe;
    v1::MeshInfo info;
    ASSERT_TRUE(probe.upload(a, "a.obj", &info).ok());
    mesh_bytes = info.memory_bytes();
  }
  ASSERT_GT(mesh_bytes, 0u);
  auto options = quiet_options();
  options.max_running_jobs = 1;
  options.mesh_cache_bytes = mesh_bytes * 3 / 2;  // room for one of the two meshes, not both
  {
    TestServer ts(options);
    const std::string a_id = ts.upload_ok(a, "a.obj");
    const std::string running = ts.submit_ok(long_job(a_id, 0, 399));
    const std::string b_id = ts.upload_ok(b, "b.obj");  // the newest mesh stays, over budget
    v1::SubmitJobResponse reply;
    const auto refused = ts.submit(job_spec(b_id, 0, 399), &reply);
    EXPECT_EQ(refused.error_code(), StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_NE(refused.error_message().find("--mesh-cache-bytes"), std::string::npos) << refused.error_message();
    const std::string same_mesh = ts.submit_ok(job_spec(a_id, 0, 399));  // a is held already
    EXPECT_FALSE(same_mesh.empty());
    ts.cancel(running);
    std::vector<v1::JobEvent> events;
    ASSERT_TRUE(ts.watch(same_mesh, 0, &events).ok());
    ASSERT_NE(find_terminal(events), nullptr);
    EXPECT_EQ(find_terminal(events)->state().state(), v1::JOB_STATE_SUCCEEDED);
  }
  const auto dir = std::filesystem::temp_directory_path() / ("depath_budget_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  options.data_dir = dir.string();
  {
    TestServer ts(options);
    const std::string a_id = ts.upload_ok(a, "a.obj"), b_id = ts.upload_ok(b, "b.obj");
    const std::string running = ts.submit_ok(long_job(a_id, 0, 399));
    const std::string queued = ts.submit_ok(job_spec(b_id, 0, 399));
    ts.cancel(running);
    std::vector<v1::JobEvent> events;
    ASSERT_TRUE(ts.watch(queued, 0, &events).ok());
    ASSERT_NE(find_terminal(events), nullptr);
    EXPECT_EQ(find_terminal(events)->state().state(), v1::JOB_STATE_SUCCEEDED);
  }
  std::filesystem::remove_all(dir);
}

// A port another server holds is refused at start (gRPC would otherwise share it with
// SO_REUSEPORT and split the connections between the two servers).
TEST(ServiceStartup, APortInUseIsRefused) {
  TestServer first;
  auto options = quiet_options();
  options.listen = first.address();
  expect_server_refused(options, "cannot listen", "the address of another server, " + first.address());
}

// Calls that reload a mesh from the store (stored before a restart, or evicted) parse it off
// gRPC's callback threads, so health and ListJobs answer while the reloads run. Four persisted
// meshes, reloaded one at a time (--max-concurrent-parses 1) for a SubmitJob, a Solve and a
// GetMesh each right after a restart. The liveness bound on health and ListJobs is the
// deployment's probe timeout (deploy/k8s/base: timeoutSeconds 5), scaled for sanitizers;
// whether they answered while reloads were still running is checked by order, not by time.
TEST(ServiceMeshes, ReloadsAfterARestartLeaveHealthAndListJobsAnswering) {
  const auto dir = std::filesystem::temp_directory_path() / ("depath_reload_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  auto options = quiet_options();
  options.data_dir = dir.string();
  options.max_concurrent_parses = 1;
  const int n = sanitized_build() ? 120 : 250;  // 15,625 / 62,500 vertices a mesh
  std::vector<std::string> ids;
  {
    TestServer ts(options);
    for (int k = 0; k < 4; ++k) ids.push_back(ts.upload_ok(grid_obj(n, 0.1 + 0.1 * k), "m" + std::to_string(k) + ".obj"));
  }
  TestServer ts(options);
  const int last = n * n - 1;
  std::atomic<int> pending{0};
  std::vector<std::thread> calls;
  std::vector<grpc::Status> submit_status(ids.size()), get_status(ids.size()), solve_status(ids.size());
  std::vector<v1::JobState> solve_end(ids.size(), v1::JOB_STATE_UNSPECIFIED);
  std::vector<uint32_t> get_vertices(ids.size(), 0);
  for (size_t k = 0; k < ids.size(); ++k) {
    pending += 3;
    calls.emplace_back([&, k] {
      v1::SubmitJobResponse reply;
      submit_status[k] = ts.submit(job_spec(ids[k], 0, last), &reply);
      --pending;
    });
    calls.emplace_back([&, k] {
      v1::GetMeshRequest req;
      req.set_id(ids[k]);
      v1::MeshInfo info;
      auto ctx = ts.context();
      get_status[k] = ts.meshes().GetMesh(ctx.get(), req, &info);
      get_vertices[k] = info.num_vertices();
      --pending;
    });
    calls.emplace_back([&, k] {
      v1::SubmitJobRequest req;
      *req.mutable_spec() = job_spec(ids[k], last, 0);
      auto ctx = ts.context();
      auto reader = ts.jobs().Solve(ctx.get(), req);
      v1::JobEvent ev;
      bool first = true;
      while (reader->Read(&ev)) {
        if (first) --pending;  // the stream started: its submit is done
        first = false;
        if (ev.has_state()) solve_end[k] = ev.state().state();
      }
      if (first) --pending;
      solve_status[k] = reader->Finish();
    });
  }
  auto health = grpc::health::v1::Health::NewStub(ts.channel());
  const double probe_timeout = 5;  // deploy/k8s/base/deployment.yaml: timeoutSeconds
  int health_during = 0, list_during = 0;
  bool answered = true;
  while (answered && pending.load() > 0) {
    grpc::health::v1::HealthCheckResponse res;
    auto hctx = ts.context(probe_timeout);
    const auto hs = health->Check(hctx.get(), {}, &res);
    EXPECT_TRUE(hs.ok()) << "health did not answer while meshes reloaded: " << hs.error_message();
    EXPECT_EQ(res.status(), grpc::health::v1::HealthCheckResponse::SERVING);
    if (hs.ok() && pending.load() > 0) ++health_during;
    v1::ListJobsResponse list;
    auto lctx = ts.context(probe_timeout);
    const auto ls = ts.jobs().ListJobs(lctx.get(), {}, &list);
    EXPECT_TRUE(ls.ok()) << "ListJobs did not answer while meshes reloaded: " << ls.error_message();
    if (ls.ok() && pending.load() > 0) ++list_during;
    answered = hs.ok() && ls.ok();
  }
  for (auto& t : calls) t.join();
  EXPECT_GT(health_during, 0) << "health answered only after every reload had finished";
  EXPECT_GT(list_during, 0) << "ListJobs answered only after every reload had finished";
  for (size_t k = 0; k < ids.size(); ++k) {
    EXPECT_TRUE(submit_status[k].ok()) << submit_status[k].error_message();
    EXPECT_TRUE(get_status[k].ok()) << get_status[k].error_message();
    EXPECT_EQ(get_vertices[k], static_cast<uint32_t>(n * n));
    EXPECT_TRUE(solve_status[k].ok()) << solve_status[k].error_message();
    EXPECT_EQ(solve_end[k], v1::JOB_STATE_SUCCEEDED);
  }
  v1::GetMeshRequest missing;
  missing.set_id(std::string(64, 'a'));  // not stored: NOT_FOUND at once, as before
  v1::MeshInfo info;
  auto ctx = ts.context();
  EXPECT_EQ(ts.meshes().GetMesh(ctx.get(), missing, &info).error_code(), StatusCode::NOT_FOUND);
  std::filesystem::remove_all(dir);
}

TEST(ServiceJobs, SubmitErrorsUseTheRightCodes) {
  TestServer ts;
  const std::string grid = ts.upload_ok(grid_obj(6));
  const std::string split = ts.upload_ok(two_components_obj(), "split.obj");
  v1::SubmitJobResponse reply;

  auto s = ts.submit(job_spec(std::string(64, 'a'), 0, 1), &reply);
  EXPECT_EQ(s.error_code(), StatusCode::NOT_FOUND) << s.error_message();
  s = ts.submit(job_spec("", 0, 1), &reply);
  EXPECT_EQ(s.error_code(), StatusCode::INVALID_ARGUMENT) << s.error_message();
  s = ts.submit(job_spec(grid, 0, 0), &reply);
  EXPECT_EQ(s.error_code(), StatusCode::INVALID_ARGUMENT) << s.error_message();
  s = ts.submit(job_spec(grid, 0, 36), &reply);
  EXPECT_EQ(s.error_code(), StatusCode::INVALID_ARGUMENT) << s.error_message();
  EXPECT_NE(s.error_message().find("36"), std::string::npos) << s.error_message();
  s = ts.submit(job_spec(split, 0, 4), &reply);
  EXPECT_EQ(s.error_code(), StatusCode::FAILED_PRECONDITION) << s.error_message();
  auto bad_pop = job_spec(grid, 0, 35, v1::METHOD_DE);
  bad_pop.mutable_de()->set_population(2);
  s = ts.submit(bad_pop, &reply);
  EXPECT_EQ(s.error_code(), StatusCode::INVALID_ARGUMENT) << s.error_message();
  auto zero_gen = job_spec(grid, 0, 35, v1::METHOD_DE);
  zero_gen.mutable_de()->set_generations(0);
  s = ts.submit(zero_gen, &reply);
  EXPECT_EQ(s.error_code(), StatusCode::INVALID_ARGUMENT) << s.error_message();
  auto bad_density = job_spec(grid, 0, 35);
  bad_density.mutable_energy()->add_density(1.0);
  s = ts.submit(bad_density, &reply);
  EXPECT_EQ(s.error_code(), StatusCode::INVALID_ARGUMENT) << s.error_message();
  auto bad_method = job_spec(grid, 0, 35);
  bad_method.set_method(static_cast<v1::Method>(42));
  s = ts.submit(bad_method, &reply);
  EXPECT_EQ(s.error_code(), StatusCode::INVALID_ARGUMENT) << s.error_message();

  v1::JobInfo info;
  EXPECT_EQ(ts.get_job("job-nope", &info).error_code(), StatusCode::NOT_FOUND);
  EXPECT_EQ(ts.cancel("job-nope").error_code(), StatusCode::NOT_FOUND);
  std::vector<v1::JobEvent> events;
  EXPECT_EQ(ts.watch("job-nope", 0, &events).error_code(), StatusCode::NOT_FOUND);
  v1::JobResult result;
  EXPECT_EQ(ts.get_result("job-nope", &result).error_code(), StatusCode::NOT_FOUND);
}

TEST(ServiceJobs, IdempotentSubmitAndResultOfUnfinishedJob) {
  auto options = quiet_options();
  options.max_running_jobs = 1;
  TestServer ts(options);
  const std::string grid = ts.upload_ok(grid_obj(20));
  v1::SubmitJobResponse first, second, third;
  ASSERT_TRUE(ts.submit(long_job(grid, 0, 399), &first, "req-1").ok());
  ASSERT_TRUE(ts.submit(long_job(grid, 0, 399), &second, "req-1").ok());
  EXPECT_EQ(first.job_id(), second.job_id());
  EXPECT_FALSE(first.existing());
  EXPECT_TRUE(second.existing());
  EXPECT_EQ(ts.submit(long_job(grid, 0, 398), &third, "req-1").error_code(), StatusCode::ALREADY_EXISTS);

  v1::JobResult result;
  {
    const auto s = ts.get_result(first.job_id(), &result);
    EXPECT_EQ(s.error_code(), StatusCode::FAILED_PRECONDITION) << s.error_message();
  }
  ASSERT_TRUE(ts.cancel(first.job_id()).ok());
  std::vector<v1::JobEvent> events;
  ASSERT_TRUE(ts.watch(first.job_id(), 0, &events).ok());
}

TEST(ServiceJobs, AuthTokenRequiredButHealthExempt) {
  auto options = quiet_options();
  options.auth_tokens = {"s3cret"};
  TestServer ts(options);
  v1::MeshInfo info;
  auto s = ts.upload(grid_obj(4), "g.obj", &info);
  EXPECT_EQ(s.error_code(), StatusCode::UNAUTHENTICATED);
  v1::ListJobsResponse jobs;
  {
    auto ctx = ts.context();
    ctx->AddMetadata("authorization", "Bearer wrong");
    EXPECT_EQ(ts.jobs().ListJobs(ctx.get(), {}, &jobs).error_code(), StatusCode::UNAUTHENTICATED);
  }
  std::vector<v1::JobEvent> events;
  EXPECT_EQ(ts.watch("job-1", 0, &events).error_code(), StatusCode::UNAUTHENTICATED);
  auto health = grpc::health::v1::Health::NewStub(ts.channel());
  grpc::health::v1::HealthCheckRequest hreq;
  grpc::health::v1::HealthCheckResponse hres;
  {
    auto ctx = ts.context();
    ASSERT_TRUE(health->Check(ctx.get(), hreq, &hres).ok());
    EXPECT_EQ(hres.status(), grpc::health::v1::HealthCheckResponse::SERVING);
  }
  ts.token = "s3cret";
  EXPECT_TRUE(ts.upload(grid_obj(4), "g.obj", &info).ok());
  auto ctx = ts.context();
  EXPECT_TRUE(ts.jobs().ListJobs(ctx.get(), {}, &jobs).ok());
}

/// Runs a job through the server and through depath::solve in-process: same result.
void expect_same_as_local(TestServer& ts, const std::string& obj, const v1::JobSpec& spec_in) {
  const std::string id = ts.upload_ok(obj);
  v1::JobSpec spec = spec_in;
  spec.set_mesh_id(id);
  spec.set_path_every(2);
  const std::string job = ts.submit_ok(spec);
  std::vector<v1::JobEvent> events;
  const auto status = ts.watch(job, 0, &events);
  ASSERT_TRUE(status.ok()) << status.error_message();
  const auto* terminal = find_terminal(events);
  ASSERT_NE(terminal, nullptr);
  ASSERT_EQ(terminal->state().state(), v1::JOB_STATE_SUCCEEDED) << terminal->state().message();
  const auto* result = find_result(events);
  ASSERT_NE(result, nullptr);
  for (size_t i = 1; i < events.size(); ++i) EXPECT_GT(events[i].sequence(), events[i - 1].sequence());
  EXPECT_EQ(events.front().state().state(), v1::JOB_STATE_QUEUED);
  int progress = 0, with_path = 0;
  for (const auto& e : events) {
    if (e.has_progress()) {
      ++progress;
      with_path += e.progress().has_best_path();
    }
  }
  EXPECT_GE(progress, 1);
  if (spec.method() == v1::METHOD_DE) {
    EXPECT_GE(with_path, 1);
  }

  const Mesh mesh = load_mesh_from_bytes(obj, "obj", "grid");
  const SolveResult local = solve(mesh, wire::job_from_proto(spec));
  EXPECT_DOUBLE_EQ(result->energy(), local.energy);
  EXPECT_EQ(result->path().points_size(), static_cast<int>(local.path.points.size()));
  EXPECT_EQ(result->generations(), local.generations);

  // GetResult gives the same, and it converts back to what `depath solve` writes.
  v1::JobResult fetched;
  ASSERT_TRUE(ts.get_result(job, &fetched).ok());
  EXPECT_EQ(fetched.SerializeAsString(), result->SerializeAsString());
  const auto with_mesh = wire::result_message_to_json(fetched, &mesh);
  const auto without_mesh = wire::result_message_to_json(fetched, nullptr);
  EXPECT_EQ(with_mesh["points"], without_mesh["points"]);
  EXPECT_EQ(with_mesh["crossings"], without_mesh["crossings"]);
  EXPECT_EQ(with_mesh["points"], nlohmann::json::parse(result_json(mesh, local))["points"]);
}

TEST(ServiceJobs, GeodesicDeMatchesLocalSolve) {
  TestServer ts;
  expect_same_as_local(ts, grid_obj(10), job_spec("", 0, 99, v1::METHOD_DE));
}

TEST(ServiceJobs, GeodesicFmmAndDescentMatchLocalSolve) {
  TestServer ts;
  expect_same_as_local(ts, grid_obj(10), job_spec("", 3, 96, v1::METHOD_FMM));
  expect_same_as_local(ts, grid_obj(10), job_spec("", 3, 96, v1::METHOD_DESCENT));
}

TEST(ServiceJobs, VectorFieldMatchesLocalSolve) {
  TestServer ts;
  auto spec = job_spec("", 0, 99, v1::METHOD_DE);
  spec.mutable_energy()->set_kind(v1::ENERGY_KIND_VECTOR_FIELD);
  spec.mutable_energy()->set_field_from_height(true);
  spec.mutable_energy()->set_rotate_degrees(30);
  expect_same_as_local(ts, grid_obj(10), spec);
}

TEST(ServiceJobs, ConstantSlopeMatchesLocalSolve) {
  TestServer ts;
  auto spec = job_spec("", 0, 99, v1::METHOD_DE);
  spec.mutable_energy()->set_kind(v1::ENERGY_KIND_CONSTANT_SLOPE);
  spec.mutable_energy()->set_slope(0.2);
  spec.mutable_energy()->set_smoothness(0.01);
  expect_same_as_local(ts, grid_obj(10), spec);
}

TEST(ServiceJobs, SolveRpcSubmitsAndStreams) {
  TestServer ts;
  const std::string id = ts.upload_ok(grid_obj(8));
  v1::SubmitJobRequest req;
  *req.mutable_spec() = job_spec(id, 0, 63, v1::METHOD_DE);
  auto ctx = ts.context();
  auto reader = ts.jobs().Solve(ctx.get(), req);
  std::vector<v1::JobEvent> events;
  v1::JobEvent ev;
  while (reader->Read(&ev)) events.push_back(ev);
  ASSERT_TRUE(reader->Finish().ok());
  ASSERT_FALSE(events.empty());
  EXPECT_FALSE(events.front().job_id().empty());
  ASSERT_NE(find_terminal(events), nullptr);
  EXPECT_EQ(find_terminal(events)->state().state(), v1::JOB_STATE_SUCCEEDED);
  EXPECT_NE(find_result(events), nullptr);

  req.mutable_spec()->set_target(0);
  auto ctx2 = ts.context();
  auto bad = ts.jobs().Solve(ctx2.get(), req);
  while (bad->Read(&ev)) {
  }
  EXPECT_EQ(bad->Finish().error_code(), StatusCode::INVALID_ARGUMENT);
}

TEST(ServiceJobs, CancelMidRunStopsPromptly) {
  TestServer ts;
  const std::string id = ts.upload_ok(grid_obj(20));
  const std::string job = ts.submit_ok(long_job(id, 0, 399));
  // Wait for a few generations through a watch, then cancel from another connection.
  auto ctx = ts.context();
  v1::WatchJobRequest req;
  req.set_job_id(job);
  auto reader = ts.jobs().WatchJob(ctx.get(), req);
  v1::JobEvent ev;
  std::vector<v1::JobEvent> events;
  std::chrono::steady_clock::time_point cancelled_at{};
  while (reader->Read(&ev)) {
    events.push_back(ev);
    if (ev.has_progress() && ev.progress().generation() >= 3 && cancelled_at == decltype(cancelled_at){}) {
      cancelled_at = std::chrono::steady_clock::now();
      ASSERT_TRUE(ts.cancel(job).ok());
    }
  }
  ASSERT_TRUE(reader->Finish().ok());
  // Liveness, not speed: DE polls the cancel flag before every evaluation, and one decode on
  // this 400-vertex grid takes well under a millisecond in Release, so the job stops almost at
  // once; 5 s (times the sanitizer slow-down) is thousands of evaluations of margin and only a
  // job that ignores cancellation can exceed it.
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - cancelled_at).count();
  EXPECT_LT(seconds, 5.0 * test::time_scale());
  const auto* terminal = find_terminal(events);
  ASSERT_NE(terminal, nullptr);
  EXPECT_EQ(terminal->state().state(), v1::JOB_STATE_CANCELLED);
  EXPECT_EQ(terminal->state().error_code(), static_cast<int>(StatusCode::CANCELLED));
  const auto* result = find_result(events);
  ASSERT_NE(result, nullptr);  // the best path so far
  EXPECT_EQ(result->stop_reason(), "cancelled");
  v1::JobInfo info;
  ASSERT_TRUE(ts.get_job(job, &info).ok());
  EXPECT_EQ(info.state(), v1::JOB_STATE_CANCELLED);
  ASSERT_TRUE(ts.cancel(job, &info).ok());  // idempotent
  EXPECT_EQ(info.state(), v1::JOB_STATE_CANCELLED);
}

TEST(ServiceJobs, ResumeWatchBySequenceMissesNoStateOrResult) {
  TestServer ts;
  const std::string id = ts.upload_ok(grid_obj(10));
  auto spec = job_spec(id, 0, 99, v1::METHOD_DE);
  spec.mutable_de()->set_generations(30);
  const std::string job = ts.submit_ok(spec);
  std::vector<v1::JobEvent> all;
  ASSERT_TRUE(ts.watch(job, 0, &all).ok());
  ASSERT_NE(find_terminal(all), nullptr);
  const uint64_t last = all.back().sequence();
  for (uint64_t after : {uint64_t{1}, uint64_t{2}, last / 2, last - 2, last - 1, last}) {
    std::vector<v1::JobEvent> tail;
    ASSERT_TRUE(ts.watch(job, after, &tail).ok());
    for (const auto& e : tail) EXPECT_GT(e.sequence(), after);
    for (const auto& e : all) {
      if (e.sequence() > after && !e.has_progress()) {
        bool found = false;
        for (const auto& t : tail) found |= t.sequence() == e.sequence();
        EXPECT_TRUE(found) << "missing event " << e.sequence() << " after " << after;
      }
    }
    if (after < last) {
      ASSERT_NE(find_terminal(tail), nullptr);
    } else {
      EXPECT_TRUE(tail.empty());
    }
  }
}

TEST(ServiceJobs, FiftyWatchersGetTheSameResult) {
  TestServer ts;
  const std::string id = ts.upload_ok(grid_obj(16));
  auto spec = job_spec(id, 0, 255, v1::METHOD_DE);
  spec.mutable_de()->set_generations(60);
  spec.mutable_de()->set_population(12);
  const std::string job = ts.submit_ok(spec);
  constexpr int kWatchers = 50;
  std::vector<std::string> results(kWatchers);
  std::vector<int> states(kWatchers, 0);
  std::vector<std::thread> threads;
  for (int i = 0; i < kWatchers; ++i) {
    threads.emplace_back([&, i] {
      std::vector<v1::JobEvent> events;
      if (!ts.watch(job, 0, &events).ok()) return;
      if (const auto* r = find_result(events)) results[i] = r->SerializeAsString();
      if (const auto* t = find_terminal(events)) states[i] = t->state().state();
    });
  }
  for (auto& t : threads) t.join();
  for (int i = 0; i < kWatchers; ++i) {
    EXPECT_EQ(states[i], v1::JOB_STATE_SUCCEEDED) << "watcher " << i;
    EXPECT_FALSE(results[i].empty());
    EXPECT_EQ(results[i], results[0]) << "watcher " << i;
  }
}

TEST(ServiceJobs, ConcurrentJobsShareThePool) {
  auto options = quiet_options();
  options.max_running_jobs = 3;
  TestServer ts(options);
  const std::string id = ts.upload_ok(grid_obj(20));
  std::vector<std::string> jobs;
  for (int i = 0; i < 3; ++i) jobs.push_back(ts.submit_ok(long_job(id, i, 399 - i)));
  // All three run at once and all make progress on the shared pool (a liveness wait: three
  // generations take milliseconds in Release).
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(30.0 * test::time_scale());
  bool all_progressing = false;
  while (!all_progressing && std::chrono::steady_clock::now() < deadline) {
    all_progressing = true;
    for (const auto& j : jobs) {
      v1::JobInfo info;
      ASSERT_TRUE(ts.get_job(j, &info).ok());
      all_progressing &= info.state() == v1::JOB_STATE_RUNNING && info.last_progress().generation() >= 3;
    }
    if (!all_progressing) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_TRUE(all_progressing);
  v1::ListJobsRequest running;
  running.add_states(v1::JOB_STATE_RUNNING);
  v1::ListJobsResponse list;
  {
    auto ctx = ts.context();
    ASSERT_TRUE(ts.jobs().ListJobs(ctx.get(), running, &list).ok());
  }
  EXPECT_EQ(list.jobs_size(), 3);
  for (const auto& j : jobs) ASSERT_TRUE(ts.cancel(j).ok());
  for (const auto& j : jobs) {
    std::vector<v1::JobEvent> events;
    ASSERT_TRUE(ts.watch(j, 0, &events).ok());
    EXPECT_EQ(find_terminal(events)->state().state(), v1::JOB_STATE_CANCELLED);
  }
}

TEST(ServiceJobs, QueueFullAnswersResourceExhausted) {
  auto options = quiet_options();
  options.max_running_jobs = 1;
  options.max_queued_jobs = 1;
  TestServer ts(options);
  const std::string id = ts.upload_ok(grid_obj(12));
  const std::string a = ts.submit_ok(long_job(id, 0, 143));
  // Wait until a runs so that b is the one queued.
  for (int i = 0; i < 500; ++i) {
    v1::JobInfo info;
    ts.get_job(a, &info);
    if (info.state() == v1::JOB_STATE_RUNNING) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const std::string b = ts.submit_ok(long_job(id, 1, 143));
  v1::JobInfo info;
  ASSERT_TRUE(ts.get_job(b, &info).ok());
  EXPECT_EQ(info.state(), v1::JOB_STATE_QUEUED);
  EXPECT_EQ(info.queue_position(), 1);
  v1::SubmitJobResponse reply;
  const auto s = ts.submit(long_job(id, 2, 143), &reply);
  EXPECT_EQ(s.error_code(), StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(s.error_message().find("--max-queued-jobs"), std::string::npos) << s.error_message();
  // Cancelling the queued job frees the slot; it never ran.
  ASSERT_TRUE(ts.cancel(b).ok());
  std::vector<v1::JobEvent> events;
  ASSERT_TRUE(ts.watch(b, 0, &events).ok());
  EXPECT_EQ(find_terminal(events)->state().state(), v1::JOB_STATE_CANCELLED);
  EXPECT_EQ(find_result(events), nullptr);
  const std::string c = ts.submit_ok(long_job(id, 2, 143));
  ts.cancel(c);
  ts.cancel(a);
}

// GetJob's status once the job is forgotten (NOT_FOUND), or at the deadline. The clean-up
// runs at least once a second, so 10 s (times the sanitizer slow-down) cannot pass on a
// healthy build, and a job never forgotten still fails the caller's check.
grpc::Status status_once_forgotten(TestServer& ts, const std::string& job) {
  v1::JobInfo info;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(10.0 * test::time_scale());
  grpc::Status status = ts.get_job(job, &info);
  while (status.error_code() != StatusCode::NOT_FOUND && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    status = ts.get_job(job, &info);
  }
  return status;
}

TEST(ServiceJobs, FinishedJobsExpireAfterTtl) {
  auto options = quiet_options();
  // The watch below must attach before the finished job expires: the TTL (0.3 s, times the
  // sanitizer slow-down) leaves that pair of RPCs hundreds of times the time they take.
  options.job_ttl_seconds = 0.3 * test::time_scale();
  TestServer ts(options);
  const std::string id = ts.upload_ok(grid_obj(6));
  const std::string job = ts.submit_ok(job_spec(id, 0, 35));
  std::vector<v1::JobEvent> events;
  ASSERT_TRUE(ts.watch(job, 0, &events).ok());
  // The clean-up runs every min(1 s, ttl / 2 + 10 ms), so the job is gone at most ttl + 1 s
  // after it finished (0.46 s in Release).
  EXPECT_EQ(status_once_forgotten(ts, job).error_code(), StatusCode::NOT_FOUND);
}

// Retention is bounded by count as well as by time: past --max-finished-jobs the oldest
// finished jobs go first, and their ids then answer NOT_FOUND naming the limit.
TEST(ServiceJobs, FinishedJobsPastTheCapAreForgottenOldestFirst) {
  auto options = quiet_options();
  options.max_finished_jobs = 2;
  TestServer ts(options);
  const std::string id = ts.upload_ok(grid_obj(6));
  std::vector<std::string> jobs;
  for (int i = 0; i < 4; ++i) {
    jobs.push_back(ts.submit_ok(job_spec(id, 0, 35 - i)));
    std::vector<v1::JobEvent> events;
    ASSERT_TRUE(ts.watch(jobs.back(), 0, &events).ok());
  }
  // The clean-up runs at least once a second.
  const grpc::Status second = status_once_forgotten(ts, jobs[1]);
  EXPECT_EQ(second.error_code(), StatusCode::NOT_FOUND);
  v1::JobInfo info;
  EXPECT_NE(second.error_message().find("--max-finished-jobs"), std::string::npos) << second.error_message();
  EXPECT_EQ(ts.get_job(jobs[0], &info).error_code(), StatusCode::NOT_FOUND);
  EXPECT_TRUE(ts.get_job(jobs[2], &info).ok());
  EXPECT_TRUE(ts.get_job(jobs[3], &info).ok());
}

TEST(ServiceShutdown, MidJobEndsWatchersCleanlyAndRefusesNewWork) {
  auto ts = std::make_unique<TestServer>();
  const std::string id = ts->upload_ok(grid_obj(20));
  const std::string job = ts->submit_ok(long_job(id, 0, 399));
  const std::string queued_behind = [&] {
    std::vector<std::string> more;
    for (int i = 0; i < 3; ++i) more.push_back(ts->submit_ok(long_job(id, i + 1, 399)));
    return more.back();
  }();
  constexpr int kWatchers = 5;
  std::vector<std::vector<v1::JobEvent>> seen(kWatchers);
  std::vector<grpc::Status> statuses(kWatchers);
  std::atomic<int> started{0};
  std::vector<std::thread> watchers;
  for (int i = 0; i < kWatchers; ++i) {
    watchers.emplace_back([&, i] {
      auto ctx = ts->context();
      v1::WatchJobRequest req;
      req.set_job_id(i % 2 ? queued_behind : job);
      auto reader = ts->jobs().WatchJob(ctx.get(), req);
      v1::JobEvent ev;
      bool counted = false;
      while (reader->Read(&ev)) {
        seen[i].push_back(ev);
        if (!counted) {
          counted = true;
          ++started;
        }
      }
      statuses[i] = reader->Finish();
    });
  }
  while (started < kWatchers) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_TRUE(ts->server().shutdown());
  // The server's own bound: shutdown cancels the running job and ends every watcher, and
  // gives up waiting after options.shutdown_timeout_seconds (5 s) whatever happens; the 2 s
  // margin (times the sanitizer slow-down) covers joining the threads afterwards.
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(seconds, ts->options().shutdown_timeout_seconds + 2.0 * test::time_scale());
  for (auto& t : watchers) t.join();
  for (int i = 0; i < kWatchers; ++i) {
    EXPECT_TRUE(statuses[i].ok()) << statuses[i].error_message();
    const auto* terminal = find_terminal(seen[i]);
    ASSERT_NE(terminal, nullptr) << "watcher " << i << " got no final event";
    EXPECT_EQ(terminal->state().state(), v1::JOB_STATE_CANCELLED);
    EXPECT_EQ(terminal->state().error_code(), static_cast<int>(StatusCode::UNAVAILABLE));
    EXPECT_NE(terminal->state().message().find("shutting down"), std::string::npos);
  }
  // After shutdown nothing is accepted.
  v1::SubmitJobResponse reply;
  EXPECT_EQ(ts->submit(job_spec(id, 0, 5), &reply).error_code(), StatusCode::UNAVAILABLE);
}

TEST(ServiceEvents, SlowWatcherGetsCoalescedProgressButEveryStateChange) {
  service::EventHub hub;
  auto log = std::make_shared<service::EventLog>("job-x", hub);
  auto state = [](v1::JobState s) {
    v1::JobEvent e;
    e.mutable_state()->set_state(s);
    return e;
  };
  log->publish(state(v1::JOB_STATE_QUEUED));
  log->publish(state(v1::JOB_STATE_RUNNING));
  for (int g = 1; g <= 100; ++g) {
    v1::JobEvent e;
    e.mutable_progress()->set_generation(g);
    log->publish(e);
  }
  v1::JobEvent r;
  r.mutable_result()->set_energy(1.5);
  log->publish(r);
  log->publish(state(v1::JOB_STATE_SUCCEEDED));
  EXPECT_TRUE(log->closed());
  EXPECT_EQ(log->publish(state(v1::JOB_STATE_FAILED)), 0u);  // nothing after the terminal event
  // A watcher that only now reads from the start.
  std::vector<service::EventPtr> got;
  uint64_t cursor = 0;
  while (auto e = log->next_after(cursor)) {
    got.push_back(e);
    cursor = e->sequence();
  }
  // queued, running, the latest progress only (generation 100), result, succeeded.
  ASSERT_EQ(got.size(), 5u);
  EXPECT_EQ(got[0]->state().state(), v1::JOB_STATE_QUEUED);
  EXPECT_EQ(got[1]->state().state(), v1::JOB_STATE_RUNNING);
  ASSERT_TRUE(got[2]->has_progress());
  EXPECT_EQ(got[2]->progress().generation(), 100);
  EXPECT_TRUE(got[3]->has_result());
  EXPECT_EQ(got[4]->state().state(), v1::JOB_STATE_SUCCEEDED);
  EXPECT_EQ(got[4]->sequence(), 104u);
  // Progress still pending when the result has not come yet: the latest only.
  auto log2 = std::make_shared<service::EventLog>("job-y", hub);
  log2->publish(state(v1::JOB_STATE_RUNNING));
  for (int g = 1; g <= 10; ++g) {
    v1::JobEvent e;
    e.mutable_progress()->set_generation(g);
    log2->publish(e);
  }
  auto e1 = log2->next_after(0);
  auto e2 = log2->next_after(e1->sequence());
  ASSERT_TRUE(e2 && e2->has_progress());
  EXPECT_EQ(e2->progress().generation(), 10);
  EXPECT_EQ(log2->next_after(e2->sequence()), nullptr);
  hub.flush();
}

// A sequence names one event in the store and in a log alike. A runner stores its result and
// end, then publishes them; a sync of the same log from the store (a cancel, a mirror) may
// read them back in between. Each event must appear once, with its stored number: before,
// the runner's publish renumbered an event the sync had added, so a watcher got the result
// twice (seen under TSan: a cancelled job with two result events).
TEST(ServiceEvents, AnEventReadBackFromTheStoreIsNotAddedTwice) {
  service::EventHub hub;
  auto numbered = [](uint64_t sequence, bool result) {
    v1::JobEvent e;
    e.set_sequence(sequence);
    if (result) e.mutable_result()->set_energy(1.5);
    else e.mutable_state()->set_state(v1::JOB_STATE_CANCELLED);
    return e;
  };
  // Every order of the runner's two publishes and the sync's two reads (runner and sync each
  // in their own order).
  const std::vector<std::vector<int>> orders = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 2, 3, 1},
                                                {2, 0, 1, 3}, {2, 0, 3, 1}, {2, 3, 0, 1}};
  for (const auto& order : orders) {
    auto log = std::make_shared<service::EventLog>("job-z", hub);
    v1::JobEvent progress;
    progress.mutable_progress()->set_generation(3);
    ASSERT_EQ(log->publish(progress), 1u);
    int runner = 0, sync = 0;
    for (int step : order) {
      const bool by_runner = step < 2;
      const int k = by_runner ? runner++ : sync++;
      log->publish(numbered(2 + k, k == 0));
    }
    std::vector<service::EventPtr> got;
    uint64_t cursor = 0;
    while (auto e = log->next_after(cursor)) {
      got.push_back(e);
      cursor = e->sequence();
    }
    ASSERT_EQ(got.size(), 3u) << "order " << order[0] << order[1] << order[2] << order[3];
    EXPECT_TRUE(got[1]->has_result());
    EXPECT_EQ(got[1]->sequence(), 2u);
    EXPECT_EQ(got[2]->state().state(), v1::JOB_STATE_CANCELLED);
    EXPECT_EQ(got[2]->sequence(), 3u);
    EXPECT_TRUE(log->closed());
    EXPECT_EQ(log->last_sequence(), 3u);
  }
  hub.flush();
}


// The store parses within its budget: past the deadline a parse stops with RESOURCE_EXHAUSTED
// naming the flag (budget 0: the deadline has passed by the reader's first check), and a
// failed parse leaves the store usable.
TEST(ServiceMeshStore, ParseBudgetStopsAParseWithResourceExhausted) {
  depath::service::Log log("text", "off");
  const auto memory = service::JobStore::open("memory");
  service::MeshStore store(1ull << 30, *memory, log, service::ParseLimits{1, 0.0});
  const std::string big = grid_obj(100);  // 10,000 vertices: past the reader's first deadline check
  try {
    (void)store.add(std::string(64, 'a'), "big.obj", "obj", big);
    ADD_FAILURE() << "parse budget ignored";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::resource_exhausted) << e.what();
    EXPECT_NE(std::string(e.what()).find("--parse-timeout-seconds"), std::string::npos) << e.what();
  }
  service::MeshStore roomy(1ull << 30, *memory, log, service::ParseLimits{1, 600.0});
  EXPECT_EQ(roomy.add(std::string(64, 'a'), "big.obj", "obj", big).num_vertices(), 10000);
  EXPECT_EQ(roomy.add(std::string(64, 'b'), "small.obj", "obj", grid_obj(3)).num_vertices(), 9);
}

// Stores a queued job `id` (mesh "m") and claims it for "owner", as a runner would.
void insert_and_claim(service::JobStore& store, const std::string& id) {
  service::JobRecord record;
  record.id = id;
  record.mesh_id = "m";
  v1::JobEvent queued;
  queued.mutable_state()->set_state(v1::JOB_STATE_QUEUED);
  store.insert_job(record, queued);
  ASSERT_TRUE(store.claim("owner", 1.0, 600));
}

// A finished job keeps only what its result needs: the per-vertex arrays of its spec
// (densities, field vectors) are dropped when it ends, whether it finished or was cancelled
// while queued, so retention does not scale with the size of what jobs carried.
TEST(ServiceJobStore, FinishedJobsKeepNoPerVertexArrays) {
  const auto store = service::JobStore::open("memory");
  auto queued_event = [](v1::JobState state) {
    v1::JobEvent e;
    e.mutable_state()->set_state(state);
    return e;
  };
  auto carried = [](const std::string& id) {
    service::JobRecord job;
    job.id = id;
    job.mesh_id = "m";
    job.spec.set_mesh_id("m");
    for (int i = 0; i < 1000; ++i) job.spec.mutable_energy()->add_density(1.5);
    job.spec.mutable_energy()->add_field()->set_x(1);
    return job;
  };
  store->insert_job(carried("job-run"), queued_event(v1::JOB_STATE_QUEUED));
  store->insert_job(carried("job-cancel"), queued_event(v1::JOB_STATE_QUEUED));
  EXPECT_EQ(store->get_job("job-run")->spec.energy().density_size(), 1000);
  EXPECT_EQ(store->cancel("job-cancel", queued_event(v1::JOB_STATE_CANCELLED)),
            service::CancelOutcome::cancelled_queued);
  const auto claimed = store->claim("replica", 1.0, 60);
  ASSERT_TRUE(claimed);
  ASSERT_EQ(claimed->id, "job-run");
  EXPECT_EQ(claimed->spec.energy().density_size(), 1000);  // the runner gets the whole spec
  v1::JobEvent done = queued_event(v1::JOB_STATE_SUCCEEDED);
  done.set_sequence(2);
  v1::JobResult result;
  result.set_energy(1);
  ASSERT_TRUE(store->finish("job-run", "replica", &result, {done}));
  for (const char* id : {"job-run", "job-cancel"}) {
    const auto job = store->get_job(id);
    ASSERT_TRUE(job) << id;
    EXPECT_EQ(job->spec.energy().density_size(), 0) << id;
    EXPECT_EQ(job->spec.energy().field_size(), 0) << id;
    EXPECT_EQ(job->spec.mesh_id(), "m") << id;
  }
  EXPECT_EQ(store->get_result("job-run")->energy(), 1);
}

// A finished job's result is stored once: its result event keeps no copy of the path (the
// results row is its payload), and reading the events back gives the whole result.
TEST(ServiceJobStore, AResultIsStoredOnceAndReadBackWhole) {
  const auto dir = std::filesystem::temp_directory_path() / ("depath_result_once_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "store.db").string();
  v1::JobResult result;
  result.set_energy(2.5);
  result.set_stop_reason("converged");
  for (int i = 0; i < 500; ++i) {
    auto* p = result.mutable_path()->add_points();
    p->set_x(i);
    p->set_y(0.5 * i);
    result.mutable_path()->add_segment_faces(i);
  }
  v1::JobEvent result_event;
  result_event.set_job_id("job-r");
  result_event.set_sequence(2);
  *result_event.mutable_result() = result;
  v1::JobEvent done;
  done.set_job_id("job-r");
  done.set_sequence(3);
  done.mutable_state()->set_state(v1::JOB_STATE_SUCCEEDED);
  {
    const auto store = service::JobStore::open("sqlite:" + path);
    insert_and_claim(*store, "job-r");
    ASSERT_TRUE(store->finish("job-r", "owner", &result, {result_event, done}));
    const auto events = store->events_after("job-r", 1);
    ASSERT_EQ(events.size(), 2u);
    EXPECT_EQ(events[0].SerializeAsString(), result_event.SerializeAsString());
    EXPECT_EQ(events[1].SerializeAsString(), done.SerializeAsString());
    EXPECT_EQ(store->get_result("job-r")->SerializeAsString(), result.SerializeAsString());
  }
  {
    const auto db = service::open_sqlite(path);
    auto s = db->session();
    const auto event_bytes =
        service::sql_int(s->exec("SELECT length(body) FROM events WHERE job_id = $1 AND sequence = 2", {"job-r"})
                             .rows.at(0)
                             .at(0));
    EXPECT_LT(event_bytes, 64) << "the result event stores the path again";
    EXPECT_EQ(service::sql_int(s->exec("SELECT length(body) FROM results WHERE job_id = $1", {"job-r"}).rows.at(0).at(0)),
              static_cast<int64_t>(result.ByteSizeLong()));
  }
  std::filesystem::remove_all(dir);
}

// The progress history: every generation while under kProgressHistoryPoints, then the first,
// the multiples of a doubling stride and the latest; written only by the lease holder (with
// progress, checkpoints and the finish), unchanged by repeated generations of a resumed run,
// removed when the job expires.
TEST(ServiceJobStore, ProgressHistoryIsThinnedAndWrittenByTheOwnerOnly) {
  EXPECT_EQ(service::progress_history_stride(999), 1);
  EXPECT_EQ(service::progress_history_stride(1000), 2);
  EXPECT_EQ(service::progress_history_stride(2500), 4);
  const auto store = service::JobStore::open("memory");
  insert_and_claim(*store, "job-h");
  auto point = [](int g) { return service::ProgressPoint{g, 100.0 - g * 0.01, 200.0 - g * 0.01}; };
  auto progress = [](int g, uint64_t seq) {
    v1::JobEvent e;
    e.set_sequence(seq);
    e.mutable_progress()->set_generation(g);
    return e;
  };
  uint64_t seq = 1;
  std::vector<service::ProgressPoint> batch;
  for (int g = 1; g <= 2500; ++g) {
    batch.push_back(point(g));
    if (g % 37 == 0) {  // a progress event every 37 generations carries the ones since the last
      ASSERT_EQ(store->append_event("job-h", "owner", progress(g, ++seq), true, batch),
                service::JobStore::Append::stored);
      batch.clear();
    }
    if (g == 1200) {  // a checkpoint carries the unstored ones too; a resumed run repeats 1100..1200
      ASSERT_TRUE(store->put_checkpoint("job-h", "owner", g, "state", batch));
      batch.clear();
      for (int r = 1100; r <= 1200; ++r) batch.push_back(point(r));
    }
  }
  // Someone else (the lease lost) writes nothing.
  EXPECT_EQ(store->append_event("job-h", "intruder", progress(2600, 999), true, {point(2600)}),
            service::JobStore::Append::lost);
  v1::JobEvent done;
  done.set_sequence(++seq);
  done.mutable_state()->set_state(v1::JOB_STATE_SUCCEEDED);
  ASSERT_TRUE(store->finish("job-h", "owner", nullptr, {done}, batch));
  const auto history = store->progress_history("job-h");
  std::vector<int> got, want = {1};
  for (const auto& p : history) got.push_back(p.generation);
  for (int g = 4; g <= 2500; g += 4) want.push_back(g);
  EXPECT_EQ(got, want);
  for (const auto& p : history) {
    EXPECT_EQ(p.best_energy, point(p.generation).best_energy) << p.generation;
    EXPECT_EQ(p.mean_energy, point(p.generation).mean_energy) << p.generation;
  }
  EXPECT_TRUE(store->progress_history("job-unknown").empty());
  EXPECT_EQ(store->expire(1e18, 0), 1);
  EXPECT_TRUE(store->progress_history("job-h").empty());
}

// The journal of trial energies: written by the lease holder only, read back byte for byte
// by the entries that reach past a generation, an entry with the same first generation (a
// resumed run's) replacing the earlier; a checkpoint drops the entries it covers whole, the
// finish the rest, and it survives a reopen of the file (a restart after kill -9).
TEST(ServiceJobStore, JournalIsTheOwnersSinceTheCheckpointAndDroppedAtTheEnd) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("depath_journal_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string uri = "sqlite:" + (dir / "depath.db").string();
  auto entry = [](int first, int last) {
    std::string bytes(16 * (last - first + 1), '\0');
    for (size_t b = 0; b < bytes.size(); ++b)
      bytes[b] = static_cast<char>((first * 31 + b * 7) & 0xff);  // NULs too
    return service::JournalEntry{first, last, bytes};
  };
  auto firsts = [](const std::vector<service::JournalEntry>& entries) {
    std::vector<int> g;
    for (const auto& e : entries) g.push_back(e.first_generation);
    return g;
  };
  {
    const auto store = service::JobStore::open(uri);
    insert_and_claim(*store, "job-j");
    ASSERT_TRUE(store->append_journal("job-j", "owner", entry(0, 3)));
    ASSERT_TRUE(store->append_journal("job-j", "owner", entry(4, 4)));
    ASSERT_TRUE(store->append_journal("job-j", "owner", entry(5, 6)));
    ASSERT_TRUE(store->append_journal("job-j", "owner", entry(5, 9)));  // a resumed run's, longer
    EXPECT_FALSE(store->append_journal("job-j", "intruder", entry(10, 12)));
    EXPECT_EQ(firsts(store->journal_after("job-j", -1)), (std::vector<int>{0, 4, 5}));
    EXPECT_EQ(firsts(store->journal_after("job-j", 2)), (std::vector<int>{0, 4, 5}));  // 0-3 reaches past 2
    EXPECT_EQ(firsts(store->journal_after("job-j", 4)), (std::vector<int>{5}));
    EXPECT_TRUE(store->journal_after("job-j", 9).empty());
    EXPECT_TRUE(store->journal_after("job-other", -1).empty());
    ASSERT_TRUE(store->put_checkpoint("job-j", "owner", 4, "state"));  // covers 0-3 and 4 whole
  }
  {
    const auto store = service::JobStore::open(uri);  // reopened, as after a restart
    const auto left = store->journal_after("job-j", -1);
    ASSERT_EQ(firsts(left), (std::vector<int>{5}));
    EXPECT_EQ(left[0].last_generation, 9);
    EXPECT_EQ(left[0].energies, entry(5, 9).energies);
    ASSERT_TRUE(store->claim("owner", 1.0, 600));  // a reopened store voids the earlier process's leases
    v1::JobEvent done;
    done.set_sequence(2);
    done.mutable_state()->set_state(v1::JOB_STATE_SUCCEEDED);
    ASSERT_TRUE(store->finish("job-j", "owner", nullptr, {done}));
    EXPECT_TRUE(store->journal_after("job-j", -1).empty());
  }
  std::filesystem::remove_all(dir);
}

// ---- AccessGuard (tokens, failed-attempt limit, request rate) ------------------------------

TEST(AccessGuard, PeerHostDropsThePort) {
  EXPECT_EQ(service::AccessGuard::peer_host("ipv4:127.0.0.1:54321"), "127.0.0.1");
  EXPECT_EQ(service::AccessGuard::peer_host("ipv6:[::1]:54321"), "::1");
  EXPECT_EQ(service::AccessGuard::peer_host("unix:/tmp/s"), "unix:/tmp/s");
}

TEST(AccessGuard, RateLimiterRefillsAtItsRate) {
  service::RateLimiter limiter(/*rate=*/2.0, /*burst=*/3.0);
  const auto t0 = service::RateLimiter::Clock::now();
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(limiter.take("a", t0)) << i;
  EXPECT_FALSE(limiter.take("a", t0));
  EXPECT_TRUE(limiter.take("b", t0));  // another key has its own bucket
  EXPECT_DOUBLE_EQ(limiter.wait_seconds("a", t0), 0.5);
  EXPECT_FALSE(limiter.available("a", t0 + std::chrono::milliseconds(499)));
  EXPECT_TRUE(limiter.take("a", t0 + std::chrono::milliseconds(500)));
  EXPECT_FALSE(limiter.take("a", t0 + std::chrono::milliseconds(500)));
  // Refill is capped at the burst.
  const auto later = t0 + std::chrono::seconds(100);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(limiter.take("a", later)) << i;
  EXPECT_FALSE(limiter.take("a", later));
}

TEST(AccessGuard, AnyConfiguredTokenIsAcceptedAndNamedByPosition) {
  auto options = quiet_options();
  options.auth_tokens = {"alpha", "beta", "gamma"};
  options.auth_failure_burst = 100;
  service::Log log("text", "off");
  service::AccessGuard guard(options, log);
  ASSERT_TRUE(guard.auth_required());
  using Md = service::AccessGuard::Metadata;
  const std::string key = "authorization";
  auto call = [&](const std::string& value, std::string* client) {
    Md md;
    if (!value.empty()) md.emplace(grpc::string_ref(key), grpc::string_ref(value));
    return guard.check("ListJobs", md, "ipv4:10.1.2.3:999", client);
  };
  std::string client;
  ASSERT_TRUE(call("Bearer beta", &client).ok());
  EXPECT_EQ(client, "token #2");
  ASSERT_TRUE(call("Bearer gamma", &client).ok());
  EXPECT_EQ(client, "token #3");
  for (const std::string bad : {"", "Bearer ", "Bearer alph", "Bearer alphaa", "bearer alpha", "alpha", "Bearer  alpha"}) {
    const grpc::Status s = call(bad, nullptr);
    EXPECT_EQ(s.error_code(), StatusCode::UNAUTHENTICATED) << "'" << bad << "'";
  }
}

TEST(AccessGuard, NoAuthIdentifiesThePeerAndLimitsItsRate) {
  auto options = quiet_options();
  options.max_requests_per_second_per_client = 0.01;  // a bucket of 1, refilled after 100 s
  service::Log log("text", "off");
  service::AccessGuard guard(options, log);
  service::AccessGuard::Metadata md;
  std::string client;
  ASSERT_TRUE(guard.check("GetJob", md, "ipv4:10.0.0.7:1", &client).ok());
  EXPECT_EQ(client, "peer 10.0.0.7");
  const grpc::Status s = guard.check("GetJob", md, "ipv4:10.0.0.7:2", nullptr);  // same host, other port
  EXPECT_EQ(s.error_code(), StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(s.error_message().find("--max-requests-per-second-per-client"), std::string::npos) << s.error_message();
  EXPECT_TRUE(guard.check("GetJob", md, "ipv4:10.0.0.8:1", nullptr).ok());  // another peer
}

}  // namespace
}  // namespace depath::test
