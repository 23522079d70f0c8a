// SPDX-License-Identifier: MIT
// Reading a job's result JSON (the `--out x.json` / result.json format) for drawing.
//
// Inputs: the result file and the mesh it claims to lie on. Outputs: the path's points, source
// first. Guarantees: Error(invalid_argument) naming the file and the problem when the file is
// missing or not a result, or when the result is not on this mesh (a vertex id out of range,
// an edge the mesh lacks, a point away from the vertex or edge it names).
#pragma once

#include <string>
#include <vector>

#include "depath/mesh/mesh.hpp"

namespace depath::picture {

std::vector<Vec3> read_result_path(const std::string& result_file, const Mesh& mesh);

}  // namespace depath::picture
