// libFuzzer target: the mesh readers of every format on arbitrary bytes. The first byte picks
// the format; the rest is the file. A read either gives a mesh whose faces index its vertices
// and whose coordinates are finite, or throws depath::Error; anything else (crash, leak,
// sanitizer report, timeout, out-of-memory) is a finding.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "depath/io/mesh_reader.hpp"
#include "depath/util/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* const kFormats[] = {"obj", "off", "ply", "stl"};
  const char* format = kFormats[data[0] % 4];
  const std::string_view bytes(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    const depath::Mesh mesh = depath::load_mesh_from_bytes(bytes, format, "fuzz");
    for (int v = 0; v < mesh.num_vertices(); ++v)
      if (!mesh.position(v).allFinite()) std::abort();
    for (int f = 0; f < mesh.num_faces(); ++f)
      for (int v : mesh.face(f))
        if (v < 0 || v >= mesh.num_vertices()) std::abort();
  } catch (const depath::Error&) {
  }
  return 0;
}
