// SPDX-License-Identifier: MIT
// Paths, results and progress on the wire: depath.v1.Path / JobResult / Progress <-> the
// core's SurfacePath / SolveResult / Progress, and writing a received result.
//
// Inputs: a result from the core (with its mesh) or a message from a server (with or
// without the job's mesh file). Outputs: the other form; files and JSON as `depath solve`
// writes them. Guarantees: a Path carries points, crossings, faces and the positions of the
// vertices its crossings use, so a client can write the result without the mesh and get the
// same points and crossings as with it.
#pragma once

#include "depath/mesh/mesh.hpp"
#include "depath/mesh/surface_path.hpp"
#include "depath/solve/solve.hpp"
#include "depath/v1/job.pb.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace depath::wire {

namespace v1 = ::depath::v1;

/// Fills `out` with the path's points, crossings, faces and the positions of every vertex
/// the crossings refer to.
void path_to_proto(const Mesh& mesh, const SurfacePath& path, v1::Path* out);
/// The path's crossings and faces (positions come from the mesh the caller holds).
SurfacePath path_from_proto(const v1::Path& path);

void result_to_proto(const Mesh& mesh, const SolveResult& result, v1::JobResult* out);
/// Everything but the point positions: pair it with the job's mesh or with the message's
/// own points (see write_result_message).
SolveResult result_from_proto(const v1::JobResult& result);

void progress_to_proto(const Mesh& mesh, const Progress& progress, v1::Progress* out);
/// The figures of a progress message (best_path is left null: it needs a mesh).
Progress progress_from_proto(const v1::Progress& progress);

/// A result received from a server, ready to write: the core result and the position of
/// each of its path points.
struct ReceivedResult {
  SolveResult result;
  std::vector<Vec3> points;
};
/// The point positions come from `mesh` when given (the crossings are checked against it),
/// else from the message's own points, which the server computed on the job's mesh the same
/// way. Throws Error(invalid_argument) for an empty path, crossings outside `mesh`, or a
/// message without positions and no mesh.
ReceivedResult received_result(const v1::JobResult& result, const Mesh* mesh);

/// Writes a received result like `depath solve --out` does (format by the extension);
/// positions as in received_result.
void write_result_message(const std::string& out_path, const v1::JobResult& result, const Mesh* mesh);
/// The result's JSON (SPEC §4) for a received result (same rule for `mesh`).
nlohmann::json result_message_to_json(const v1::JobResult& result, const Mesh* mesh);

}  // namespace depath::wire
