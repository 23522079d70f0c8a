// STL reader, ascii ("solid ... facet ... vertex x y z ...") and binary (80-byte header, triangle
// count, 50 bytes per triangle). STL repeats the corners of every triangle: equal positions are
// merged into one vertex, numbered in order of first appearance.
#include <cstring>
#include <unordered_map>
#include <vector>

#include "io/mesh_soup.hpp"
#include "io/text_scan.hpp"

namespace depath::io {

namespace {

struct Corner {
  float x, y, z;
  bool operator==(const Corner& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct CornerHash {
  size_t operator()(const Corner& c) const {
    // +0.0 and -0.0 compare equal: hash them alike.
    auto bits = [](float f) {
      uint32_t u;
      f = f == 0.0f ? 0.0f : f;
      std::memcpy(&u, &f, 4);
      return static_cast<size_t>(u);
    };
    return bits(c.x) * 0x9E3779B97F4A7C15ull ^ bits(c.y) * 0xC2B2AE3D27D4EB4Full ^ bits(c.z);
  }
};

class CornerMerger {
 public:
  explicit CornerMerger(SoupBuilder& soup) : soup_(soup) {}
  int64_t index(const Corner& c, const std::string& where) {
    const auto [it, added] = ids_.try_emplace(c, soup_.num_vertices());
    if (added) soup_.add_vertex(c.x, c.y, c.z, where);
    return it->second;
  }

 private:
  SoupBuilder& soup_;
  std::unordered_map<Corner, int64_t, CornerHash> ids_;
};

void read_binary(std::string_view bytes, SoupBuilder& soup) {
  if (bytes.size() < 84)
    soup.truncated("a binary STL needs an 84-byte header, the file has " + std::to_string(bytes.size()) +
                   " bytes");
  uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);  // little endian, as is every machine we build for
  if (84 + 50ull * count > bytes.size())
    soup.truncated("its binary STL header declares " + std::to_string(count) + " triangles, the file holds " +
                   std::to_string((bytes.size() - 84) / 50));
  soup.reserve(count, count);
  CornerMerger merger(soup);
  int64_t tri[3];
  for (uint32_t t = 0; t < count; ++t) {
    soup.tick();
    const char* record = bytes.data() + 84 + 50ull * t;
    const std::string where = "triangle " + std::to_string(t);
    for (int k = 0; k < 3; ++k) {
      Corner c;
      std::memcpy(&c.x, record + 12 + 12 * k, 4);
      std::memcpy(&c.y, record + 16 + 12 * k, 4);
      std::memcpy(&c.z, record + 20 + 12 * k, 4);
      tri[k] = merger.index(c, where);
    }
    soup.add_polygon(tri, where);
  }
}

void read_ascii(std::string_view bytes, SoupBuilder& soup) {
  LineScanner lines(bytes);
  std::string_view line, token;
  CornerMerger merger(soup);
  std::vector<int64_t> facet;
  std::string facet_start;
  while (lines.next(line)) {
    Tokens words(line);
    if (!words.next(token)) continue;
    if (token == "facet") {
      facet.clear();
      facet_start = lines.where();
    } else if (token == "vertex") {
      soup.tick();
      float xyz[3];
      for (float& x : xyz) {
        if (!words.next(token))
          soup.fail("has a 'vertex' line with fewer than 3 coordinates (" + lines.where() + ")");
        const auto value = parse_real(token, true);
        if (!value)
          soup.fail("has a coordinate " + quoted(token) + " that is not a number (" + lines.where() + ")");
        x = static_cast<float>(*value);
      }
      facet.push_back(merger.index({xyz[0], xyz[1], xyz[2]}, lines.where()));
    } else if (token == "endfacet") {
      soup.add_polygon(facet, "facet at " + facet_start);
      facet.clear();
    }
  }
}

}  // namespace

void read_stl(std::string_view bytes, SoupBuilder& soup) {
  // A binary STL's 80-byte header may itself start with "solid": its size then matches the
  // declared triangle count exactly, and no "facet" keyword follows.
  bool ascii = bytes.substr(0, 5) == "solid";
  if (ascii && bytes.size() >= 84) {
    uint32_t count = 0;
    std::memcpy(&count, bytes.data() + 80, 4);
    const bool sized_as_binary = 84 + 50ull * count == bytes.size();
    const bool has_facet = bytes.substr(0, 1024).find("facet") != std::string_view::npos;
    ascii = !sized_as_binary || has_facet;
  }
  if (ascii)
    read_ascii(bytes, soup);
  else
    read_binary(bytes, soup);
}

}  // namespace depath::io
