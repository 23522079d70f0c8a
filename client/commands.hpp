// Subcommands of the `depath` command line; each add_* registers one or more on the app.
#pragma once

#include <CLI/CLI.hpp>

namespace depath::cli {

/// `depath solve`: run a job in-process (embedded engine, no server).
void add_solve_command(CLI::App& app);

/// Network subcommands talking to depathd: upload, submit, watch, result, jobs, cancel,
/// run, health (client/remote_commands.cpp; built when the service is).
void add_remote_commands(CLI::App& app);

/// `depath generate grid|peaks|cone`: write the paper's test surfaces (client/generate_command.cpp).
void add_generate_command(CLI::App& app);

}  // namespace depath::cli
