// SPDX-License-Identifier: MIT
#include "depath/generators/surfaces.hpp"

#include "depath/mesh/tangent_fields.hpp"
#include "depath/util/error.hpp"

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace depath {

namespace {

void check_positive(double value, const char* what) {
  if (!std::isfinite(value) || !(value > 0.0))
    throw Error(ErrorCode::invalid_argument, std::string(what) + " must be finite and > 0, got " + std::to_string(value));
}

// A point from plane coordinates (u, v) and a height: the plane axes follow the up axis
// cyclically so that (first, second, up) is right-handed.
Vec3 place(int up_axis, double u, double v, double h) {
  Vec3 p;
  p[(up_axis + 1) % 3] = u;
  p[(up_axis + 2) % 3] = v;
  p[up_axis] = h;
  return p;
}

}  // namespace

GridHeight parse_grid_height(std::string_view name) {
  if (name == "flat") return GridHeight::flat;
  if (name == "peaks") return GridHeight::peaks;
  throw Error(ErrorCode::invalid_argument, "unknown grid terrain '" + std::string(name) + "' (expected flat or peaks)");
}

GridDiagonals parse_grid_diagonals(std::string_view name) {
  if (name == "uniform") return GridDiagonals::uniform;
  if (name == "alternating") return GridDiagonals::alternating;
  throw Error(ErrorCode::invalid_argument,
              "unknown diagonal pattern '" + std::string(name) + "' (expected uniform or alternating)");
}

double matlab_peaks(double x, double y) {
  return 3.0 * (1.0 - x) * (1.0 - x) * std::exp(-x * x - (y + 1.0) * (y + 1.0)) -
         10.0 * (x / 5.0 - x * x * x - std::pow(y, 5)) * std::exp(-x * x - y * y) -
         std::exp(-(x + 1.0) * (x + 1.0) - y * y) / 3.0;
}

Mesh make_grid(const GridOptions& o) {
  check_up_axis(o.up_axis);
  if (o.n < 2) throw Error(ErrorCode::invalid_argument, "grid needs n >= 2 vertices per side, got " + std::to_string(o.n));
  if (o.n > 20000) throw Error(ErrorCode::invalid_argument, "grid n = " + std::to_string(o.n) + " is too large (max 20000)");
  check_positive(o.half_size, "grid half size");
  if (!std::isfinite(o.height_scale))
    throw Error(ErrorCode::invalid_argument, "grid height scale must be finite");
  const int n = o.n;
  std::vector<Vec3> positions;
  positions.reserve(static_cast<size_t>(n) * n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      // Computed from both ends so that the grid is exactly symmetric about the centre.
      const double u = o.half_size * (2.0 * i - (n - 1)) / (n - 1);
      const double v = o.half_size * (2.0 * j - (n - 1)) / (n - 1);
      double h = 0.0;
      if (o.height == GridHeight::peaks) {
        const double s = 3.0 / o.half_size;
        h = matlab_peaks(u * s, v * s) / s;
      }
      positions.push_back(place(o.up_axis, u, v, o.height_scale * h));
    }
  }
  std::vector<std::array<int, 3>> faces;
  faces.reserve(2 * static_cast<size_t>(n - 1) * (n - 1));
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const int v00 = j * n + i, v10 = v00 + 1, v01 = v00 + n, v11 = v01 + 1;
      const bool main_diagonal = o.diagonals == GridDiagonals::uniform || (i + j) % 2 == 0;
      if (main_diagonal) {
        faces.push_back({v00, v10, v11});
        faces.push_back({v00, v11, v01});
      } else {
        faces.push_back({v00, v10, v01});
        faces.push_back({v10, v11, v01});
      }
    }
  }
  return Mesh(std::move(positions), std::move(faces));
}

Mesh make_cone(const ConeOptions& o) {
  check_up_axis(o.up_axis);
  check_positive(o.height, "cone height");
  check_positive(o.radius, "cone radius");
  if (o.rings < 1) throw Error(ErrorCode::invalid_argument, "cone needs rings >= 1, got " + std::to_string(o.rings));
  if (o.sectors < 3) throw Error(ErrorCode::invalid_argument, "cone needs sectors >= 3, got " + std::to_string(o.sectors));
  if (static_cast<long long>(o.rings) * o.sectors > 100'000'000LL)
    throw Error(ErrorCode::invalid_argument, "cone rings x sectors is too large (max 1e8 vertices)");
  std::vector<Vec3> positions;
  positions.reserve(static_cast<size_t>(o.rings) * o.sectors + 2);
  positions.push_back(place(o.up_axis, 0.0, 0.0, o.height));
  for (int r = 1; r <= o.rings; ++r) {
    const double fraction = static_cast<double>(r) / o.rings;
    const double radius = o.radius * fraction;
    const double h = o.height * (1.0 - fraction);
    for (int j = 0; j < o.sectors; ++j) {
      const double phi = 2.0 * std::numbers::pi * j / o.sectors;
      positions.push_back(place(o.up_axis, radius * std::cos(phi), radius * std::sin(phi), h));
    }
  }
  auto id = [&](int ring, int sector) { return cone_vertex(o, ring, sector % o.sectors); };
  std::vector<std::array<int, 3>> faces;
  for (int j = 0; j < o.sectors; ++j) faces.push_back({0, id(1, j), id(1, j + 1)});
  for (int r = 1; r < o.rings; ++r) {
    for (int j = 0; j < o.sectors; ++j) {
      const int a = id(r, j), b = id(r, j + 1), c = id(r + 1, j), d = id(r + 1, j + 1);
      faces.push_back({a, c, d});
      faces.push_back({a, d, b});
    }
  }
  if (o.cap) {
    const int centre = static_cast<int>(positions.size());
    positions.push_back(place(o.up_axis, 0.0, 0.0, 0.0));
    for (int j = 0; j < o.sectors; ++j) faces.push_back({centre, id(o.rings, j + 1), id(o.rings, j)});
  }
  return Mesh(std::move(positions), std::move(faces));
}

}  // namespace depath
