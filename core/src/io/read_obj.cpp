// OBJ reader: 'v' and 'f' lines only. Every other statement is ignored, in particular mtllib,
// usemtl, call and csh: a mesh upload never makes us open or run anything else. Face corners may
// be "v", "v/vt", "v//vn" or "v/vt/vn"; negative indices count back from the last vertex.
// Coordinates are single precision, as our readers always delivered them.
#include <vector>

#include "io/mesh_soup.hpp"
#include "io/text_scan.hpp"

namespace depath::io {

void read_obj(std::string_view bytes, SoupBuilder& soup) {
  LineScanner lines(bytes);
  std::string_view line, token;
  std::vector<int64_t> face;
  while (lines.next(line)) {
    Tokens words(strip_comment(line));
    if (!words.next(token)) continue;
    if (token == "v") {
      soup.tick();
      double xyz[3];
      for (double& x : xyz) {
        if (!words.next(token))
          soup.fail("has a 'v' line with fewer than 3 coordinates (" + lines.where() + ")");
        const auto value = parse_real(token, true);
        if (!value)
          soup.fail("has a coordinate " + quoted(token) + " that is not a number (" + lines.where() + ")");
        x = *value;
      }
      soup.add_vertex(xyz[0], xyz[1], xyz[2], lines.where());
    } else if (token == "f") {
      soup.tick();
      face.clear();
      while (words.next(token)) {
        const auto index = parse_integer(token.substr(0, token.find('/')));
        if (!index)
          soup.fail("has a face corner " + quoted(token) + " that is not a vertex index (" + lines.where() +
                    ")");
        if (*index == 0)
          soup.fail("has a face with vertex index 0; OBJ indices start at 1 (" + lines.where() + ")");
        face.push_back(*index > 0 ? *index - 1 : soup.num_vertices() + *index);
      }
      soup.add_polygon(face, lines.where());
    }
  }
}

}  // namespace depath::io
