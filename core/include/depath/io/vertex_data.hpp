// SPDX-License-Identifier: MIT
// Reading per-vertex data files: one scalar, or one "x y z" vector, per line.
//
// Inputs: a file name. Outputs: the values in file order (the caller checks the count
// against the mesh). Guarantees: errors name the file and the line.
#pragma once

#include "depath/mesh/mesh.hpp"

#include <string>
#include <vector>

namespace depath {

/// One number per non-empty line ('#' starts a comment). Throws Error(invalid_argument)
/// naming the file and line for a missing file or a value that does not parse.
std::vector<double> read_scalar_file(const std::string& path);

/// Three numbers "x y z" per non-empty line. Same errors as read_scalar_file.
std::vector<Vec3> read_vector_file(const std::string& path);

}  // namespace depath
