// SPDX-License-Identifier: MIT
// solve(): the job rules of SPEC §2 (each error names the problem) and the result writers.
#include "depath/util/error.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/io/result_writer.hpp"
#include "depath/io/vertex_data.hpp"
#include "depath/solve/solve.hpp"
#include "job_builders.hpp"
#include "path_checks.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace depath {
namespace {

const Mesh& cone() {
  static const Mesh mesh = load_mesh(test::test_data("cone.off"));
  return mesh;
}

JobSpec fmm_job(int s = 0, int t = 348) { return test::method_job(Method::fmm, s, t); }

void expect_error(const Mesh& mesh, const JobSpec& job, ErrorCode code, const std::string& words) {
  try {
    (void)solve(mesh, job);
    ADD_FAILURE() << "accepted; expected an error mentioning '" << words << "'";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), code) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << "message: " << e.what();
  }
}

TEST(SolveJobs, RejectsEachBadJobNamingTheProblem) {
  const Mesh& mesh = cone();
  JobSpec job = fmm_job();
  job.source = mesh.num_vertices();
  expect_error(mesh, job, ErrorCode::invalid_argument, "source vertex 1153 is out of range");
  job = fmm_job();
  job.target = -1;
  expect_error(mesh, job, ErrorCode::invalid_argument, "target vertex -1 is out of range");
  job = fmm_job(7, 7);
  expect_error(mesh, job, ErrorCode::invalid_argument, "same vertex");
  job = fmm_job();
  job.de.population = 3;
  expect_error(mesh, job, ErrorCode::invalid_argument, "population");
  job = fmm_job();
  job.de.generations = 0;
  expect_error(mesh, job, ErrorCode::invalid_argument, "generations");
  job = fmm_job();
  job.de.F = 0.0;
  expect_error(mesh, job, ErrorCode::invalid_argument, "F must be");
  job = fmm_job();
  job.de.F = std::numeric_limits<double>::quiet_NaN();
  expect_error(mesh, job, ErrorCode::invalid_argument, "F must be");
  job = fmm_job();
  job.de.CR = 1.5;
  expect_error(mesh, job, ErrorCode::invalid_argument, "CR must be");
  job = fmm_job();
  job.energy.density.assign(10, 1.0);
  expect_error(mesh, job, ErrorCode::invalid_argument, "density has 10 values but the mesh has 1153");
  job = fmm_job();
  job.energy.density.assign(mesh.num_vertices(), 1.0);
  job.energy.density[42] = -1.0;
  expect_error(mesh, job, ErrorCode::invalid_argument, "density at vertex 42");
  job.energy.density[42] = std::numeric_limits<double>::infinity();
  expect_error(mesh, job, ErrorCode::invalid_argument, "density at vertex 42");
  job = fmm_job();
  job.energy.smoothness = -1.0;
  expect_error(mesh, job, ErrorCode::invalid_argument, "smoothness");
  job = fmm_job();
  job.energy.kind = EnergyKind::vector_field;
  job.energy.field.assign(5, Vec3(1, 0, 0));
  expect_error(mesh, job, ErrorCode::invalid_argument, "field");
}

TEST(SolveJobs, DensityZeroAndOutOfRangeAreRefusedNotNoPath) {
  const Mesh& mesh = cone();
  JobSpec job = fmm_job();
  job.energy.density.assign(mesh.num_vertices(), 1.0);
  job.energy.density[7] = 0.0;
  expect_error(mesh, job, ErrorCode::invalid_argument, "density at vertex 7 is 0: densities must be finite and > 0");
  for (double d : {1e308, 1e-308, 1e101, 1e-101}) {
    job.energy.density.assign(mesh.num_vertices(), d);
    expect_error(mesh, job, ErrorCode::invalid_argument, "densities must lie in [1e-100, 1e100]");
  }
}

TEST(SolveJobs, DensitiesAtTheEndsOfTheRangeScaleTheEnergyOnly) {
  const Mesh& mesh = cone();
  const SolveResult unit = solve(mesh, fmm_job());
  for (double d : {1e100, 1e-100}) {
    JobSpec job = fmm_job();
    job.energy.density.assign(mesh.num_vertices(), d);
    const SolveResult scaled = solve(mesh, job);
    EXPECT_NEAR(scaled.length, unit.length, 1e-9 * unit.length) << d;
    EXPECT_NEAR(scaled.energy / d, unit.energy, 1e-9 * unit.energy) << d;
  }
}

