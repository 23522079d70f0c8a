// SPDX-License-Identifier: MIT
#include "depath/io/vertex_data.hpp"

#include "depath/util/error.hpp"

#include <charconv>
#include <fstream>
#include <string>

namespace depath {
namespace {

// Calls on_line(values, line_number) for each non-empty, non-comment line.
template <typename OnLine>
void read_numeric_lines(const std::string& path, int expected, const char* what, OnLine on_line) {
  std::ifstream in(path);
  if (!in) throw Error(ErrorCode::invalid_argument, std::string("cannot open ") + what + " file '" + path + "'");
  std::string line;
  int line_number = 0;
  double values[3];
  while (std::getline(in, line)) {
    ++line_number;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    const char* p = line.data();
    const char* end = p + line.size();
    int count = 0;
    for (;;) {
      while (p < end && (*p == ' ' || *p == '\t' || *p == ',' || *p == '\r')) ++p;
      if (p >= end) break;
      double value = 0;
      auto [next, ec] = std::from_chars(p, end, value);
      if (ec != std::errc() || count >= expected) {
        throw Error(ErrorCode::invalid_argument, std::string(what) + " file '" + path + "' line " +
                                                     std::to_string(line_number) + ": expected " +
                                                     std::to_string(expected) + " number(s), got '" + line + "'");
      }
      values[count++] = value;
      p = next;
    }
    if (count == 0) continue;
    if (count != expected)
      throw Error(ErrorCode::invalid_argument, std::string(what) + " file '" + path + "' line " +
                                                   std::to_string(line_number) + ": expected " +
                                                   std::to_string(expected) + " number(s), got " + std::to_string(count));
    on_line(values);
  }
}

}  // namespace

std::vector<double> read_scalar_file(const std::string& path) {
  std::vector<double> out;
  read_numeric_lines(path, 1, "scalar", [&](const double* v) { out.push_back(v[0]); });
  return out;
}

std::vector<Vec3> read_vector_file(const std::string& path) {
  std::vector<Vec3> out;
  read_numeric_lines(path, 3, "vector", [&](const double* v) { out.emplace_back(v[0], v[1], v[2]); });
  return out;
}

}  // namespace depath
