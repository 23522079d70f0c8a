// SPDX-License-Identifier: MIT
#include "depath/mesh/tangent_fields.hpp"

#include "depath/util/error.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>
#include <string>

namespace depath {

void check_up_axis(int up_axis) {
  if (up_axis < 0 || up_axis > 2)
    throw Error(ErrorCode::invalid_argument, "up axis must be 0 (x), 1 (y) or 2 (z), got " + std::to_string(up_axis));
}

namespace {

Vec3 axis_vector(int up_axis) {
  Vec3 up = Vec3::Zero();
  up[up_axis] = 1.0;
  return up;
}

}  // namespace

FaceFrame face_frame(const Mesh& mesh, int f) {
  const auto& t = mesh.face(f);
  const Vec3& p0 = mesh.position(t[0]);
  const Vec3 a = mesh.position(t[1]) - p0;
  const Vec3 c = a.cross(mesh.position(t[2]) - p0);
  const double cn = c.norm(), an = a.norm();
  FaceFrame frame;
  if (!(cn > 0.0) || !(an > 0.0)) return frame;
  frame.e1 = a / an;
  frame.e2 = (c / cn).cross(frame.e1);
  frame.valid = true;
  return frame;
}

std::vector<Vec3> face_gradients(const Mesh& mesh, const std::vector<double>& scalar) {
  if (static_cast<int>(scalar.size()) != mesh.num_vertices())
    throw Error(ErrorCode::invalid_argument, "scalar field has " + std::to_string(scalar.size()) +
                                                 " values but the mesh has " + std::to_string(mesh.num_vertices()) +
                                                 " vertices");
  std::vector<Vec3> grads(mesh.num_faces(), Vec3::Zero());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const auto& t = mesh.face(f);
    const Vec3& p0 = mesh.position(t[0]);
    const Vec3& p1 = mesh.position(t[1]);
    const Vec3& p2 = mesh.position(t[2]);
    // Computed here rather than taken from the mesh so that the unit normal and the
    // area come from the same cross product (consistent even for near-slivers).
    const Vec3 c = (p1 - p0).cross(p2 - p0);
    const double twice_area = c.norm();
    if (!(twice_area > 0.0)) continue;
    const Vec3 n = c / twice_area;
    // grad f = sum_i f_i (n x e_i) / (2A), e_i the counter-clockwise edge opposite corner i:
    // n x e_i points from that edge towards corner i with length |e_i| = 2A / height_i.
    const Vec3 g = scalar[t[0]] * n.cross(p2 - p1) + scalar[t[1]] * n.cross(p0 - p2) + scalar[t[2]] * n.cross(p1 - p0);
    grads[f] = g / twice_area;
  }
  return grads;
}

std::vector<Vec3> height_gradients(const Mesh& mesh, int up_axis) {
  check_up_axis(up_axis);
  std::vector<double> height(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) height[v] = mesh.position(v)[up_axis];
  return face_gradients(mesh, height);
}

std::vector<Vec3> rotate_face_vectors(const Mesh& mesh, const std::vector<Vec3>& face_vectors, double radians) {
  if (static_cast<int>(face_vectors.size()) != mesh.num_faces())
    throw Error(ErrorCode::invalid_argument, "face field length does not match the face count");
  const double c = std::cos(radians), s = std::sin(radians);
  std::vector<Vec3> out(face_vectors.size());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Vec3& v = face_vectors[f];
    const Vec3& n = mesh.face_normal(f);
    // Rodrigues' rotation for a vector orthogonal to the axis.
    out[f] = c * v + s * n.cross(v);
  }
  return out;
}

std::vector<Vec3> face_to_vertex_field(const Mesh& mesh, const std::vector<Vec3>& face_vectors) {
  if (static_cast<int>(face_vectors.size()) != mesh.num_faces())
    throw Error(ErrorCode::invalid_argument, "face field length does not match the face count");
  std::vector<Vec3> out(mesh.num_vertices(), Vec3::Zero());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    Vec3 sum = Vec3::Zero();
    Vec3 normal = Vec3::Zero();
    double total_area = 0.0;
    for (const int* f = mesh.vertex_faces_begin(v); f != mesh.vertex_faces_end(v); ++f) {
      const double a = mesh.face_area(*f);
      sum += a * face_vectors[*f];
      normal += a * mesh.face_normal(*f);
      total_area += a;
    }
    if (!(total_area > 0.0)) continue;
    sum /= total_area;
    const double nn = normal.norm();
    if (nn > 0.0) {
      normal /= nn;
      sum -= sum.dot(normal) * normal;
    }
    out[v] = sum;
  }
  return out;
}

std::vector<Vec3> height_gradient_field(const Mesh& mesh, int up_axis, double rotate_degrees) {
  const double radians = rotate_degrees * std::numbers::pi / 180.0;
  return face_to_vertex_field(mesh, rotate_face_vectors(mesh, height_gradients(mesh, up_axis), radians));
}

std::vector<Vec3> scalar_gradient_field(const Mesh& mesh, const std::vector<double>& scalar, double rotate_degrees) {
  const double radians = rotate_degrees * std::numbers::pi / 180.0;
  return face_to_vertex_field(mesh, rotate_face_vectors(mesh, face_gradients(mesh, scalar), radians));
}

std::vector<Vec3> rotation_field(const Mesh& mesh, const Vec3& origin, int up_axis) {
  check_up_axis(up_axis);
  const Vec3 up = axis_vector(up_axis);
  std::vector<Vec3> out(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) out[v] = up.cross(mesh.position(v) - origin);
  return out;
}

std::vector<Vec3> converge_field(const Mesh& mesh, const Vec3& origin, int up_axis, double length) {
  check_up_axis(up_axis);
  if (!std::isfinite(length) || !(length > 0.0))
    throw Error(ErrorCode::invalid_argument, "converge field length must be finite and > 0");
  const int u_axis = (up_axis + 1) % 3, v_axis = (up_axis + 2) % 3;
  std::vector<Vec3> out(mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    Vec3 f = Vec3::Zero();
    f[u_axis] = 1.0;
    f[v_axis] = -(mesh.position(v)[v_axis] - origin[v_axis]) / length;
    out[v] = f;
  }
  return out;
}

}  // namespace depath
