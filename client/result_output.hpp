// SPDX-License-Identifier: MIT
// Output of a finished job, shared by `depath solve` and the network subcommands: the result
// written to --out (format by extension) and shown as one JSON line (--json) or as a summary.
#pragma once

#include "depath/mesh/mesh.hpp"
#include "depath/solve/solve.hpp"

#include <string>
#include <vector>

namespace depath::cli {

/// One line of figures (method, energy, length, fmm energy, generations, evaluations, time,
/// stop reason) and one per metric, on stderr.
void print_summary(const SolveResult& result);

/// Writes `result` to `out` when not empty, then prints it: with `json`, one line
/// {"event":"result", ...the result's JSON..., "job_id"} on stdout (job_id only when not
/// empty); else the summary and "wrote OUT" on stderr. `points[i]` is the position of
/// result.path.points[i].
void deliver_result(const std::vector<Vec3>& points, const SolveResult& result, const std::string& out, bool json,
                    const std::string& job_id = "");

}  // namespace depath::cli
