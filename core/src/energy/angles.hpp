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

/// atan2(y, x) for y, x >= 0 (the first quadrant: a result in [0, pi/2]), within 2 ulp of
/// the exact angle; 0 for (0, 0), like std::atan2.
///
/// Why not std::atan2: the angle energies call it three times per segment, and glibc's
/// (correctly rounded in most cases, with a slow path, and saving and restoring the
/// rounding mode on every call) was 46% of a vector-field refinement's profile. Here the
/// ratio y / x is reduced to |r| <= 0.66 by one division chosen without a branch
/// (r = y / x, (y - x) / (y + x) around pi/4, or -x / y near pi/2), then atan(r) is
/// Cephes' rational approximation (relative error 1.1e-16 on that range).
/// Reference: S. L. Moshier, Cephes Math Library, atan.c (1984, 1995).
inline double first_quadrant_atan2(double y, double x) {
  constexpr double kPio2 = 1.5707963267948966192, kPio4 = 0.78539816339744830962;
  constexpr double kMoreBits = 6.123233995736765886130e-17;  // pi/2 - kPio2
  constexpr double kTan3Pi8 = 2.41421356237309504880;        // tan(3 pi / 8)
  // The range tests multiply x: keep it normal there (only degenerate faces give such x).
  if (x < 0x1p-960) [[unlikely]] x *= 0x1p960, y *= 0x1p960;
  const bool steep = y > kTan3Pi8 * x, middle = !steep && y > 0.66 * x;
  double num = y, den = x, base = 0.0, more = 0.0;
  if (middle) num = y - x, den = y + x, base = kPio4, more = 0.5 * kMoreBits;
  if (steep) num = -x, den = y, base = kPio2, more = kMoreBits;
  if (den == 0.0) return 0.0;  // y = x = 0
  const double r = num / den, z = r * r;
  const double p = (((-8.750608600031904122785e-1 * z - 1.615753718733365076637e1) * z -
                     7.500855792314704667340e1) * z - 1.228866684490136173410e2) * z -
                   6.485021904942025371773e1;
  const double q = ((((z + 2.485846490142306297962e1) * z + 1.650270098316988542046e2) * z +
                     4.328810604912902668951e2) * z + 4.853903996359136964868e2) * z +
                   1.945506571482613964425e2;
  return base + (r + r * (z * p / q) + more);
}

/// Acute angle (radians, in [0, pi/2]) between the line along (dx, dy) and the line along
/// (ux, uy), 2D coordinates in one face frame: atan2(|cross|, |dot|), so neither vector
/// needs normalising.
inline double acute_angle(double dx, double dy, double ux, double uy) {
  return first_quadrant_atan2(std::abs(dx * uy - dy * ux), std::abs(dx * ux + dy * uy));
}

}  // namespace depath
