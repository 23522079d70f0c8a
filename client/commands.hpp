// Subcommands of the `depath` command line; each add_* registers one or more on the app.
#pragma once

#include <CLI/CLI.hpp>

namespace depath::cli {

/// `depath solve`: run a job in-process (embedded engine, no server).
void add_solve_command(CLI::App& app);

}  // namespace depath::cli
