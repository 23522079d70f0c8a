// SPDX-License-Identifier: MIT
// Internal to the energies: what the two angle energies (vector_field, constant_slope)
// share: their per-face tables in tangent-frame coordinates, and the angle between two lines
// (their integrand).
#pragma once

#include "depath/mesh/mesh.hpp"
#include "depath/mesh/tangent_fields.hpp"

#include <cmath>
#include <vector>

namespace depath {

/// One FaceData per face of `mesh`: its `e1`, `e2` set to the face's tangent frame (zero on a
/// degenerate face), then `fill(f, frame, data)` derives the rest from that frame.
template <class FaceData, class Fill>
std::vector<FaceData> per_face_frames(const Mesh& mesh, Fill fill) {
  std::vector<FaceData> faces(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const FaceFrame frame = face_frame(mesh, f);
    FaceData& d = faces[f];
    d.e1 = frame.e1;
    d.e2 = frame.e2;
    fill(f, frame, d);
  }
  return faces;
}

/// Acute angle (radians, in [0, pi/2]) between the line along (dx, dy) and the line along
/// (ux, uy), 2D coordinates in one face frame: atan2(|cross|, |dot|), so neither vector
/// needs normalising.
inline double acute_angle(double dx, double dy, double ux, double uy) {
  return std::atan2(std::abs(dx * uy - dy * ux), std::abs(dx * ux + dy * uy));
}

}  // namespace depath
