// SPDX-License-Identifier: MIT
// Internal to the energies: the angle between two lines, shared by vector_field and
// constant_slope (their integrands).
#pragma once

#include <cmath>

namespace depath {

/// Acute angle (radians, in [0, pi/2]) between the line along (dx, dy) and the line along
/// (ux, uy), 2D coordinates in one face frame: atan2(|cross|, |dot|), so neither vector
/// needs normalising.
inline double acute_angle(double dx, double dy, double ux, double uy) {
  return std::atan2(std::abs(dx * uy - dy * ux), std::abs(dx * ux + dy * uy));
}

}  // namespace depath
