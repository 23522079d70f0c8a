// SPDX-License-Identifier: MIT
// Table 1 of the DE-Path paper ("Computation times of our method"), re-run row by row from
// the paper's own figures (shared data: paper/table1.csv, read at run time): each row's
// experiment on a mesh with the paper's vertex count, the paper's agents (population) and
// iterations (generations), `de` with rand1bin and the paper's random initialisation.
// Printed per row: our wall time for the whole solve, the paper's, their ratio, our CPU per
// evaluation, how much of the mesh one decode marches over the whole run and for the initial
// agents (evolved populations can march much more), the CPU per marched vertex, and the
// quality reached.
//
// Rows and meshes (vertex ids chosen so the paths cross most of the surface):
//  - vector field, simple converge: flat n x n grid over [-3, 3]^2 (n = sqrt of the paper's
//    count: 41, 81, 121), field (1, -y) (`depath generate grid --field converge`),
//    s = (n/2) n + n/8, t = (n/3) n + 7n/8 (the acceptance check's pair).
//  - simple rotation: flat grid over [-1, 1]^2, circles around the centre, s = (0.45, -0.6),
//    t = (-0.45, -0.6) on one circle (the test suite's Fig. 7 pair).
//  - complex 1 / complex 2: MATLAB peaks grid, its height gradient rotated by 90 degrees
//    (contour lines), smoothness 0.1 (the paper's Fig. 3 setting); two s/t pairs on the
//    same field (the paper's second field is not available).
//  - constant slope (k from the application text): a cone of 20 rings x 84 sectors + apex
//    (1,681 vertices, height 1, radius 1), rim -> half radius at 120 degrees; the peaks grid.
//  - geodesics on the shared meshes (their vertex counts differ from the paper's: kitten
//    2,500 vs 1,370, dragon 10,002 vs 5,098, beethoven 2,521 vs 10,406, bimba 23,112 vs
//    15,653), so the ratio is per evaluation and per vertex:
//      ratio = (paper s / paper evaluations / paper vertices) / (ours s / our evaluations / our vertices).
//    Kitten and Dragon: uniform density, a pair of truth/geodesic_exact.csv (quality = our
//    length / exact). Beethoven: its bumps density, a pair of truth/weighted_steiner.csv
//    (quality = energy / Steiner cost, 16 points per edge). Bimba: no shared density, so a
//    Gaussian bump 1 + 4 exp(-d^2 / 2 sigma^2) at the centroid, sigma = 0.15 x bounding-box
//    diagonal (quality = energy / fmm energy).
// Paper evaluations = agents x (iterations + 1) (the initial population is evaluated too).
// On the grids and the cone the evaluations match ours, so the ratio is the ratio of times.
// "paper [s]" is the paper's time scaled to the evaluations we ran (its row time unless
// --max-iterations caps the run).
//
// Without --rows, the 1 -> 2 thread scaling of generation throughput and the quality of
// seeded `de` against the Steiner truth follow the table.
//
// Usage: bench_table1 [--rows LIST] [--threads T] [--max-iterations K] [--repeat K] [--data DIR]
//                     [--strategy NAME] [--seeded] [--seed S]
//   --rows            comma-separated row numbers (1-based, csv order) or texts matched against
//                     "application category", ignoring case (e.g. --rows 1,3 or --rows converge);
//                     an item that names no row is an error
//   --threads         evaluation threads (default 2, the issue's setting)
//   --max-iterations  caps every row's iterations (ratios stay per evaluation)
//   --repeat          runs each row K times and keeps the fastest (the runs are identical)
//   --seed            DE's seed (default 1), to see the quality column over several runs
#include <algorithm>
#include <charconv>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "../tests/job_builders.hpp"
#include "bench_stats.hpp"
#include "depath/de/differential_evolution.hpp"
#include "depath/decode/fast_marching.hpp"
#include "depath/generators/surfaces.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/io/vertex_data.hpp"
#include "depath/mesh/tangent_fields.hpp"
#include "depath/solve/solve.hpp"

#ifndef DEPATH_SHARED_DATA
#define DEPATH_SHARED_DATA "../shared/data"
#endif

