// OFF reader (ascii; the [ST][C][N][4][n]OFF header variants): one vertex or face per line, extra
// values (colours, normals, texture coordinates) ignored. Coordinates are single precision, as
// the OFF files we read were written and as our readers always delivered them.
#include <vector>

#include "io/mesh_soup.hpp"
#include "io/text_scan.hpp"

namespace depath::io {

namespace {

// The next line holding anything but blanks and a comment; false at the end.
bool next_data_line(LineScanner& lines, std::string_view& line) {
  while (lines.next(line)) {
    line = strip_comment(line);
    std::string_view token;
    if (Tokens(line).next(token)) return true;
  }
  return false;
}

int64_t header_number(SoupBuilder& soup, std::string_view token, const char* what) {
  const auto n = parse_integer(token);
  if (!n || *n < 0)
    soup.truncated("the OFF header's " + std::string(what) + " " + quoted(token) + " is not a count");
  return *n;
}

}  // namespace

void read_off(std::string_view bytes, SoupBuilder& soup) {
  LineScanner lines(bytes);
  std::string_view line, token;
  if (!next_data_line(lines, line)) soup.fail("does not parse as off: it does not start with an OFF header");
  Tokens header(line);
  header.next(token);
  const std::string_view keyword = token;
  if (keyword.size() < 3 || keyword.size() > 8 || keyword.substr(keyword.size() - 3) != "OFF")
    soup.fail("does not parse as off: it does not start with an OFF header");
  // nOFF gives the dimension first; 4OFF has homogeneous coordinates (we read the first three).
  const bool has_dimension = keyword.find('n') != std::string_view::npos;
  // The counts may follow the keyword on its line or come on the next data line.
  std::vector<std::string_view> words;
  while (header.next(token)) words.push_back(token);
  if (!words.empty() && words[0] == "BINARY")
    soup.fail("is a binary OFF file, which is not supported: convert it to ascii OFF or to PLY");
  const size_t needed = has_dimension ? 3 : 2;
  while (words.size() < needed) {
    if (!next_data_line(lines, line)) soup.truncated("the OFF header lacks vertex and face counts");
    Tokens more(line);
    while (more.next(token)) words.push_back(token);
  }
  size_t w = 0;
  int64_t dimension = 3;
  if (has_dimension) {
    dimension = header_number(soup, words[w++], "dimension");
    if (dimension < 3 || dimension > 16)
      soup.fail("is an nOFF file of dimension " + std::to_string(dimension) + "; only 3 to 16 are read");
  }
  if (keyword.find('4') != std::string_view::npos) ++dimension;
  const int64_t nv = header_number(soup, words[w++], "vertex count");
  const int64_t nf = header_number(soup, words[w++], "face count");
  // At least "0 0 0" per vertex and "3 0 1 2" per face, less a little for the line ends.
  const uint64_t left = lines.bytes_left();
  soup.check_count(nv, 4, left, "vertices");
  soup.check_count(nf, 6, left, "faces");
  if (static_cast<uint64_t>(nv) * 4 + static_cast<uint64_t>(nf) * 6 > left)
    soup.truncated("its OFF header declares " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                   " faces, more than its " + std::to_string(bytes.size()) + " bytes can hold");
  soup.reserve(nv, nf);

  for (int64_t v = 0; v < nv; ++v) {
    soup.tick();
    if (!next_data_line(lines, line))
      soup.truncated("the file ends after " + std::to_string(v) + " of its " + std::to_string(nv) +
                     " vertices");
    Tokens values(line);
    double xyz[3];
    for (int k = 0; k < 3; ++k) {
      if (!values.next(token))
        soup.fail("has a vertex line with fewer than 3 coordinates (vertex " + std::to_string(v) + ", " +
                  lines.where() + ")");
      const auto x = parse_real(token, true);
      if (!x)
        soup.fail("has a coordinate " + quoted(token) + " that is not a number (" + lines.where() + ")");
      xyz[k] = *x;
    }
    soup.add_vertex(xyz[0], xyz[1], xyz[2], lines.where());
  }

  std::vector<int64_t> face;
  for (int64_t f = 0; f < nf; ++f) {
    soup.tick();
    if (!next_data_line(lines, line))
      soup.truncated("the file ends after " + std::to_string(f) + " of its " + std::to_string(nf) + " faces");
    Tokens values(line);
    values.next(token);
    const auto n = parse_integer(token);
    const std::string where = "face " + std::to_string(f) + ", " + lines.where();
    if (!n || *n < 0)
      soup.fail("has a face whose vertex count " + quoted(token) + " is not a count (" + where + ")");
    if (*n < 3)
      soup.fail("has a face with " + std::to_string(*n) + " vertices (" + where +
                "); a face needs at least 3");
    face.clear();
    for (int64_t k = 0; k < *n; ++k) {
      if (!values.next(token))
        soup.fail("has a face line claiming " + std::to_string(*n) + " vertices but giving " +
                  std::to_string(k) + " (" + where + ")");
      const auto index = parse_integer(token);
      if (!index)
        soup.fail("has a face vertex index " + quoted(token) + " that is not an integer (" + where + ")");
      face.push_back(*index);
    }
    soup.add_polygon(face, where);
  }
}

}  // namespace depath::io
