// SPDX-License-Identifier: MIT
// `depath solve`: runs a job with the embedded engine (no server).
#include "commands.hpp"
#include "depath/util/error.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/io/result_writer.hpp"
#include "depath/solve/solve.hpp"
#include "interrupt.hpp"
#include "job_options.hpp"
#include "progress_display.hpp"
#include "result_output.hpp"

#include <cstdio>
#include <memory>

namespace depath::cli {
namespace {

void run_solve(const JobOptions& options) {
  if (!options.out.empty()) check_result_path(options.out);
  const Mesh mesh = load_mesh(options.mesh_path, options.mesh_format);
  const JobSpec job = make_job_spec(options);
  ProgressDisplay display(options.json);

  SolveHooks hooks;
  hooks.on_progress = [&](const Progress& p) { display.update(p); };
  hooks.is_cancelled = [] { return g_interrupted.load(); };
  SolveResult result;
  {
    InterruptGuard guard;  // Ctrl-C stops the search and keeps the best path found so far
    try {
      result = solve(mesh, job, hooks);
    } catch (...) {
      display.finish();
      throw;
    }
  }
  display.finish();

  deliver_result(path_positions(mesh, result.path), result, options.out, options.json);
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
