// SPDX-License-Identifier: MIT
// Internal: rejects mesh files whose header declares more elements than the bytes hold.
#pragma once

#include <string>
#include <string_view>

namespace depath {

/// Checks the magic and the element counts declared by an OFF or PLY header (and a binary STL's
/// triangle count) against the bytes present, walking binary PLY records exactly.
/// OpenMesh's readers trust those counts: a truncated or lying file makes them loop or
/// allocate without bound. Throws Error(invalid_argument) naming `label` and the problem.
void check_declared_sizes(std::string_view bytes, std::string_view format, const std::string& label);

}  // namespace depath
