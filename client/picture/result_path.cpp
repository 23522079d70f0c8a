// SPDX-License-Identifier: MIT
#include "picture/result_path.hpp"

#include <fstream>
#include <nlohmann/json.hpp>

#include "depath/util/error.hpp"

namespace depath::picture {
namespace {

[[noreturn]] void fail(const std::string& file, const std::string& problem) {
  throw Error(ErrorCode::invalid_argument, "result " + file + ": " + problem);
}

int vertex_id(const nlohmann::json& v, const std::string& file, size_t i, const Mesh& mesh) {
  if (!v.is_number_integer())
    fail(file, "crossing " + std::to_string(i) + " has a vertex id that is not an integer");
  const long long id = v.get<long long>();
  if (id < 0 || id >= mesh.num_vertices())
    fail(file, "crossing " + std::to_string(i) + " names vertex " + std::to_string(id) +
                   " but the mesh has " + std::to_string(mesh.num_vertices()) +
                   " vertices: the result is not on this mesh");
  return static_cast<int>(id);
}

}  // namespace

std::vector<Vec3> read_result_path(const std::string& file, const Mesh& mesh) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file, "cannot open the file");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    fail(file, std::string("not JSON (") + e.what() + ")");
  }
  if (!j.is_object() || !j.contains("points") || !j["points"].is_array() || !j.contains("crossings") ||
      !j["crossings"].is_array())
    fail(file, "not a depath result (needs \"points\" and \"crossings\" lists)");
  const auto& points = j["points"];
  const auto& crossings = j["crossings"];
  if (points.size() < 2) fail(file, "the path has fewer than two points");
  if (points.size() != crossings.size())
    fail(file,
         std::to_string(points.size()) + " points but " + std::to_string(crossings.size()) + " crossings");

  // A point may sit off its vertex or edge by the rounding of the mesh's coordinates.
  const double tolerance = 1e-5 * std::max(mesh.bounding_box().diagonal(), 1e-12);
  std::vector<Vec3> path;
  path.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() || !p[2].is_number())
      fail(file, "point " + std::to_string(i) + " is not [x, y, z]");
    const Vec3 at(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
    if (!at.allFinite()) fail(file, "point " + std::to_string(i) + " is not finite");
    const auto& c = crossings[i];
    Vec3 expected;
    if (c.is_object() && c.contains("vertex")) {
      expected = mesh.position(vertex_id(c["vertex"], file, i, mesh));
    } else if (c.is_object() && c.contains("edge") && c["edge"].is_array() && c["edge"].size() == 2 &&
               c.contains("t") && c["t"].is_number()) {
      const int a = vertex_id(c["edge"][0], file, i, mesh), b = vertex_id(c["edge"][1], file, i, mesh);
      if (mesh.face_with_edge(a, b) < 0)
        fail(file, "crossing " + std::to_string(i) + " is on edge " + std::to_string(a) + "-" +
                       std::to_string(b) + " which this mesh does not have: the result is not on this mesh");
      const double t = c["t"].get<double>();
      expected = (1 - t) * mesh.position(a) + t * mesh.position(b);
    } else {
      fail(file, "crossing " + std::to_string(i) + " is neither {\"vertex\"} nor {\"edge\", \"t\"}");
    }
    if ((expected - at).norm() > tolerance)
      fail(file, "point " + std::to_string(i) + " is " + std::to_string((expected - at).norm()) +
                     " away from the vertex or edge its crossing names: the result is not on this mesh");
    path.push_back(at);
  }
  return path;
}

}  // namespace depath::picture
