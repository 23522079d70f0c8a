// Writing results: JSON (SPEC §4), OBJ/PLY polylines and CSV, chosen by file extension.
#pragma once

#include "depath/mesh/mesh.hpp"
#include "depath/solve/solve.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace depath {

/// JSON of a result: points, crossings, energy, length, method, generations, evaluations,
/// seconds, fmm_energy, refined, stop_reason, metrics (SPEC §4).
nlohmann::json result_to_json(const Mesh& mesh, const SolveResult& result);

/// JSON of a path alone: {"points": [[x,y,z],...], "crossings": [...]}.
nlohmann::json path_to_json(const Mesh& mesh, const SurfacePath& path);

/// Checks that `path` has a result extension (.json, .obj, .ply, .csv), so that a job is not
/// run only to fail at the end. Throws Error(invalid_argument).
void check_result_path(const std::string& path);

/// Writes the result to `path`; the format follows the extension (.json, .obj, .ply, .csv).
/// Throws Error(invalid_argument) for another extension or a file that cannot be written.
void write_result(const std::string& path, const Mesh& mesh, const SolveResult& result);

}  // namespace depath
