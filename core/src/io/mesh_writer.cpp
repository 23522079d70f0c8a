// SPDX-License-Identifier: MIT
#include "depath/io/mesh_writer.hpp"

#include "depath/util/error.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

namespace depath {

namespace {

std::string lower_extension(std::string_view path) {
  const size_t dot = path.rfind('.');
  const size_t slash = path.find_last_of("/\\");
  if (dot == std::string_view::npos || (slash != std::string_view::npos && dot < slash)) return {};
  std::string ext(path.substr(dot + 1));
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

void append_number(std::string& out, double value) {
  char buffer[32];
  const int n = std::snprintf(buffer, sizeof buffer, "%.17g", value);
  out.append(buffer, static_cast<size_t>(n));
}

void append_vertex_line(std::string& out, const char* prefix, const Vec3& p) {
  out += prefix;
  for (int k = 0; k < 3; ++k) {
    if (k) out += ' ';
    append_number(out, p[k]);
  }
  out += '\n';
}

template <typename T>
void append_le(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes, bytes + sizeof(T));
  out.append(bytes, sizeof(T));
}

}  // namespace

std::string write_mesh_to_string(const Mesh& mesh, std::string_view format, bool binary_ply) {
  std::string out;
  const auto& faces = mesh.faces();
  if (format == "obj") {
    out += "# written by depath\n";
    for (const Vec3& p : mesh.positions()) append_vertex_line(out, "v ", p);
    for (const auto& f : faces)
      out += "f " + std::to_string(f[0] + 1) + ' ' + std::to_string(f[1] + 1) + ' ' + std::to_string(f[2] + 1) + '\n';
  } else if (format == "off") {
    out += "OFF\n" + std::to_string(mesh.num_vertices()) + ' ' + std::to_string(mesh.num_faces()) + " 0\n";
    for (const Vec3& p : mesh.positions()) append_vertex_line(out, "", p);
    for (const auto& f : faces)
      out += "3 " + std::to_string(f[0]) + ' ' + std::to_string(f[1]) + ' ' + std::to_string(f[2]) + '\n';
  } else if (format == "ply") {
    out += "ply\n";
    out += binary_ply ? "format binary_little_endian 1.0\n" : "format ascii 1.0\n";
    out += "comment written by depath\n";
    out += "element vertex " + std::to_string(mesh.num_vertices()) + '\n';
    out += "property double x\nproperty double y\nproperty double z\n";
    out += "element face " + std::to_string(mesh.num_faces()) + '\n';
    out += "property list uchar int vertex_indices\nend_header\n";
    if (binary_ply) {
      for (const Vec3& p : mesh.positions())
        for (int k = 0; k < 3; ++k) append_le(out, p[k]);
      for (const auto& f : faces) {
        out += static_cast<char>(3);
        for (int k = 0; k < 3; ++k) append_le(out, static_cast<int32_t>(f[k]));
      }
    } else {
      for (const Vec3& p : mesh.positions()) append_vertex_line(out, "", p);
      for (const auto& f : faces)
        out += "3 " + std::to_string(f[0]) + ' ' + std::to_string(f[1]) + ' ' + std::to_string(f[2]) + '\n';
    }
  } else {
    throw Error(ErrorCode::invalid_argument, "cannot write mesh format '" + std::string(format) +
                                                 "' (expected obj, off or ply)");
  }
  return out;
}

void write_mesh(const std::string& path, const Mesh& mesh, bool binary_ply) {
  const std::string ext = lower_extension(path);
  if (ext != "obj" && ext != "off" && ext != "ply")
    throw Error(ErrorCode::invalid_argument,
                "cannot write mesh '" + path + "': unknown extension (expected .obj, .off or .ply)");
  const std::string bytes = write_mesh_to_string(mesh, ext, binary_ply);
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) throw Error(ErrorCode::invalid_argument, "cannot open '" + path + "' for writing");
  file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  file.close();
  if (!file) throw Error(ErrorCode::invalid_argument, "failed writing '" + path + "'");
}

}  // namespace depath