TEST(SolveJobs, DifferentComponentsIsFailedPrecondition) {
  DEPATH_REQUIRE_SHARED_DATA();
  const Mesh mesh = load_mesh(test::shared_data("meshes/beethoven.ply"));
  ASSERT_EQ(mesh.num_components(), 3);
  // The stray triangles are the last vertices of the file; find one outside the main body.
  int stray = -1;
  for (int v = mesh.num_vertices() - 1; v >= 0 && stray < 0; --v)
    if (mesh.component(v) != mesh.component(0) && mesh.is_referenced(v)) stray = v;
  ASSERT_GE(stray, 0);
  expect_error(mesh, fmm_job(0, stray), ErrorCode::failed_precondition, "different connected components");
}

TEST(SolveJobs, UnreferencedVertexIsRejected) {
  const Mesh mesh({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(5, 5, 5)}, {{0, 1, 2}});
  expect_error(mesh, fmm_job(0, 3), ErrorCode::invalid_argument, "used by no face");
}

TEST(SolveJobs, FmmResultFieldsAndWriters) {
  const Mesh& mesh = cone();
  const SolveResult r = solve(mesh, fmm_job());
  EXPECT_TRUE(test::is_valid_path(mesh, r.path, 0, 348));
  EXPECT_DOUBLE_EQ(r.energy, r.fmm_energy);
  EXPECT_NEAR(r.energy, r.length, 1e-9 * r.length);  // uniform density: energy is length
  EXPECT_EQ(r.method, Method::fmm);

  const nlohmann::json j = nlohmann::json::parse(result_json(mesh, r));
  for (const char* key : {"points", "crossings", "energy", "length", "method", "generations", "evaluations",
                          "seconds", "fmm_energy"})
    EXPECT_TRUE(j.contains(key)) << key;
  ASSERT_EQ(j["points"].size(), r.path.points.size());
  EXPECT_EQ(j["crossings"][0]["vertex"], 0);
  EXPECT_EQ(j["method"], "fmm");

  const auto dir = std::filesystem::temp_directory_path() / ("depath_writers_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  write_result((dir / "p.json").string(), mesh, r);
  std::ifstream json_in(dir / "p.json");
  EXPECT_EQ(nlohmann::json::parse(json_in)["energy"].get<double>(), r.energy);

  write_result((dir / "p.csv").string(), mesh, r);
  std::ifstream csv(dir / "p.csv");
  std::string line;
  int rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, static_cast<int>(r.path.points.size()) + 1);

  write_result((dir / "p.obj").string(), mesh, r);
  const Mesh reread_points_only = [&] {
    std::ifstream obj(dir / "p.obj");
    std::stringstream ss;
    ss << obj.rdbuf();
    EXPECT_NE(ss.str().find("\nl 1 2"), std::string::npos);
    return mesh;
  }();
  write_result((dir / "p.ply").string(), mesh, r);
  std::ifstream ply(dir / "p.ply");
  std::getline(ply, line);
  EXPECT_EQ(line, "ply");

  try {
    write_result((dir / "p.txt").string(), mesh, r);
    ADD_FAILURE() << "unknown extension accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(".json, .obj, .ply or .csv"), std::string::npos);
  }
  std::filesystem::remove_all(dir);
}

TEST(SolveJobs, ScalarFilesReportLineOfBadValue) {
  const auto path = std::filesystem::temp_directory_path() / ("depath_scalars_" + std::to_string(::getpid()));
  std::ofstream(path) << "1.0\n# comment\n2.5\nabc\n";
  try {
    (void)read_scalar_file(path.string());
    ADD_FAILURE() << "bad value accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("line 4"), std::string::npos) << e.what();
  }
  std::ofstream(path) << "1.0\n# comment\n2.5\n";
  EXPECT_EQ(read_scalar_file(path.string()), (std::vector<double>{1.0, 2.5}));
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace depath
