// SPDX-License-Identifier: MIT
// Exact uniform geodesics (issue 13, item 4): every pair of truth/geodesic_exact.csv on the
// chosen shared meshes, solved by `descent` and by `de --refine`, each twice: as a job on a
// fresh mesh (solve() builds the fast-marching stencils, what every job paid before the
// server cached them) and as a job on a mesh the server has cached (solve() given the
// stencils built once per mesh, SolveHooks::stencils, exactly what depathd passes).
// The two runs of a pair run back to back, so their ratio holds on a busy machine; they must
// give the same path (checked: equal length and energy, else the program fails).
//
// Printed: per mesh the parse and stencil-build times, then per method the pairs within 0.1%
// of the exact length, the worst pair, the median and max wall time per path uncached and
// cached, the median CPU time per path (all threads; the figure that holds on a busy
// machine) and the median per-pair CPU ratio uncached / cached.
//
// Usage: bench_geodesic_table [--meshes LIST|all] [--methods LIST] [--threads T] [--data DIR]
//                             [--generations G] [--population P] [--pairs N]
//   --meshes       comma-separated file names (default: the 7 scanned models, i.e. every mesh
//                  of the table but the synthetic cone.off and terrain_grid30.obj: 84 pairs)
//   --methods      descent, de or both (default descent,de)
//   --threads      evaluation threads of each job (default 1: one core per path)
//   --generations, --population   DE settings (default: the job defaults, 100 and 20)
//   --pairs        at most N pairs per mesh (default all 12)
//   --each         also print every pair: its error and cached wall time per method
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "../tests/truth_tables.hpp"
#include "bench_stats.hpp"
#include "depath/decode/fast_marching.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/solve/solve.hpp"

namespace {

using namespace depath;
using bench::Clock;
using bench::cpu_seconds;
using bench::median;
using bench::seconds_since;

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

struct Run {
  std::string mesh;
  int source = 0, target = 0;
  double error = 0.0;                           // length / exact - 1
  double uncached = 0.0, cached = 0.0;          // wall seconds per path
  double uncached_cpu = 0.0, cached_cpu = 0.0;  // CPU seconds per path
};

void print_summary(const std::string& method, const std::vector<Run>& runs) {
  if (runs.empty()) return;
  int within = 0;
  const Run* worst = &runs.front();
  std::vector<double> uncached, cached, uncached_cpu, cached_cpu, ratio;
  for (const Run& r : runs) {
    within += r.error <= 1e-3;
    if (r.error > worst->error) worst = &r;
    uncached.push_back(r.uncached);
    cached.push_back(r.cached);
    uncached_cpu.push_back(r.uncached_cpu);
    cached_cpu.push_back(r.cached_cpu);
    ratio.push_back(r.uncached_cpu / r.cached_cpu);
  }
  std::printf(
      "%-8s %5zu %6d  %-24s %+7.3f%%  %8.1f %8.1f  %8.1f %8.1f  %8.1f %8.1f  %6.2fx\n", method.c_str(),
      runs.size(), within,
      (worst->mesh + " " + std::to_string(worst->source) + "->" + std::to_string(worst->target)).c_str(),
      100.0 * worst->error, 1e3 * median(uncached), 1e3 * median(cached),
      1e3 * *std::max_element(uncached.begin(), uncached.end()),
      1e3 * *std::max_element(cached.begin(), cached.end()), 1e3 * median(uncached_cpu),
      1e3 * median(cached_cpu), median(ratio));
}

}  // namespace

