// SPDX-License-Identifier: MIT
// Time per decode (fast marching + back-trace + energy) on each shared mesh.
//
//   build/bench/decode_benchmark [--benchmark_filter=bimba]
//
// Reports, per mesh: a full-mesh fast march (no early stop), a decode with the early stop
// at the target (what DE does thousands of times), and throughput in vertices per second.
#include "depath/energy/energy.hpp"
#include "depath/decode/fast_marching.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/decode/path_decoder.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace {

const char* kMeshes[] = {"terrain_grid30.obj", "cone.off",      "kitten.off",    "beethoven.ply", "dragon.obj",
                         "camelhead.off",      "bimba.obj",     "bunny.off",     "armadillo.obj"};

std::string shared_mesh(const std::string& name) { return std::string(DEPATH_SHARED_DATA) + "/meshes/" + name; }

// Random densities are cycled through, never repeated back to back: with one density, the
// branch predictor learns a small mesh's whole march by heart (terrain_grid30 ran at
// 22.7 M vertices/s on a repeated density, 9 M/s on fresh ones, as DE's trials are).
constexpr int kDensities = 16;

struct Fixture {
  std::unique_ptr<depath::Mesh> mesh;
  std::unique_ptr<depath::FastMarchingStencils> stencils;
  std::vector<std::vector<double>> densities;  // kDensities DE-like random densities
};

Fixture& fixture(const std::string& name) {
  static std::map<std::string, Fixture> cache;
  Fixture& f = cache[name];
  if (!f.mesh) {
    f.mesh = std::make_unique<depath::Mesh>(depath::load_mesh(shared_mesh(name)));
    f.stencils = std::make_unique<depath::FastMarchingStencils>(*f.mesh);
    // DE-like random densities in (0, 1].
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(1e-9, 1.0);
    f.densities.assign(kDensities, std::vector<double>(f.mesh->num_vertices()));
    for (auto& density : f.densities)
      for (double& d : density) d = u(rng);
  }
  return f;
}

void full_march(benchmark::State& state, std::string name) {
  Fixture& f = fixture(name);
  depath::FastMarching fm(*f.stencils);
  int k = 0;
  for (auto _ : state) {
    fm.run(f.densities[k++ % kDensities], 0);
    benchmark::DoNotOptimize(fm.value(f.mesh->num_vertices() - 1));
  }
  state.counters["vertices"] = f.mesh->num_vertices();
  state.counters["vertices/s"] =
      benchmark::Counter(double(f.mesh->num_vertices()) * state.iterations(), benchmark::Counter::kIsRate);
}

// A far-away target: the last vertex of the file's main component.
int far_target(const depath::Mesh& mesh, int source) {
  int target = mesh.num_vertices() - 1;
  while (target > 0 && (mesh.component(target) != mesh.component(source) || !mesh.is_referenced(target))) --target;
  return target;
}

void decode_to_target(benchmark::State& state, std::string name, bool uniform) {
  Fixture& f = fixture(name);
  depath::PathDecoder decoder(*f.stencils);
  depath::EnergySpec spec;
  if (!uniform) spec.density = f.densities[0];
  const auto energy = depath::make_energy(*f.mesh, spec);
  const std::vector<double> ones(f.mesh->num_vertices(), 1.0);
  depath::SurfacePath path;
  const int source = 0;
  const int target = far_target(*f.mesh, source);
  double e = 0;
  int k = 0;
  for (auto _ : state) {
    decoder.decode(uniform ? ones : f.densities[k++ % kDensities], source, target, path);
    e = energy->evaluate(path);
    benchmark::DoNotOptimize(e);
  }
  state.counters["path_points"] = double(path.points.size());
  state.counters["marched"] = decoder.fast_marching().num_final();
}

// What DE does per trial: decode_log (densities as logarithms, exponentiated on the fly).
void decode_log_to_target(benchmark::State& state, std::string name) {
  Fixture& f = fixture(name);
  depath::PathDecoder decoder(*f.stencils);
  std::vector<std::vector<double>> log_densities = f.densities;
  for (auto& density : log_densities)
    for (double& d : density) d = std::log(d);
  depath::SurfacePath path;
  const int source = 0;
  const int target = far_target(*f.mesh, source);
  int k = 0;
  for (auto _ : state) {
    decoder.decode_log(log_densities[k++ % kDensities], source, target, path);
    benchmark::DoNotOptimize(path.points.data());
  }
  state.counters["path_points"] = double(path.points.size());
  state.counters["marched"] = decoder.fast_marching().num_final();
}

int register_all() {
  if (!std::filesystem::exists(shared_mesh("kitten.off"))) return 0;
  for (const char* m : kMeshes) {
    benchmark::RegisterBenchmark((std::string("full_march/") + m).c_str(), full_march, std::string(m))
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark((std::string("decode_uniform/") + m).c_str(), decode_to_target, std::string(m), true)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark((std::string("decode_random/") + m).c_str(), decode_to_target, std::string(m), false)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark((std::string("decode_log/") + m).c_str(), decode_log_to_target, std::string(m))
        ->Unit(benchmark::kMillisecond);
  }
  return 0;
}
const int registered = register_all();

}  // namespace

BENCHMARK_MAIN();
