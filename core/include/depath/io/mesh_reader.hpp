// SPDX-License-Identifier: MIT
// Reading meshes from files and from in-memory bytes (OBJ, OFF, PLY ascii/binary, STL).
//
// Inputs: a file name or bytes with their format. Outputs: a Mesh, polygons triangulated,
// vertex ids in file order. Guarantees: hostile input (truncated or lying headers, NaNs,
// no faces) gets Error(invalid_argument) naming the file and the problem, never a hang or
// unbounded memory: headers are checked against the bytes before OpenMesh reads them.
#pragma once

#include "depath/mesh/mesh.hpp"

#include <string>
#include <string_view>

namespace depath {

/// Mesh file format from a file name's extension ("obj", "off", "ply", "stl"), lowercase.
/// Throws Error(invalid_argument) for an unknown extension.
std::string mesh_format_from_path(std::string_view path);

/// Loads a mesh file through OpenMesh's readers. Polygons are triangulated; vertex ids
/// keep file order. Throws Error(invalid_argument) naming the file and the problem when
/// the file is missing, does not parse, is empty, has no faces or non-finite coordinates.
Mesh load_mesh(const std::string& path);

/// Same as load_mesh, from the bytes of a file of the given format ("obj", "off", ...).
/// `name` is only used in error messages.
Mesh load_mesh_from_bytes(std::string_view bytes, std::string_view format, std::string_view name = "upload");

}  // namespace depath
