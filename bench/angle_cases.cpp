// SPDX-License-Identifier: MIT
// The angle energies on random analytic cases (tests/random_cases.hpp, issue 12): for each
// family (contour fields on Gaussian terrains, constant-slope spirals on cones) and each
// smoothness lambda, `de --refine` over many seeded instances; prints per instance the
// figure (normalized field energy / mean slope error), the total turning and the time, then
// the distribution per family and lambda (median, worst, mean time per solve).
//
// Usage: bench_angle_cases [--family contour|spiral|both] [--count N] [--first SEED]
//                          [--lambdas 0,0.01,0.1] [--population P] [--generations G]
//                          [--threads T] [--strategy NAME] [--no-refine] [--diagnose] [--quiet]
// --diagnose: per instance, the turning of the fmm path, of DE's best decoded path and of the
// refined path (penalty-free problem), in the surface and in 3D, and the points per path.
#include "depath/energy/energy.hpp"
#include "depath/solve/solve.hpp"
#include "../tests/angle_job.hpp"
#include "../tests/random_cases.hpp"
#include "bench_stats.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

namespace {

using depath::bench::median;

using namespace depath;

struct Figures {
  std::vector<double> figure, turning, seconds;
};

// Sum of 3D angles between consecutive segments (what the penalty measured before issue 12).
double turning_3d(const Mesh& mesh, const SurfacePath& path) {
  const std::vector<Vec3> p = path_positions(mesh, path);
  double sum = 0.0;
  for (size_t i = 1; i + 1 < p.size(); ++i) {
    const Vec3 a = p[i] - p[i - 1], b = p[i + 1] - p[i];
    if (a.norm() > 0 && b.norm() > 0) sum += std::atan2(a.cross(b).norm(), a.dot(b));
  }
  return sum;
}

void diagnose_case(const test::AngleCase& c, int population, int generations, int threads) {
  JobSpec job = test::angle_job(c, 0.0, population, generations, threads);
  const char* names[3] = {"fmm (decoded)", "de best decoded", "de --refine"};
  for (int k = 0; k < 3; ++k) {
    job.method = k == 0 ? Method::fmm : Method::de;
    job.refine = k == 2;
    const SolveResult r = solve(c.mesh, job);
    std::printf("    %-16s turning in surface %7.3f  3D %7.3f  points %4zu  normalized %.4f\n", names[k],
                test::total_turning(c.mesh, r.path), turning_3d(c.mesh, r.path), r.path.points.size(),
                test::result_metric(r, "normalized_energy"));
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string family = "both", strategy = "shade";
  int count = 20, population = test::kAnglePopulation, generations = test::kAngleGenerations, threads = 2;
  uint64_t first = 1;
  bool quiet = false, refine = true, diagnose = false;
  std::vector<double> lambdas = {0.0, 0.1};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "%s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--family") family = next();
    else if (a == "--count") count = std::atoi(next().c_str());
    else if (a == "--first") first = std::strtoull(next().c_str(), nullptr, 10);
    else if (a == "--population") population = std::atoi(next().c_str());
    else if (a == "--generations") generations = std::atoi(next().c_str());
    else if (a == "--threads") threads = std::atoi(next().c_str());
    else if (a == "--strategy") strategy = next();
    else if (a == "--quiet") quiet = true;
    else if (a == "--no-refine") refine = false;
    else if (a == "--diagnose") diagnose = true;
    else if (a == "--lambdas") {
      lambdas.clear();
      std::stringstream ss(next());
      std::string item;
      while (std::getline(ss, item, ',')) lambdas.push_back(std::atof(item.c_str()));
    } else {
      std::fprintf(stderr, "unknown option %s\n", a.c_str());
      return 2;
    }
  }
  std::vector<test::AngleFamily> families;
  if (family == "contour" || family == "both") families.push_back(test::AngleFamily::contour);
  if (family == "spiral" || family == "both") families.push_back(test::AngleFamily::spiral);

  std::printf("de --refine, %s, %d agents x %d generations, %d threads; figure = normalized field energy "
              "(contour) / mean |dz/ds - k| (spiral)\n",
              strategy.c_str(), population, generations, threads);
  std::vector<std::vector<Figures>> table(families.size(), std::vector<Figures>(lambdas.size()));
  for (size_t f = 0; f < families.size(); ++f) {
    const bool spiral = families[f] == test::AngleFamily::spiral;
    for (uint64_t seed = first; seed < first + count; ++seed) {
      const test::AngleCase c = test::random_angle_case(families[f], seed);
      if (!quiet) std::printf("%-7s seed %3d  %s\n", spiral ? "spiral" : "contour", static_cast<int>(seed), c.description.c_str());
      if (diagnose) {
        diagnose_case(c, population, generations, threads);
        continue;
      }
      for (size_t l = 0; l < lambdas.size(); ++l) {
        JobSpec job = test::angle_job(c, lambdas[l], population, generations, threads);
        job.de.strategy = strategy;
        job.refine = refine;
        const SolveResult r = solve(c.mesh, job);
        const double figure = test::result_metric(r, spiral ? "mean_slope_error" : "normalized_energy");
        const double turning = test::total_turning(c.mesh, r.path);
        const double charged = test::penalty_turning(c.mesh, job.energy, r.path);
        table[f][l].figure.push_back(figure);
        table[f][l].turning.push_back(turning);
        table[f][l].seconds.push_back(r.seconds);
        if (!quiet)
          std::printf("    lambda %-5g figure %.4f  turning %6.3f  charged %6.3f  energy %8.4f  length %7.3f  %.2fs\n",
                      lambdas[l], figure, turning, charged, r.energy, r.length, r.seconds);
      }
      std::fflush(stdout);
    }
  }
  if (diagnose) return 0;
  std::printf("\n%-8s %-7s %9s %9s %14s %14s %10s\n", "family", "lambda", "median", "worst", "turning med", "turning worst",
              "s/solve");
  for (size_t f = 0; f < families.size(); ++f) {
    for (size_t l = 0; l < lambdas.size(); ++l) {
      const Figures& x = table[f][l];
      double mean_s = 0;
      for (double s : x.seconds) mean_s += s;
      mean_s /= std::max<size_t>(1, x.seconds.size());
      std::printf("%-8s %-7g %9.4f %9.4f %14.3f %14.3f %10.2f\n",
                  families[f] == test::AngleFamily::spiral ? "spiral" : "contour", lambdas[l], median(x.figure),
                  *std::max_element(x.figure.begin(), x.figure.end()), median(x.turning),
                  *std::max_element(x.turning.begin(), x.turning.end()), mean_s);
    }
  }
  return 0;
}
