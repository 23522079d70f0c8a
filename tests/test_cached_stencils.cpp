// SPDX-License-Identifier: MIT
// solve() with the caller's fast-marching stencils (SolveHooks::stencils, what the server's
// mesh cache passes): no table is built, and the result is bit-identical to a solve() that
// builds its own, for every method.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "depath/decode/fast_marching.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/solve/solve.hpp"
#include "depath/util/error.hpp"
#include "job_builders.hpp"
#include "path_checks.hpp"
#include "test_support.hpp"

namespace depath {
namespace {

const Mesh& kitten() {
  static const Mesh mesh = load_mesh(test::test_data("kitten.off"));
  return mesh;
}

std::vector<JobSpec> jobs() {
  JobSpec fmm;
  fmm.source = 0;
  fmm.target = 1500;
  fmm.method = Method::fmm;
  fmm.threads = 1;
  JobSpec descent = fmm;
  descent.method = Method::descent;
  descent.refine = true;
  JobSpec de = test::de_job(0, 1500, 12, 15, 7, 2);
  de.refine = true;
  return {fmm, descent, de};
}

TEST(CachedStencils, SolveWithTheCallersStencilsBuildsNoneAndGivesTheSameResult) {
  const Mesh& mesh = kitten();
  const FastMarchingStencils cached(mesh);
  for (const JobSpec& job : jobs()) {
    SCOPED_TRACE(method_name(job.method));
    const uint64_t before = FastMarchingStencils::builds();
    const SolveResult own = solve(mesh, job);
    EXPECT_EQ(FastMarchingStencils::builds(), before + 1)
        << "solve() without stencils builds exactly one table";
    SolveHooks hooks;
    hooks.stencils = &cached;
    const SolveResult first = solve(mesh, job, hooks);
    const SolveResult second = solve(mesh, job, hooks);
    EXPECT_EQ(FastMarchingStencils::builds(), before + 1) << "solve() rebuilt the stencils it was given";
    EXPECT_TRUE(test::identical_results(own, first));
    EXPECT_TRUE(test::identical_results(own, second));
  }
}

TEST(CachedStencils, StencilsOfAnotherMeshAreRefused) {
  const Mesh copy = kitten();  // same geometry, another object: the stencils refer to the other
  const FastMarchingStencils stencils(copy);
  SolveHooks hooks;
  hooks.stencils = &stencils;
  try {
    (void)solve(kitten(), jobs()[0], hooks);
    ADD_FAILURE() << "accepted stencils of another mesh";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
    EXPECT_NE(std::string(e.what()).find("another mesh"), std::string::npos) << e.what();
  }
}

TEST(CachedStencils, MemoryIsCountedForTheCacheBudget) {
  const FastMarchingStencils stencils(kitten());
  // At least one group (16 bytes) per directed edge: 3 per face.
  EXPECT_GE(stencils.memory_bytes(), uint64_t(3 * kitten().num_faces() * 16));
}

}  // namespace
}  // namespace depath
