// SPDX-License-Identifier: MIT
#include "depath/io/mesh_reader.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iterator>

#include "depath/util/error.hpp"
#include "io/mesh_soup.hpp"

namespace depath {

namespace {
std::string lowercase(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return std::tolower(c); });
  return out;
}
bool known_format(const std::string& f) { return f == "obj" || f == "off" || f == "ply" || f == "stl"; }
}  // namespace

std::string mesh_format_from_path(std::string_view path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  std::string ext;
  if (dot != std::string_view::npos && (slash == std::string_view::npos || dot > slash))
    ext = lowercase(path.substr(dot + 1));
  if (known_format(ext)) return ext;
  throw Error(ErrorCode::invalid_argument, "unknown mesh format for '" + std::string(path) +
                                               "': expected a .obj, .off, .ply or .stl file");
}

Mesh load_mesh_from_bytes(std::string_view bytes, std::string_view format, std::string_view name,
                          const MeshReadLimits& limits) {
  const std::string fmt = lowercase(format);
  if (!known_format(fmt))
    throw Error(ErrorCode::invalid_argument, "unknown mesh format '" + fmt + "' for " + std::string(name) +
                                                 ": expected obj, off, ply or stl");
  const std::string label(name);
  if (bytes.empty()) throw Error(ErrorCode::invalid_argument, "mesh " + label + " is empty (0 bytes)");
  io::SoupBuilder soup(label, fmt, limits.deadline);
  if (fmt == "obj")
    io::read_obj(bytes, soup);
  else if (fmt == "off")
    io::read_off(bytes, soup);
  else if (fmt == "ply")
    io::read_ply(bytes, soup);
  else
    io::read_stl(bytes, soup);
  return soup.build();
}

Mesh load_mesh_from_bytes(std::string_view bytes, std::string_view format, std::string_view name) {
  return load_mesh_from_bytes(bytes, format, name, MeshReadLimits{});
}

Mesh load_mesh(const std::string& path, std::string_view format) {
  const std::string fmt = format.empty() ? mesh_format_from_path(path) : lowercase(format);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorCode::invalid_argument, "cannot open mesh file '" + path + "'");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return load_mesh_from_bytes(bytes, fmt, "'" + path + "'");
}

Mesh load_mesh(const std::string& path) { return load_mesh(path, {}); }

}  // namespace depath
