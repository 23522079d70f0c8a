// SPDX-License-Identifier: MIT
// Reading meshes from files and from in-memory bytes (OBJ, OFF, PLY ascii/binary, STL).
//
// Inputs: a file name or bytes with their format. Outputs: a Mesh, polygons triangulated,
// vertex ids in file order. Guarantees: hostile input (truncated or lying headers, NaNs,
// no faces) gets Error(invalid_argument) naming the file and the problem, never a hang or
// unbounded memory: element counts are checked against the bytes before anything is
// allocated, and no other file is ever opened.
#pragma once

#include "depath/mesh/mesh.hpp"

#include <chrono>
#include <string>
#include <string_view>

namespace depath {

/// Mesh file format from a file name's extension ("obj", "off", "ply", "stl"), lowercase.
/// Throws Error(invalid_argument) for an unknown extension.
std::string mesh_format_from_path(std::string_view path);

/// Loads a mesh file with our own readers (core/src/io/read_<format>.cpp): they parse the
/// file's bytes only and never open another file (OBJ's mtllib and the like are ignored).
/// Polygons are fan-triangulated; vertex ids keep file order (STL: first appearance, equal
/// corners merged); coordinates of OBJ, OFF and STL are single precision. Throws
/// Error(invalid_argument) naming the file and the problem (missing, truncated, counts larger
/// than the bytes hold, non-finite coordinates, face index out of range, a face line giving
/// fewer indices than it claims, empty, no faces, ...).
Mesh load_mesh(const std::string& path);

/// Same, with the format given ("obj", "off", "ply", "stl") instead of taken from the extension;
/// an empty `format` means "from the extension".
Mesh load_mesh(const std::string& path, std::string_view format);

/// Bounds on one read. The element counts are always capped by the byte size.
struct MeshReadLimits {
  /// Past it the read stops with Error(resource_exhausted).
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
};

/// Same as load_mesh, from the bytes of a file of the given format ("obj", "off", ...).
/// `name` is only used in error messages. No state is shared between reads.
Mesh load_mesh_from_bytes(std::string_view bytes, std::string_view format, std::string_view name = "upload");
Mesh load_mesh_from_bytes(std::string_view bytes, std::string_view format, std::string_view name,
                          const MeshReadLimits& limits);

}  // namespace depath
