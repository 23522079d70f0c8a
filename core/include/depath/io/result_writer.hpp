// SPDX-License-Identifier: MIT
// Writing results: JSON (SPEC §4), OBJ/PLY polylines and CSV, chosen by file extension.
//
// Inputs: a SolveResult (its path's crossings and figures) and the 3D position of each of the
// path's points — from the mesh (the overloads taking a Mesh) or from wherever the caller has
// them (a result received from a server carries them), so that no mesh is needed to write a
// file. Outputs: a file, or the JSON text. Guarantees: the same result and positions give the
// same bytes; doubles are written so that they read back exactly (JSON: shortest round-trip
// form; OBJ, PLY, CSV: 17 significant digits). Errors are Error(invalid_argument) naming the
// file: unknown extension, a file that cannot be written, or positions that do not match the
// path's points.
#pragma once

#include "depath/mesh/mesh.hpp"
#include "depath/solve/solve.hpp"

#include <ostream>
#include <string>
#include <vector>

namespace depath {

/// Checks that `path` has a result extension (.json, .obj, .ply, .csv), so that a job is not
/// run only to fail at the end. Throws Error(invalid_argument).
void check_result_path(const std::string& path);

/// JSON text of a result, one object: points, crossings, energy, length, method,
/// generations, evaluations, seconds, fmm_energy, refined, stop_reason, metrics (SPEC §4).
/// `indent` < 0: one line; else pretty-printed with that indent. `points[i]` is the position
/// of result.path.points[i].
std::string result_json(const std::vector<Vec3>& points, const SolveResult& result, int indent = -1);
/// Same, with the positions computed on `mesh`.
std::string result_json(const Mesh& mesh, const SolveResult& result, int indent = -1);

/// Writes the result to `out` in `format` ("json", "obj", "ply" or "csv", as the extensions):
/// the same bytes write_result puts in a file (a server sends them as a download). Throws
/// Error(invalid_argument) for another format or positions that do not match the path.
void write_result(std::ostream& out, const std::string& format, const std::vector<Vec3>& points,
                  const SolveResult& result);

/// Writes the result to `path`; the format follows the extension (.json, .obj, .ply, .csv).
/// Throws Error(invalid_argument) for another extension or a file that cannot be written.
void write_result(const std::string& path, const std::vector<Vec3>& points, const SolveResult& result);
/// Same, with the positions computed on `mesh`.
void write_result(const std::string& path, const Mesh& mesh, const SolveResult& result);

}  // namespace depath