int main(int argc, char** argv) {
  std::string data = DEPATH_SHARED_DATA, meshes_arg, methods_arg = "descent,de";
  int threads = 1, generations = 0, population = 0, max_pairs = 1 << 30;
  bool each = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--meshes" && has_value)
      meshes_arg = argv[++i];
    else if (arg == "--methods" && has_value)
      methods_arg = argv[++i];
    else if (arg == "--threads" && has_value)
      threads = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--data" && has_value)
      data = argv[++i];
    else if (arg == "--generations" && has_value)
      generations = std::atoi(argv[++i]);
    else if (arg == "--population" && has_value)
      population = std::atoi(argv[++i]);
    else if (arg == "--pairs" && has_value)
      max_pairs = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--each")
      each = true;
    else {
      std::fprintf(stderr,
                   "usage: bench_geodesic_table [--meshes LIST|all] [--methods LIST] [--threads T] "
                   "[--data DIR] [--generations G] [--population P] [--pairs N] [--each]\n");
      return 2;
    }
  }
  try {
    std::vector<test::ExactGeodesic> pairs = test::read_exact_geodesics(data + "/truth/geodesic_exact.csv");
    if (pairs.empty()) throw std::runtime_error("no pairs in " + data + "/truth/geodesic_exact.csv");
    std::vector<std::string> meshes;
    for (const auto& p : pairs) {
      if (std::find(meshes.begin(), meshes.end(), p.mesh) == meshes.end()) meshes.push_back(p.mesh);
    }
    if (meshes_arg.empty()) {
      std::erase_if(meshes,
                    [](const std::string& m) { return m == "cone.off" || m == "terrain_grid30.obj"; });
    } else if (meshes_arg != "all") {
      meshes = split(meshes_arg);
    }
    const std::vector<std::string> methods = split(methods_arg);

    std::printf(
        "threads per job %d; DE population %s, generations %s, refine on; descent: fmm path + refinement\n",
        threads, population ? std::to_string(population).c_str() : "default",
        generations ? std::to_string(generations).c_str() : "default");
    std::printf("%-20s %8s %10s %12s %12s\n", "mesh", "vertices", "parse ms", "stencils ms", "stencils MB");
    std::map<std::string, std::vector<Run>> runs;  // per method
    for (const std::string& name : meshes) {
      auto t0 = Clock::now();
      const Mesh mesh = load_mesh(data + "/meshes/" + name);
      const double parse = seconds_since(t0);
      t0 = Clock::now();
      const FastMarchingStencils stencils(mesh);  // the server's cached copy
      const double build = seconds_since(t0);
      std::printf("%-20s %8d %10.1f %12.1f %12.2f\n", name.c_str(), mesh.num_vertices(), 1e3 * parse,
                  1e3 * build, double(stencils.memory_bytes()) / (1 << 20));
      std::fflush(stdout);
      int done = 0;
      for (const auto& pair : pairs) {
        if (pair.mesh != name || done >= max_pairs) continue;
        ++done;
        for (const std::string& method : methods) {
          JobSpec job;
          job.source = pair.source;
          job.target = pair.target;
          job.method = parse_method(method);
          job.refine = true;
          job.threads = threads;
          if (generations > 0) job.de.generations = generations;
          if (population > 0) job.de.population = population;
          double c0 = cpu_seconds();
          t0 = Clock::now();
          const SolveResult fresh = solve(mesh, job);
          const double uncached = seconds_since(t0), uncached_cpu = cpu_seconds() - c0;
          SolveHooks hooks;
          hooks.stencils = &stencils;
          const uint64_t builds = FastMarchingStencils::builds();
          c0 = cpu_seconds();
          t0 = Clock::now();
          const SolveResult reused = solve(mesh, job, hooks);
          const double cached = seconds_since(t0), cached_cpu = cpu_seconds() - c0;
          if (FastMarchingStencils::builds() != builds || reused.energy != fresh.energy ||
              reused.length != fresh.length)
            throw std::runtime_error("the cached run differs from the uncached one (or built stencils) on " +
                                     name);
          runs[method].push_back({name, pair.source, pair.target, fresh.length / pair.length - 1.0, uncached,
                                  cached, uncached_cpu, cached_cpu});
          if (each) {
            std::printf("  %-8s %-16s %6d -> %-6d %+8.4f%%  %8.1f ms cached\n", method.c_str(), name.c_str(),
                        pair.source, pair.target, 100.0 * runs[method].back().error, 1e3 * cached);
          }
        }
      }
    }
    std::printf(
        "\nwall and CPU time per path, ms; unc = fresh mesh (stencils built by the job), cache = cached "
        "mesh\n");
    std::printf("%-8s %5s %6s  %-24s %8s  %8s %8s  %8s %8s  %8s %8s  %7s\n", "method", "pairs", "<=0.1%",
                "worst pair", "worst", "med unc", "med cach", "max unc", "max cach", "cpu unc", "cpu cach",
                "ratio");
    std::printf("%-8s %5s %6s  %-24s %8s  %8s %8s  %8s %8s  %8s %8s  %7s\n", "", "", "", "", "", "wall",
                "wall", "wall", "wall", "median", "median", "cpu u/c");
    for (const std::string& method : methods) print_summary(method, runs[method]);
    std::printf("\nper mesh (median CPU ms per path uncached / cached, pairs within 0.1%%, worst):\n");
    for (const std::string& method : methods) {
      for (const std::string& name : meshes) {
        std::vector<double> u, c;
        int within = 0;
        double worst = -1.0;
        for (const Run& r : runs[method]) {
          if (r.mesh != name) continue;
          u.push_back(r.uncached_cpu);
          c.push_back(r.cached_cpu);
          within += r.error <= 1e-3;
          worst = std::max(worst, r.error);
        }
        if (u.empty()) continue;
        std::printf("  %-8s %-20s %8.1f / %8.1f   %2d/%zu   worst %+.3f%%\n", method.c_str(), name.c_str(),
                    1e3 * median(u), 1e3 * median(c), within, u.size(), 100.0 * worst);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_geodesic_table: %s\n", e.what());
    return 1;
  }
  return 0;
}
