// SPDX-License-Identifier: MIT
// The mesh cache keeps each mesh's fast-marching stencils: the first job on a mesh builds
// them, later jobs on the cached mesh build none (counted, not timed), the cache counts
// their memory, and the results are the same as a solve() that builds its own.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "depath/decode/fast_marching.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/solve/solve.hpp"
#include "mesh_store.hpp"
#include "service_test_support.hpp"

namespace depath::test {
namespace {

// The store itself: two leases share one build, and the record's memory (so the cache's
// bytes) grows by the stencils' memory.
TEST(ServiceMeshCache, LeasesShareOneStencilBuildCountedInTheCache) {
  depath::service::Log log("text", "off");
  const auto memory = service::JobStore::open("memory");
  service::MeshStore store(1ull << 30, *memory, log);
  const std::string id(64, 'a');
  const uint64_t mesh_bytes = store.add(id, "grid.obj", "obj", grid_obj(12)).memory_bytes();
  EXPECT_EQ(store.cached_bytes(), mesh_bytes);
  EXPECT_EQ(store.cache_stats().stencil_builds, 0u) << "an upload builds no stencils";

  const FastMarchingStencils* first = nullptr;
  {
    auto lease = store.acquire(id);
    first = &lease->stencils();
    EXPECT_EQ(&first->mesh(), &lease->mesh());
    EXPECT_EQ(&lease->stencils(), first);
  }
  EXPECT_EQ(store.cache_stats().stencil_builds, 1u);
  EXPECT_EQ(store.cached_bytes(), mesh_bytes + first->memory_bytes()) << "stencils kept after their job";
  EXPECT_EQ(store.get(id).memory_bytes(), mesh_bytes + first->memory_bytes());
  {
    auto lease = store.acquire(id);
    EXPECT_EQ(&lease->stencils(), first) << "a second job got other stencils";
  }
  EXPECT_EQ(store.cache_stats().stencil_builds, 1u);
  store.remove(id);
  EXPECT_EQ(store.cached_bytes(), 0u);
}

// Stencils are derived data: building them never evicts a mesh (in a memory store the only
// copy of an upload), and over budget the stencils of meshes no job holds go first.
TEST(ServiceMeshCache, StencilsNeverEvictAMeshAndGoFirstOverBudget) {
  depath::service::Log log("text", "off");
  const auto memory = service::JobStore::open("memory");
  const std::string a(64, 'a'), b(64, 'b'), c(64, 'c');
  uint64_t mesh_bytes = 0, stencil_bytes = 0;
  {
    service::MeshStore probe(1ull << 30, *memory, log);
    mesh_bytes = probe.add(a, "a.obj", "obj", grid_obj(12)).memory_bytes();
    stencil_bytes = probe.acquire(a)->stencils().memory_bytes();
  }
  ASSERT_GT(stencil_bytes, 0u);
  // Room for two meshes, not for two meshes and a's stencils.
  service::MeshStore store(2 * mesh_bytes + stencil_bytes / 2, *memory, log);
  store.add(a, "a.obj", "obj", grid_obj(12));
  store.add(b, "b.obj", "obj", grid_obj(12, 0.5));
  {
    auto lease = store.acquire(a);
    lease->stencils();  // a job on a: over budget while it holds them
    EXPECT_EQ(store.cached_bytes(), 2 * mesh_bytes + stencil_bytes);
    EXPECT_EQ(store.cache_stats().evictions, 0u) << "building stencils evicted a mesh";
    EXPECT_NO_THROW(store.get(b));
  }
  // The job is done: a's stencils are the first thing to go, and both meshes stay.
  EXPECT_EQ(store.cached_bytes(), 2 * mesh_bytes);
  EXPECT_EQ(store.cache_stats().evictions, 0u);
  EXPECT_NO_THROW(store.get(a));
  EXPECT_NO_THROW(store.get(b));
  // A third mesh over budget: a mesh goes (the least recently used), as before.
  store.add(c, "c.obj", "obj", grid_obj(12, 0.25));
  EXPECT_EQ(store.cache_stats().evictions, 1u);
  EXPECT_EQ(store.cached_bytes(), 2 * mesh_bytes);
}

// Through the service: two jobs on one uploaded mesh build the stencils once (the build
// counter of this process, where the server runs), and both results equal, bit for bit, a
// local solve() that builds its own.
TEST(ServiceMeshCache, SecondJobOnACachedMeshBuildsNoStencils) {
  TestServer ts;
  const std::string obj = grid_obj(15);
  const std::string id = ts.upload_ok(obj);
  auto spec = job_spec(id, 3, 220, v1::METHOD_DE);
  spec.set_refine(true);

  auto run = [&] {
    std::vector<v1::JobEvent> events;
    const auto status = ts.watch(ts.submit_ok(spec), 0, &events);
    EXPECT_TRUE(status.ok()) << status.error_message();
    const auto* result = find_result(events);
    return result ? *result : v1::JobResult{};
  };
  const uint64_t before = FastMarchingStencils::builds();
  const v1::JobResult first = run();
  EXPECT_EQ(FastMarchingStencils::builds(), before + 1);
  const v1::JobResult second = run();
  EXPECT_EQ(FastMarchingStencils::builds(), before + 1)
      << "the second job rebuilt the cached mesh's stencils";

  const Mesh mesh = load_mesh_from_bytes(obj, "obj", "grid");
  const SolveResult local = solve(mesh, wire::job_from_proto(spec));
  v1::JobResult expected;
  wire::result_to_proto(mesh, local, &expected);
  expected.set_seconds(0);  // the one figure that is a clock
  for (v1::JobResult r : {first, second}) {
    ASSERT_EQ(r.path().points_size(), static_cast<int>(local.path.points.size()));
    EXPECT_EQ(r.energy(), local.energy);  // bit for bit
    r.set_seconds(0);
    EXPECT_EQ(r.SerializeAsString(), expected.SerializeAsString());
  }

  v1::GetMeshRequest get;
  get.set_id(id);
  v1::MeshInfo info;
  auto ctx = ts.context();
  ASSERT_TRUE(ts.meshes().GetMesh(ctx.get(), get, &info).ok());
  EXPECT_GT(info.memory_bytes(), wire::mesh_memory_bytes(mesh))
      << "the stencils are not counted in the cache";
}

}  // namespace
}  // namespace depath::test
