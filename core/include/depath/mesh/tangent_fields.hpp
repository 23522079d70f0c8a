// SPDX-License-Identifier: MIT
// Tangent vector fields on a mesh: gradients of per-vertex scalars, rotations in the
// tangent plane, and per-vertex averages, so that generated fields feed the same
// per-vertex code path as fields read from a file (the vector_field energy).
#pragma once

#include "depath/mesh/mesh.hpp"

#include <vector>

namespace depath {

/// Orthonormal tangent frame of a face: e1 along the edge from corner 0 to corner 1,
/// e2 = n x e1, so (e1, e2, n) is right-handed and 2D coordinates (v.e1, v.e2) of a vector
/// are its projection onto the face plane with counter-clockwise angles about n.
/// `valid` is false for degenerate (zero-area) faces, whose frame is zero.
struct FaceFrame {
  Vec3 e1 = Vec3::Zero();
  Vec3 e2 = Vec3::Zero();
  bool valid = false;
};
FaceFrame face_frame(const Mesh& mesh, int f);

/// Gradient of a per-vertex scalar, linear inside each face: one constant vector per face,
/// lying in the face's plane. Its length is the largest rate of change per unit 3D arc
/// length inside the face; for a unit tangent direction d of the face, d . g is the rate of
/// change along d. Degenerate (zero-area) faces get the zero vector.
/// Requires scalar.size() == mesh.num_vertices().
std::vector<Vec3> face_gradients(const Mesh& mesh, const std::vector<double>& scalar);

/// Throws Error(invalid_argument) unless up_axis is 0 (x), 1 (y) or 2 (z): the one check of
/// an up axis (tangent fields, generators).
void check_up_axis(int up_axis);

/// Gradient of one coordinate (height; up_axis 0 = x, 1 = y, 2 = z) per face.
std::vector<Vec3> height_gradients(const Mesh& mesh, int up_axis);

/// Rotates each face vector counter-clockwise about its face normal by `radians`. The
/// vectors must lie in their face planes (as gradients do); lengths are kept.
std::vector<Vec3> rotate_face_vectors(const Mesh& mesh, const std::vector<Vec3>& face_vectors, double radians);

/// Per-vertex field from a per-face field: the area-weighted average of the incident
/// faces' vectors, projected onto the vertex's tangent plane (normal = area-weighted
/// average of the incident face normals). Unreferenced vertices get the zero vector.
std::vector<Vec3> face_to_vertex_field(const Mesh& mesh, const std::vector<Vec3>& face_vectors);

/// The generated field of `--field-from-height [--rotate DEG]`: the height gradient per face,
/// rotated by `rotate_degrees` about each face normal, averaged to the vertices.
std::vector<Vec3> height_gradient_field(const Mesh& mesh, int up_axis, double rotate_degrees);

/// Same for any per-vertex scalar.
std::vector<Vec3> scalar_gradient_field(const Mesh& mesh, const std::vector<double>& scalar, double rotate_degrees);

/// Analytic fields of the paper's vector-field experiments, per vertex. Both are linear in
/// the position, so their linear interpolation inside faces is exact on planar meshes.
/// (u, v) are plane coordinates relative to `origin` along the two axes after `up_axis` in
/// cyclic order (z up: u = x, v = y), as in the surface generators.
///  - rotation: up x (p - origin) = (-v, u): tangent of the circles around the up axis
///    through `origin` (counter-clockwise seen from above); vanishes on that axis.
///  - converge: (1, -v / length): a flow along +u pulled towards the line v = 0; its field
///    lines v = v0 exp(-u / length) converge towards that line. `length` > 0.
std::vector<Vec3> rotation_field(const Mesh& mesh, const Vec3& origin, int up_axis);
std::vector<Vec3> converge_field(const Mesh& mesh, const Vec3& origin, int up_axis, double length);

}  // namespace depath