namespace {

using namespace depath;
using depath::bench::cpu_seconds;

// One line of paper/table1.csv.
struct PaperRow {
  std::string application, category;
  int vertices = 0, agents = 0, iterations = 0;
  double seconds = 0.0;
  std::string label() const { return application + " " + category; }
};

// Throws std::runtime_error naming the file, the line and the field that is not a positive
// number (the file is data: a malformed one gets a message, not an abort).
std::vector<PaperRow> read_table1(const std::string& path) {
  std::ifstream csv(path);
  std::vector<PaperRow> rows;
  std::string line;
  std::getline(csv, line);  // header
  for (int number = 2; std::getline(csv, line); ++number) {
    if (line.empty()) continue;
    std::stringstream in(line);
    PaperRow r;
    std::getline(in, r.application, ',');
    std::getline(in, r.category, ',');
    const auto positive = [&](const char* column, auto& value) {
      std::string field;
      std::getline(in, field, ',');
      const char* end = field.data() + field.size();
      const auto [ptr, error] = std::from_chars(field.data(), end, value);
      if (error != std::errc() || ptr != end || !(value > 0))
        throw std::runtime_error(path + " line " + std::to_string(number) + ": " + column +
                                 " is not a positive number: '" + field + "'");
    };
    positive("vertices", r.vertices);
    positive("agents", r.agents);
    positive("iterations", r.iterations);
    positive("seconds", r.seconds);
    rows.push_back(r);
  }
  return rows;
}

// Our problem for a paper row.
struct Experiment {
  Experiment(std::string name, Mesh m, JobSpec j)
      : mesh_name(std::move(name)), mesh(std::move(m)), job(std::move(j)) {}
  std::string mesh_name;
  Mesh mesh;
  JobSpec job;
  double truth = 0.0;      // > 0: reference for the quality column
  std::string truth_name;  // "exact" (length) or "k16" (energy)
};

int grid_side(const PaperRow& row) {
  const int n = static_cast<int>(std::lround(std::sqrt(row.vertices)));
  if (n * n != row.vertices) throw std::runtime_error("vertex count is not a square grid");
  return n;
}

// Grid vertex nearest to plane point (x, y) of a grid over [-h, h]^2.
int grid_vertex(int n, double h, double x, double y) {
  const auto index = [&](double u) { return static_cast<int>(std::lround((u + h) / (2 * h) * (n - 1))); };
  return index(y) * n + index(x);
}

// First pair of `mesh` in a truth csv (mesh,[density,]source,target,value...).
bool truth_pair(const std::string& csv_path, const std::string& mesh, int skip, int& s, int& t,
                double& value) {
  std::ifstream csv(csv_path);
  std::string line;
  while (std::getline(csv, line)) {
    if (line.rfind(mesh + ",", 0) != 0) continue;
    std::stringstream in(line);
    std::string field;
    for (int k = 0; k <= skip; ++k) std::getline(in, field, ',');
    std::getline(in, field, ',');
    s = std::stoi(field);
    std::getline(in, field, ',');
    t = std::stoi(field);
    std::getline(in, field, ',');
    value = std::stod(field);
    return true;
  }
  return false;
}

double parse_slope(const std::string& application) {
  const size_t eq = application.find('=');
  if (eq == std::string::npos) throw std::runtime_error("no 'k = ...' in the application");
  return std::stod(application.substr(eq + 1));
}

Experiment make_experiment(const PaperRow& row, const std::string& data) {
  const JobSpec base = test::de_job(0, 0, row.agents, row.iterations, /*seed=*/1, /*threads=*/0);
  const std::string& c = row.category;
  if (c == "simple converge") {
    const int n = grid_side(row);
    Experiment e{"grid " + std::to_string(n) + "x" + std::to_string(n),
                 make_grid({.n = n, .half_size = 3.0, .height = GridHeight::flat}), base};
    e.job.source = (n / 2) * n + n / 8;
    e.job.target = (n / 3) * n + (7 * n) / 8;
    e.job.energy.kind = EnergyKind::vector_field;
    e.job.energy.field = converge_field(e.mesh, Vec3::Zero(), 2, 1.0);
    return e;
  }
  if (c == "simple rotation") {
    const int n = grid_side(row);
    Experiment e{"grid " + std::to_string(n) + "x" + std::to_string(n),
                 make_grid({.n = n, .half_size = 1.0, .height = GridHeight::flat}), base};
    e.job.source = grid_vertex(n, 1.0, 0.45, -0.6);
    e.job.target = grid_vertex(n, 1.0, -0.45, -0.6);
    e.job.energy.kind = EnergyKind::vector_field;
    e.job.energy.field = rotation_field(e.mesh, Vec3::Zero(), 2);
    return e;
  }
  if (c == "complex 1" || c == "complex 2") {
    const int n = grid_side(row);
    Experiment e{"peaks " + std::to_string(n) + "x" + std::to_string(n),
                 make_grid({.n = n, .half_size = 3.0, .height = GridHeight::peaks}), base};
    const bool first = c == "complex 1";
    e.job.source = first ? grid_vertex(n, 3.0, -1.5, -1.5) : grid_vertex(n, 3.0, -2.25, 0.0);
    e.job.target = first ? grid_vertex(n, 3.0, 1.5, 1.5) : grid_vertex(n, 3.0, 2.25, 0.0);
    e.job.energy.kind = EnergyKind::vector_field;
    e.job.energy.field_from_height = true;
    e.job.energy.rotate_degrees = 90.0;
    e.job.energy.smoothness = 0.1;
    return e;
  }
  if (c == "cone") {
    ConeOptions o;
    o.rings = 20;
    if ((row.vertices - 1) % o.rings != 0) throw std::runtime_error("vertex count is not 1 + 20 x sectors");
    o.sectors = (row.vertices - 1) / o.rings;
    Experiment e{"cone 20x" + std::to_string(o.sectors), make_cone(o), base};
    e.job.source = cone_vertex(o, o.rings, 0);
    e.job.target = cone_vertex(o, o.rings / 2, o.sectors / 3);
    e.job.energy.kind = EnergyKind::constant_slope;
    e.job.energy.slope = parse_slope(row.application);
    return e;
  }
  if (c == "peaks") {
    const int n = grid_side(row);
    Experiment e{"peaks " + std::to_string(n) + "x" + std::to_string(n),
                 make_grid({.n = n, .half_size = 3.0, .height = GridHeight::peaks}), base};
    e.job.source = grid_vertex(n, 3.0, -2.25, -2.25);
    e.job.target = grid_vertex(n, 3.0, 2.25, 1.5);
    e.job.energy.kind = EnergyKind::constant_slope;
    e.job.energy.slope = parse_slope(row.application);
    return e;
  }
  const std::map<std::string, std::string> files = {{"Kitten", "kitten.off"},
                                                    {"Dragon", "dragon.obj"},
                                                    {"Beethoven", "beethoven.ply"},
                                                    {"Bimba", "bimba.obj"}};
  const auto file = files.find(c);
  if (file == files.end()) throw std::runtime_error("no experiment for this row");
  Experiment e{file->second, load_mesh(data + "/meshes/" + file->second), base};
  int s = 0, t = 0;
  if (c == "Beethoven") {
    e.job.energy.density = read_scalar_file(data + "/fields/beethoven.bumps.density");
    if (!truth_pair(data + "/truth/weighted_steiner.csv", file->second, 1, s, t, e.truth))
      throw std::runtime_error("no beethoven pair in truth/weighted_steiner.csv");
    e.truth_name = "k16";
  } else if (!truth_pair(data + "/truth/geodesic_exact.csv", file->second, 0, s, t, e.truth)) {
    throw std::runtime_error("no pair in truth/geodesic_exact.csv");
  } else if (c == "Bimba") {
    e.truth = 0.0;  // the pair's exact length is for the uniform density
    Vec3 lo = e.mesh.position(0), hi = lo, centroid = Vec3::Zero();
    for (int v = 0; v < e.mesh.num_vertices(); ++v) {
      lo = lo.cwiseMin(e.mesh.position(v));
      hi = hi.cwiseMax(e.mesh.position(v));
      centroid += e.mesh.position(v);
    }
    centroid /= e.mesh.num_vertices();
    const double sigma = 0.15 * (hi - lo).norm();
    e.job.energy.density.resize(e.mesh.num_vertices());
    for (int v = 0; v < e.mesh.num_vertices(); ++v)
      e.job.energy.density[v] =
          1.0 + 4.0 * std::exp(-(e.mesh.position(v) - centroid).squaredNorm() / (2.0 * sigma * sigma));
  } else {
    e.truth_name = "exact";
  }
  e.job.source = s;
  e.job.target = t;
  return e;
}

std::string quality(const Experiment& e, const SolveResult& r) {
  char text[96];
  for (const char* name : {"mean_slope_error", "normalized_energy"}) {
    for (const Metric& m : r.metrics) {
      if (m.name != name) continue;
      std::snprintf(text, sizeof text, "%s %.4f", m.name == "normalized_energy" ? "norm.E" : "slope err",
                    m.value);
      return text;
    }
  }
  if (e.truth_name == "exact")
    std::snprintf(text, sizeof text, "len/exact %.4f", r.length / e.truth);
  else if (e.truth_name == "k16")
    std::snprintf(text, sizeof text, "E/k16 %.4f", r.energy / e.truth);
  else
    std::snprintf(text, sizeof text, "E/fmm %.4f", r.energy / r.fmm_energy);
  return text;
}

// Mean share of the mesh's vertices that the decode's early-stopped march makes final, over
// agents drawn as the paper initialises them (density uniform in (0, 1] per vertex): why rows
// of one size cost differently (end points far apart on a small grid march nearly all of it).
// Set beside the whole run's share, it shows how far evolution moved the cost.
double initial_marched_share(const Experiment& e, uint64_t seed) {
  constexpr int kAgents = 16;
  const FastMarchingStencils stencils(e.mesh);
  FastMarching march(stencils);
  DeRandom rng(seed, 0, 0);
  std::vector<double> density(e.mesh.num_vertices());
  double marched = 0.0;
  for (int k = 0; k < kAgents; ++k) {
    for (double& d : density) d = rng.uniform_open_closed();
    march.run(density, e.job.source, e.job.target);
    marched += march.num_final();
  }
  return marched / kAgents / e.mesh.num_vertices();
}

// Whether one --rows item names row `number`: the number itself, or words of its label in
// any case ("kitten" finds "uniform geodesic Kitten").
bool names_row(const std::string& item, int number, const PaperRow& row) {
  if (std::all_of(item.begin(), item.end(), [](unsigned char ch) { return std::isdigit(ch); })) {
    int value = 0;
    const auto [ptr, error] = std::from_chars(item.data(), item.data() + item.size(), value);
    return error == std::errc() && value == number;  // too large for an int names no row
  }
  std::string label = row.label(), words = item;
  for (std::string* text : {&label, &words})
    std::transform(text->begin(), text->end(), text->begin(),
                   [](unsigned char ch) { return std::tolower(ch); });
  return label.find(words) != std::string::npos;
}

// The rows --rows LIST picks (all of them for no list), or exits naming an item that picks
// none: a typo would otherwise silently run less.
std::vector<bool> pick_rows(const std::string& list, const std::vector<PaperRow>& paper,
                            const std::string& csv) {
  std::vector<bool> picked(paper.size(), list.empty());
  std::stringstream in(list);
  for (std::string item; std::getline(in, item, ',');) {
    bool found = false;
    for (size_t k = 0; k < paper.size(); ++k) {
      if (!item.empty() && names_row(item, int(k) + 1, paper[k])) picked[k] = found = true;
    }
    if (!found) {
      std::fprintf(stderr, "bench_table1: --rows item '%s' (of '%s') names none of the %zu rows of %s\n",
                   item.c_str(), list.c_str(), paper.size(), csv.c_str());
      std::exit(2);
    }
  }
  return picked;
}

struct Throughput {
  double generations_per_second = 0.0;
  double cores_used = 0.0;  // process CPU time / wall time over the timed generations
};

Throughput throughput(const Mesh& mesh, JobSpec job, int threads, int generations) {
  job.threads = threads;
  job.de.generations = generations;
  double first = 0.0, last = 0.0, cpu_first = 0.0, cpu_last = 0.0;
  SolveHooks hooks;
  // Time generations only (from the end of generation 1 to the end of the last), so the
  // stencil build, fmm baseline and initial population do not blur the figure.
  hooks.on_progress = [&](const Progress& p) {
    if (p.generation == 1) {
      first = p.elapsed_seconds;
      cpu_first = cpu_seconds();
    }
    last = p.elapsed_seconds;
    cpu_last = cpu_seconds();
  };
  solve(mesh, job, hooks);
  return {(generations - 1) / (last - first), (cpu_last - cpu_first) / (last - first)};
}

// Seeded `de` against the Steiner-graph truth (truth/weighted_steiner.csv), a few pairs per mesh.
void quality_section(const std::string& data, int threads, bool quick) {
  std::ifstream csv(data + "/truth/weighted_steiner.csv");
  if (!csv) {
    std::printf("\n(quality section skipped: %s/truth/weighted_steiner.csv not found)\n", data.c_str());
    return;
  }
  const int pairs_per_mesh = quick ? 1 : 3;
  const int generations = quick ? 10 : 50;
  std::printf(
      "\nquality vs truth (bump densities; de seeded with the problem, 20 agents, %d generations; "
      "k16 = Steiner-graph cost, 16 points/edge, slightly above the optimum)\n",
      generations);
  std::printf("%-16s %6s %6s %12s %12s %12s %12s %9s %9s\n", "mesh", "s", "t", "k16", "fmm/k16",
              "rand1bin/k16", "shade/k16", "r1b [s]", "shade [s]");
  std::string line;
  std::getline(csv, line);
  std::map<std::string, int> seen;
  std::map<std::string, Mesh> meshes;
  std::map<std::string, std::vector<double>> densities;
  while (std::getline(csv, line)) {
    std::stringstream row(line);
    std::string name, density, field;
    std::getline(row, name, ',');
    std::getline(row, density, ',');
    if (++seen[name] > pairs_per_mesh) continue;
    std::getline(row, field, ',');
    const int s = std::stoi(field);
    std::getline(row, field, ',');
    const int t = std::stoi(field);
    std::getline(row, field, ',');
    const double k16 = std::stod(field);
    if (!meshes.count(name)) {
      meshes.emplace(name, load_mesh(data + "/meshes/" + name));
      densities[name] = read_scalar_file(data + "/fields/" + density);
    }
    JobSpec job = test::de_job(s, t, 20, generations, /*seed=*/1, /*threads=*/0);
    job.threads = threads;
    job.energy.density = densities[name];
    job.de.seed_with_problem = true;
    try {
      const SolveResult r1 = solve(meshes.at(name), job);
      job.de.strategy = "shade";
      const SolveResult r2 = solve(meshes.at(name), job);
      std::printf("%-16s %6d %6d %12.5f %12.5f %12.5f %12.5f %9.2f %9.2f\n", name.c_str(), s, t, k16,
                  r1.fmm_energy / k16, r1.energy / k16, r2.energy / k16, r1.seconds, r2.seconds);
    } catch (const std::exception& e) {
      std::printf("%-16s %6d %6d  skipped: %s\n", name.c_str(), s, t, e.what());
    }
    std::fflush(stdout);
  }
}

// The paper-sized geodesic problem of the thread-scaling figure: a 125 x 125 flat grid
// (15,625 vertices) with a bump at the centre, 30 agents.
void scaling_section(const std::string& strategy) {
  const int n = 125;
  const Mesh mesh = make_grid({.n = n, .half_size = 3.0, .height = GridHeight::flat});
  JobSpec job = test::de_job(0, n * n - 1, 30, 8, /*seed=*/1, /*threads=*/0);
  job.de.strategy = strategy;
  job.energy.density.resize(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3& p = mesh.position(v);
    job.energy.density[v] = 1.0 + 4.0 * std::exp(-(p.x() * p.x() + p.y() * p.y()) / (2.0 * 1.2 * 1.2));
  }
  const Throughput one = throughput(mesh, job, 1, 8);
  const Throughput two = throughput(mesh, job, 2, 8);
  std::printf(
      "\nthread scaling (grid 125x125 flat + bump, 30 agents): 1 thread %.2f generations/s (%.1f "
      "ms/generation), "
      "2 threads %.2f generations/s -> %.2fx\n",
      one.generations_per_second, 1e3 / one.generations_per_second, two.generations_per_second,
      two.generations_per_second / one.generations_per_second);
  std::printf(
      "  CPU cores the process actually got: %.2f with 1 thread, %.2f with 2 threads "
      "(below 2 means other load on the machine caps the scaling)\n",
      one.cores_used, two.cores_used);
}

// A whole-number option value of at least `least`, or exits naming the option (no silent
// clamping, and "2x" or "abc" are not read as 2 or 0).
template <class T>
T whole_option(const char* option, const char* text, T least) {
  T value{};
  const char* end = text + std::strlen(text);
  const auto [ptr, error] = std::from_chars(text, end, value);
  if (error == std::errc::result_out_of_range) {
    std::fprintf(stderr, "bench_table1: %s value '%s' is too large\n", option, text);
    std::exit(2);
  }
  if (error != std::errc() || ptr != end || value < least) {
    std::fprintf(stderr, "bench_table1: %s needs a whole number of at least %llu, got '%s'\n", option,
                 static_cast<unsigned long long>(least), text);
    std::exit(2);
  }
  return value;
}

}  // namespace

