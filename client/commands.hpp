// SPDX-License-Identifier: MIT
// Subcommands of the `depath` command line, one file each (client/<name>_command.cpp); each
// add_*_command registers its subcommand on the app.
#pragma once

#include <CLI/CLI.hpp>

namespace depath::cli {

/// `depath solve`: run a job in-process (embedded engine, no server).
void add_solve_command(CLI::App& app);
/// `depath generate grid|peaks|cone`: write the paper's test surfaces.
void add_generate_command(CLI::App& app);
/// `depath render MESH RESULT.json --out picture.png`: shaded mesh, path and endpoints (Cairo).
void add_render_command(CLI::App& app);
/// `depath plot PROGRESS.jsonl --out convergence.svg`: the convergence plot (Cairo).
void add_plot_command(CLI::App& app);

// Network subcommands talking to depathd (built when the service is; SPEC §4).
void add_upload_command(CLI::App& app);
void add_submit_command(CLI::App& app);
void add_watch_command(CLI::App& app);
void add_result_command(CLI::App& app);
void add_jobs_command(CLI::App& app);
void add_cancel_command(CLI::App& app);
void add_run_command(CLI::App& app);
void add_health_command(CLI::App& app);

}  // namespace depath::cli
