// SPDX-License-Identifier: MIT
#include "io/header_check.hpp"

#include "depath/util/error.hpp"

#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

namespace depath {
namespace {

[[noreturn]] void truncated(const std::string& label, const std::string& what) {
  throw Error(ErrorCode::invalid_argument, "mesh " + label + " is truncated or malformed: " + what);
}

// Each ASCII number takes at least one digit and one separator.
constexpr uint64_t kMinAsciiNumberBytes = 2;

void check_off(std::string_view bytes, const std::string& label) {
  std::istringstream in{std::string(bytes.substr(0, 4096))};
  std::string keyword;
  in >> keyword;
  // OpenMesh's OFF reader keeps options from earlier reads and may chew on a file that is
  // no OFF at all for a long time: refuse it here.
  if (keyword.size() < 3 || keyword.size() > 8 || keyword.compare(keyword.size() - 3, 3, "OFF") != 0)
    throw Error(ErrorCode::invalid_argument, "mesh " + label + " does not parse as off: it does not start with an OFF header");
  const bool binary = bytes.substr(0, 64).find("BINARY") != std::string_view::npos;
  if (binary) in >> keyword;
  // Counts follow, possibly after comment lines.
  std::string token;
  std::vector<uint64_t> counts;
  while (counts.size() < 2 && in >> token) {
    if (token[0] == '#') {
      std::getline(in, token);
      continue;
    }
    try {
      counts.push_back(std::stoull(token));
    } catch (...) {
      truncated(label, "the OFF header's vertex and face counts are not numbers");
    }
  }
  if (counts.size() < 2) truncated(label, "the OFF header lacks vertex and face counts");
  const uint64_t nv = counts[0], nf = counts[1];
  const uint64_t need = binary ? nv * 12 + nf * 16 : (nv * 3 + nf * 4) * kMinAsciiNumberBytes;
  if (nv > bytes.size() || nf > bytes.size() || need > bytes.size())
    truncated(label, "its OFF header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                         " faces, more than its " + std::to_string(bytes.size()) + " bytes can hold");
}

struct PlyProperty {
  int size = 0;        // bytes of a scalar, or of each list item
  int count_size = 0;  // > 0 for a list: bytes of its length prefix
};
struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

int ply_type_size(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" || type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

uint64_t read_count(const char* p, int size, bool big_endian) {
  uint64_t v = 0;
  for (int i = 0; i < size; ++i) {
    const uint8_t byte = static_cast<uint8_t>(p[big_endian ? i : size - 1 - i]);
    v = (v << 8) | byte;
  }
  return v;
}

void check_ply(std::string_view bytes, const std::string& label) {
  if (bytes.substr(0, 3) != "ply")
    throw Error(ErrorCode::invalid_argument, "mesh " + label + " does not parse as ply: it does not start with 'ply'");
  const size_t header_end = bytes.find("end_header");
  if (header_end == std::string_view::npos)
    throw Error(ErrorCode::invalid_argument, "mesh " + label + " does not parse as ply: its header has no end_header");
  size_t data = bytes.find('\n', header_end);
  if (data == std::string_view::npos) truncated(label, "nothing follows the PLY header");
  ++data;
  std::istringstream header{std::string(bytes.substr(0, header_end))};
  std::string line, format;
  std::vector<PlyElement> elements;
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word == "format") {
      words >> format;
    } else if (word == "element") {
      PlyElement e;
      words >> e.name >> e.count;
      if (!words) truncated(label, "bad PLY element line '" + line + "'");
      elements.push_back(e);
    } else if (word == "property" && !elements.empty()) {
      std::string type;
      words >> type;
      PlyProperty p;
      if (type == "list") {
        std::string count_type, item_type;
        words >> count_type >> item_type;
        p.count_size = ply_type_size(count_type);
        p.size = ply_type_size(item_type);
      } else {
        p.size = ply_type_size(type);
      }
      if (p.size == 0 || (type == "list" && p.count_size == 0))
        truncated(label, "unknown PLY property type in '" + line + "'");
      elements.back().properties.push_back(p);
    }
  }
  const uint64_t available = bytes.size() - data;
  if (format == "ascii") {
    uint64_t need = 0;
    for (const auto& e : elements) {
      if (e.count > available) truncated(label, "element '" + e.name + "' declares " + std::to_string(e.count) + " records");
      need += e.count * e.properties.size() * kMinAsciiNumberBytes;
    }
    if (need > available) truncated(label, "the PLY header declares more values than the file holds");
    return;
  }
  if (format != "binary_little_endian" && format != "binary_big_endian") return;
  const bool big_endian = format == "binary_big_endian";
  // Walk every record: scalars have fixed sizes, lists carry their length.
  uint64_t pos = data;
  for (const auto& e : elements) {
    if (e.count > available) truncated(label, "element '" + e.name + "' declares " + std::to_string(e.count) + " records");
    for (uint64_t r = 0; r < e.count; ++r) {
      for (const auto& p : e.properties) {
        if (p.count_size == 0) {
          pos += p.size;
        } else {
          if (pos + p.count_size > bytes.size()) truncated(label, "the data ends inside element '" + e.name + "'");
          const uint64_t n = read_count(bytes.data() + pos, p.count_size, big_endian);
          pos += p.count_size + n * p.size;
        }
        if (pos > bytes.size())
          truncated(label, "the data ends inside element '" + e.name + "' record " + std::to_string(r) + " of " +
                               std::to_string(e.count));
      }
    }
  }
}

void check_stl(std::string_view bytes, const std::string& label) {
  if (bytes.substr(0, 5) == "solid") return;  // ASCII STL declares no counts
  if (bytes.size() < 84) truncated(label, "a binary STL needs an 84-byte header, the file has " + std::to_string(bytes.size()));
  uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  if (84 + 50ull * count > bytes.size())
    truncated(label, "its binary STL header declares " + std::to_string(count) + " triangles, the file holds " +
                         std::to_string((bytes.size() - 84) / 50));
}

}  // namespace

void check_declared_sizes(std::string_view bytes, std::string_view format, const std::string& label) {
  if (format == "off") check_off(bytes, label);
  else if (format == "ply") check_ply(bytes, label);
  else if (format == "stl") check_stl(bytes, label);
}

}  // namespace depath