int main(int argc, char** argv) {
  int threads = 2, repeat = 1, max_iterations = 0;
  uint64_t seed = 1;
  bool seeded = false;
  std::string data = DEPATH_SHARED_DATA, strategy = "rand1bin", rows_arg;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--threads" && i + 1 < argc)
      threads = whole_option("--threads", argv[++i], 1);
    else if (arg == "--rows" && i + 1 < argc)
      rows_arg = argv[++i];
    else if (arg == "--max-iterations" && i + 1 < argc)
      max_iterations = whole_option("--max-iterations", argv[++i], 1);
    else if (arg == "--seeded")
      seeded = true;
    else if (arg == "--data" && i + 1 < argc)
      data = argv[++i];
    else if (arg == "--strategy" && i + 1 < argc)
      strategy = argv[++i];
    else if (arg == "--seed" && i + 1 < argc)
      seed = whole_option<uint64_t>("--seed", argv[++i], 0);
    else if (arg == "--repeat" && i + 1 < argc)
      repeat = whole_option("--repeat", argv[++i], 1);
    else {
      std::fprintf(stderr,
                   "usage: %s [--rows LIST] [--threads T] [--max-iterations K] [--repeat K] [--data DIR] "
                   "[--strategy NAME] [--seeded] [--seed S]\n",
                   argv[0]);
      return 2;
    }
  }
  const std::vector<std::string>& strategies = de_strategy_names();
  if (std::find(strategies.begin(), strategies.end(), strategy) == strategies.end()) {
    std::string names;
    for (const std::string& name : strategies) names += (names.empty() ? "" : ", ") + name;
    std::fprintf(stderr, "bench_table1: --strategy '%s' is none of: %s\n", strategy.c_str(), names.c_str());
    return 2;
  }
  const std::string csv = data + "/paper/table1.csv";
  if (!std::filesystem::exists(csv)) {
    std::printf("bench_table1: %s not found (shared data absent): nothing to run\n", csv.c_str());
    return 0;
  }
  std::vector<PaperRow> paper;
  try {
    paper = read_table1(csv);
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "bench_table1: %s\n", ex.what());
    return 1;
  }
  const std::vector<bool> picked = pick_rows(rows_arg, paper, csv);
  std::printf("DE-Path Table 1 (%s), re-run with %d thread(s), strategy %s, %s, fastest of %d run(s)%s\n",
              csv.c_str(), threads, strategy.c_str(),
              seeded ? "seeded with the problem" : "paper initialisation", repeat,
              max_iterations > 0 ? (", iterations capped at " + std::to_string(max_iterations)).c_str() : "");
  std::printf(
      "ratio = paper's time per evaluation / ours (per vertex too where the vertex counts differ: *);\n"
      "cores = CPU time / wall time the solve got (below the threads: the machine was loaded);\n"
      "full-core ratio = the ratio had it got every thread's core (paper / (CPU per evaluation / "
      "threads));\n"
      "marched = share of the vertices one decode's march makes final, mean over the whole run; "
      "initial = the same for 16 agents\ndrawn as the paper initialises; ns/vertex = CPU per "
      "evaluation / the whole run's marched vertices per evaluation\n\n");
  std::printf("%2s %-34s %-14s %6s %6s %6s %5s %8s %9s %9s %7s %11s %5s %9s %7s %7s %9s %-17s %s\n", "#",
              "experiment", "mesh", "n", "paper", "agents", "iter", "evals", "ours [s]", "paper [s]", "ratio",
              "CPU ms/eval", "cores", "full-core", "marched", "initial", "ns/vertex", "quality", "stop");
  double worst = INFINITY;
  int number = 0;
  for (const PaperRow& row : paper) {
    ++number;
    if (!picked[number - 1]) continue;
    try {
      Experiment e = make_experiment(row, data);
      JobSpec job = e.job;
      job.threads = threads;
      job.de.strategy = strategy;
      job.de.seed_with_problem = seeded;
      job.seed = seed;
      if (max_iterations > 0) job.de.generations = std::min(job.de.generations, max_iterations);
      SolveResult r;
      double wall = INFINITY, cpu = 0.0, made_final = 0.0;
      for (int k = 0; k < repeat; ++k) {
        const double cpu0 = cpu_seconds();
        const uint64_t final0 = FastMarching::vertices_made_final();
        const auto t0 = bench::Clock::now();
        SolveResult run = solve(e.mesh, job);
        const double seconds = bench::seconds_since(t0);
        if (seconds < wall) {
          wall = seconds;
          cpu = cpu_seconds() - cpu0;
          // The solve's few decodes beyond the evaluations (the best agent, baselines) are
          // counted too: a handful among hundreds of thousands.
          made_final = static_cast<double>(FastMarching::vertices_made_final() - final0);
          r = std::move(run);
        }
      }
      const int n = e.mesh.num_vertices();
      const double evaluations = static_cast<double>(r.evaluations);
      const double paper_evaluations = static_cast<double>(row.agents) * (row.iterations + 1);
      const double paper_per_eval = row.seconds / paper_evaluations * (static_cast<double>(n) / row.vertices);
      const double ratio = paper_per_eval / (wall / evaluations);
      worst = std::min(worst, ratio);
      const double full_core_ratio = paper_per_eval / (cpu / evaluations / threads);
      const double marched = made_final / evaluations / n;
      std::printf(
          "%2d %-34s %-14s %6d %6d %6d %5d %8.0f %9.2f %9.1f %6.1fx%s %11.3f %5.2f %8.1fx %6.0f%% %6.0f%% "
          "%9.0f %-17s %s\n",
          number, row.label().c_str(), e.mesh_name.c_str(), n, row.vertices, job.de.population, r.generations,
          evaluations, wall, row.seconds * evaluations / paper_evaluations, ratio,
          n == row.vertices ? " " : "*", 1e3 * cpu / evaluations, cpu / wall, full_core_ratio,
          100.0 * marched, 100.0 * initial_marched_share(e, seed), 1e9 * cpu / evaluations / (marched * n),
          quality(e, r).c_str(),
          r.stop_reason.c_str());
    } catch (const std::exception& ex) {
      std::printf("%2d %-34s skipped: %s\n", number, row.label().c_str(), ex.what());
    }
    std::fflush(stdout);
  }
  if (std::isfinite(worst)) std::printf("\nslowest row: %.1fx the paper's speed (goal >= 20x)\n", worst);
  if (!rows_arg.empty()) return 0;  // selected rows only: no scaling or quality sections
  try {
    scaling_section(strategy);
    quality_section(data, threads, false);
  } catch (const std::exception& ex) {  // e.g. a malformed truth file under --data
    std::fprintf(stderr, "bench_table1: %s\n", ex.what());
    return 1;
  }
  return 0;
}
