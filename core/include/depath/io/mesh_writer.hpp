// SPDX-License-Identifier: MIT
// Writing triangle meshes to OBJ, OFF or PLY (used by `depath generate`).
//
// Inputs: a mesh and a file name. Outputs: the file. Guarantees: vertex and face order kept
// (ids in the file equal the mesh's); coordinates read back exactly.
#pragma once

#include "depath/mesh/mesh.hpp"

#include <string>
#include <string_view>

namespace depath {

/// Writes `mesh` to `path`; the format follows the extension (.obj, .off, .ply, case-
/// insensitive). Vertices and faces keep their order, so vertex ids in the file equal the
/// mesh's ids. Coordinates are written with 17 significant digits (round-trip exact).
/// PLY is ascii unless `binary_ply` (then binary little-endian, float64 coordinates,
/// int32 indices). Throws Error(invalid_argument) for another extension or a file that
/// cannot be written.
void write_mesh(const std::string& path, const Mesh& mesh, bool binary_ply = false);

/// The same into a string (format "obj", "off" or "ply").
std::string write_mesh_to_string(const Mesh& mesh, std::string_view format, bool binary_ply = false);

}  // namespace depath
