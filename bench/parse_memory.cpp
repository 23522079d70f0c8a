// SPDX-License-Identifier: MIT
// Peak memory of parsing a mesh as depathd does (load_mesh_from_bytes + its MeshInfo), per byte
// of the file: the figures behind depathd's --max-upload-memory-bytes estimate
// (server/upload_budget.hpp).
//   parse_memory convert MESH OUTDIR   writes MESH as OUTDIR/NAME.{obj,off,ply,bin.ply,stl}
//   parse_memory measure FILE [FORMAT] reads FILE into memory, parses it once and prints
//                                      bytes, the peak RSS growth during the parse and their ratio
// One parse per process (`measure`), so that memory freed by an earlier step cannot hide the
// parse's own: the peak is VmHWM, reset through /proc/self/clear_refs just before the parse.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "depath/io/mesh_reader.hpp"
#include "depath/io/mesh_writer.hpp"
#include "depath/wire/mesh.hpp"

namespace {

uint64_t status_kb(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const size_t n = std::strlen(key);
  while (std::getline(in, line)) {
    if (line.compare(0, n, key) == 0 && line.size() > n && line[n] == ':')
      return std::stoull(line.substr(n + 1));
  }
  return 0;
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Binary STL (the writer has none): 80-byte header, count, 50 bytes per triangle.
std::string binary_stl(const depath::Mesh& mesh) {
  std::string out(80, ' ');
  const auto count = static_cast<uint32_t>(mesh.num_faces());
  out.append(reinterpret_cast<const char*>(&count), 4);
  for (const auto& f : mesh.faces()) {
    float record[12] = {};
    for (int k = 0; k < 3; ++k) {
      const auto& p = mesh.positions()[f[k]];
      for (int c = 0; c < 3; ++c) record[3 + 3 * k + c] = static_cast<float>(p[c]);
    }
    out.append(reinterpret_cast<const char*>(record), sizeof record);
    out.append(2, '\0');
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  if (mode == "convert" && argc == 4) {
    const std::filesystem::path in = argv[2], dir = argv[3];
    const depath::Mesh mesh = depath::load_mesh(in.string());
    const std::string stem = in.stem().string();
    auto put = [&](const std::string& name, const std::string& bytes) {
      std::ofstream(dir / (stem + name), std::ios::binary) << bytes;
    };
    put(".obj", depath::write_mesh_to_string(mesh, "obj"));
    put(".off", depath::write_mesh_to_string(mesh, "off"));
    put(".ply", depath::write_mesh_to_string(mesh, "ply"));
    put(".bin.ply", depath::write_mesh_to_string(mesh, "ply", true));
    put(".stl", binary_stl(mesh));
    return 0;
  }
  if (mode == "measure" && (argc == 3 || argc == 4)) {
    const std::string path = argv[2];
    const std::string format = argc == 4 ? argv[3] : depath::mesh_format_from_path(path);
    const std::string bytes = read_file(path);
    std::ofstream("/proc/self/clear_refs") << "5";  // VmHWM := VmRSS
    const uint64_t before = status_kb("VmRSS");
    const depath::Mesh mesh = depath::load_mesh_from_bytes(bytes, format, path);
    depath::v1::MeshInfo info;
    depath::wire::mesh_info_from_mesh(mesh, &info);
    const uint64_t peak = status_kb("VmHWM");
    const double grown = static_cast<double>(peak - before) * 1024.0;
    std::printf("%s\t%s\tbytes %zu\tvertices %d\tpeak_growth %.0f\tratio %.2f\tmesh_memory_bytes %llu\n",
                path.c_str(), format.c_str(), bytes.size(), mesh.num_vertices(), grown,
                grown / static_cast<double>(bytes.size()),
                static_cast<unsigned long long>(depath::wire::mesh_memory_bytes(mesh)));
    return 0;
  }
  std::fprintf(stderr, "usage: parse_memory convert MESH OUTDIR | parse_memory measure FILE [FORMAT]\n");
  return 2;
}
