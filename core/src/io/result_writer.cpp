// SPDX-License-Identifier: MIT
#include "depath/io/result_writer.hpp"

#include "depath/mesh/surface_path.hpp"
#include "depath/util/error.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <fstream>

namespace depath {
namespace {

std::string extension_of(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

void check_points(const std::vector<Vec3>& points, const SolveResult& result) {
  if (points.size() != result.path.points.size())
    throw Error(ErrorCode::invalid_argument, "a result to write has " + std::to_string(points.size()) +
                                                 " positions for " + std::to_string(result.path.points.size()) +
                                                 " path points");
}

nlohmann::json to_json(const std::vector<Vec3>& points, const SolveResult& result) {
  nlohmann::json xyz = nlohmann::json::array();
  nlohmann::json crossings = nlohmann::json::array();
  for (size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    const SurfacePoint& sp = result.path.points[i];
    xyz.push_back({p.x(), p.y(), p.z()});
    if (sp.is_vertex())
      crossings.push_back({{"vertex", sp.v0}});
    else
      crossings.push_back({{"edge", {sp.v0, sp.v1}}, {"t", sp.t}});
  }
  nlohmann::json j = {{"points", std::move(xyz)}, {"crossings", std::move(crossings)}};
  j["energy"] = result.energy;
  j["length"] = result.length;
  j["method"] = method_name(result.method);
  j["refined"] = result.refined;
  j["generations"] = result.generations;
  j["evaluations"] = result.evaluations;
  j["seconds"] = result.seconds;
  j["fmm_energy"] = result.fmm_energy;
  j["stop_reason"] = result.stop_reason;
  nlohmann::json metrics = nlohmann::json::object();
  for (const auto& m : result.metrics) metrics[m.name] = m.value;
  j["metrics"] = std::move(metrics);
  return j;
}

void write_json(std::ostream& out, const std::vector<Vec3>& points, const SolveResult& result) {
  out << to_json(points, result).dump(1) << '\n';
}

// The path as an OBJ polyline ("l" element through all points).
void write_obj(std::ostream& out, const std::vector<Vec3>& points, const SolveResult& result) {
  out << "# depath " << method_name(result.method) << " path, energy " << result.energy << ", length "
      << result.length << '\n';
  out.precision(17);
  for (const auto& p : points) out << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  out << 'l';
  for (size_t i = 0; i < points.size(); ++i) out << ' ' << i + 1;
  out << '\n';
}

// The path as an ASCII PLY with vertices and polyline edges.
void write_ply(std::ostream& out, const std::vector<Vec3>& points, const SolveResult& result) {
  const size_t n = points.size();
  out << "ply\nformat ascii 1.0\ncomment depath " << method_name(result.method) << " path\n"
      << "element vertex " << n << "\nproperty double x\nproperty double y\nproperty double z\n"
      << "element edge " << (n > 0 ? n - 1 : 0) << "\nproperty int vertex1\nproperty int vertex2\nend_header\n";
  out.precision(17);
  for (const auto& p : points) out << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  for (size_t i = 1; i < n; ++i) out << i - 1 << ' ' << i << '\n';
}

// One row per point: position and crossing (vertex, or edge and parameter).
void write_csv(std::ostream& out, const std::vector<Vec3>& points, const SolveResult& result) {
  out << "index,x,y,z,vertex,edge_v0,edge_v1,t\n";
  out.precision(17);
  for (size_t i = 0; i < points.size(); ++i) {
    const auto& sp = result.path.points[i];
    const Vec3& p = points[i];
    out << i << ',' << p.x() << ',' << p.y() << ',' << p.z() << ',';
    if (sp.is_vertex())
      out << sp.v0 << ",,,\n";
    else
      out << ',' << sp.v0 << ',' << sp.v1 << ',' << sp.t << '\n';
  }
}

using Writer = void (*)(std::ostream&, const std::vector<Vec3>&, const SolveResult&);

Writer writer_for_format(const std::string& ext) {
  if (ext == "json") return write_json;
  if (ext == "obj") return write_obj;
  if (ext == "ply") return write_ply;
  if (ext == "csv") return write_csv;
  return nullptr;
}

Writer writer_for(const std::string& path) {
  if (Writer w = writer_for_format(extension_of(path))) return w;
  throw Error(ErrorCode::invalid_argument,
              "cannot write '" + path + "': the output extension must be .json, .obj, .ply or .csv");
}

}  // namespace

void check_result_path(const std::string& path) { (void)writer_for(path); }

std::string result_json(const std::vector<Vec3>& points, const SolveResult& result, int indent) {
  check_points(points, result);
  return to_json(points, result).dump(indent);
}

std::string result_json(const Mesh& mesh, const SolveResult& result, int indent) {
  return result_json(path_positions(mesh, result.path), result, indent);
}

void write_result(std::ostream& out, const std::string& format, const std::vector<Vec3>& points,
                  const SolveResult& result) {
  const Writer writer = writer_for_format(format);
  if (!writer)
    throw Error(ErrorCode::invalid_argument,
                "unknown result format '" + format + "' (expected json, obj, ply or csv)");
  check_points(points, result);
  writer(out, points, result);
}

void write_result(const std::string& path, const std::vector<Vec3>& points, const SolveResult& result) {
  const Writer writer = writer_for(path);
  check_points(points, result);
  std::ofstream out(path, std::ios::binary);
  if (!out) throw Error(ErrorCode::invalid_argument, "cannot open '" + path + "' for writing");
  writer(out, points, result);
  out.flush();
  if (!out) throw Error(ErrorCode::invalid_argument, "failed to write '" + path + "'");
}

void write_result(const std::string& path, const Mesh& mesh, const SolveResult& result) {
  write_result(path, path_positions(mesh, result.path), result);
}

}  // namespace depath
