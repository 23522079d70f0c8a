// SPDX-License-Identifier: MIT
// `depath`: the command-line client and embedded engine.
#include "commands.hpp"
#include "depath/util/error.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  CLI::App app{"depath: energy-minimizing paths on triangle meshes (DE-Path)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "depath 0.1.0");
  // A flag given twice takes its last value (scripts append overrides to a base command).
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  depath::cli::add_solve_command(app);
  depath::cli::add_generate_command(app);
  depath::cli::add_render_command(app);
  depath::cli::add_plot_command(app);
#ifdef DEPATH_WITH_REMOTE
  depath::cli::add_upload_command(app);
  depath::cli::add_submit_command(app);
  depath::cli::add_watch_command(app);
  depath::cli::add_result_command(app);
  depath::cli::add_jobs_command(app);
  depath::cli::add_cancel_command(app);
  depath::cli::add_run_command(app);
  depath::cli::add_health_command(app);
#endif
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const depath::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return e.code() == depath::ErrorCode::cancelled ? 130 : 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
