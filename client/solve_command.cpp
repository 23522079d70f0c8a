// `depath solve`: runs a job with the embedded engine (no server).
#include "commands.hpp"
#include "depath/util/error.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/io/result_writer.hpp"
#include "depath/solve/solve.hpp"
#include "job_options.hpp"
#include "progress_display.hpp"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <memory>

namespace depath::cli {
namespace {

std::atomic<bool> g_interrupted{false};
extern "C" void on_interrupt(int) { g_interrupted.store(true); }

void print_summary(const SolveResult& r) {
  std::fprintf(stderr, "method %s%s: energy %.10g  length %.10g  fmm energy %.10g  generations %d  "
                       "evaluations %lld  time %.3fs  (%s)\n",
               method_name(r.method), r.refined ? "+refine" : "", r.energy, r.length, r.fmm_energy, r.generations,
               static_cast<long long>(r.evaluations), r.seconds, r.stop_reason.c_str());
  for (const auto& m : r.metrics) std::fprintf(stderr, "  %s %.6g\n", m.name.c_str(), m.value);
}

void run_solve(const JobOptions& options) {
  if (!options.out.empty()) check_result_path(options.out);
  const Mesh mesh = load_mesh(options.mesh_path, options.mesh_format);
  const JobSpec job = make_job_spec(options);
  ProgressDisplay display(options.json);

  // Ctrl-C stops the search and keeps the best path found so far.
  g_interrupted = false;
  auto previous = std::signal(SIGINT, on_interrupt);
  SolveHooks hooks;
  hooks.on_progress = [&](const Progress& p) { display.update(p); };
  hooks.is_cancelled = [] { return g_interrupted.load(); };
  SolveResult result;
  try {
    result = solve(mesh, job, hooks);
  } catch (...) {
    std::signal(SIGINT, previous);
    display.finish();
    throw;
  }
  std::signal(SIGINT, previous);
  display.finish();

  if (!options.out.empty()) write_result(options.out, mesh, result);
  if (options.json) {
    nlohmann::json line = result_to_json(mesh, result);
    line["event"] = "result";
    display.emit_json(line);
  } else {
    print_summary(result);
    if (!options.out.empty()) std::fprintf(stderr, "wrote %s\n", options.out.c_str());
  }
  // Interrupted: the best path so far is written above; exit 130 like `depath run`.
  if (result.stop_reason == "cancelled")
    throw Error(ErrorCode::cancelled, "interrupted after generation " + std::to_string(result.generations));
}

}  // namespace

void add_solve_command(CLI::App& app) {
  auto options = std::make_shared<JobOptions>();
  CLI::App* cmd = app.add_subcommand("solve", "Solve a job in-process (no server)");
  add_job_options(*cmd, *options, /*with_threads=*/true);
  cmd->callback([options] { run_solve(*options); });
}

}  // namespace depath::cli
