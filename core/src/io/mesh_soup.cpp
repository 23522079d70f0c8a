#include "io/mesh_soup.hpp"

#include <climits>
#include <cmath>

#include "depath/util/error.hpp"

namespace depath::io {

namespace {
// Meshes index vertices and faces with int.
constexpr uint64_t kMaxElements = INT_MAX;
}  // namespace

SoupBuilder::SoupBuilder(std::string label, std::string format,
                         std::chrono::steady_clock::time_point deadline)
    : label_(std::move(label)), format_(std::move(format)), deadline_(deadline) {}

void SoupBuilder::fail(const std::string& what) const {
  throw Error(ErrorCode::invalid_argument, "mesh " + label_ + " " + what);
}

void SoupBuilder::truncated(const std::string& what) const { fail("is truncated or malformed: " + what); }

void SoupBuilder::check_count(uint64_t count, uint64_t min_bytes_each, uint64_t bytes_left,
                              const std::string& what) const {
  if (count > kMaxElements || count > bytes_left / min_bytes_each)
    truncated("it declares " + std::to_string(count) + " " + what + ", more than its remaining " +
              std::to_string(bytes_left) + " bytes can hold");
}

void SoupBuilder::reserve(uint64_t vertices, uint64_t triangles) {
  positions_.reserve(vertices);
  triangles_.reserve(triangles);
}

void SoupBuilder::add_vertex(double x, double y, double z, const std::string& where) {
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
    fail("has a non-finite coordinate at vertex " + std::to_string(positions_.size()) + " (" + where +
         "): NaN, infinity or a number too large for its type");
  if (positions_.size() >= kMaxElements) fail("has more than " + std::to_string(kMaxElements) + " vertices");
  positions_.emplace_back(x, y, z);
}

int SoupBuilder::checked_index(int64_t index, const std::string& where) const {
  if (index < 0 || index >= static_cast<int64_t>(positions_.size()))
    fail("has a face referring to missing vertices (" + where + "): vertex index " + std::to_string(index) +
         " is out of range, the file defines " + std::to_string(positions_.size()) + " vertices before it");
  return static_cast<int>(index);
}

void SoupBuilder::add_polygon(std::span<const int64_t> indices, const std::string& where) {
  if (indices.size() < 3)
    fail("has a face with " + std::to_string(indices.size()) + " vertices (" + where +
         "); a face needs at least 3");
  if (triangles_.size() + indices.size() - 2 > kMaxElements)
    fail("has more than " + std::to_string(kMaxElements) + " triangles");
  const int first = checked_index(indices[0], where);
  int prev = checked_index(indices[1], where);
  for (size_t i = 2; i < indices.size(); ++i) {
    const int cur = checked_index(indices[i], where);
    triangles_.push_back({first, prev, cur});
    prev = cur;
  }
}

void SoupBuilder::add_strip(std::span<const int64_t> indices, const std::string& where) {
  int a = -1, b = -1;
  size_t run = 0;  // vertices since the last restart
  for (const int64_t raw : indices) {
    if (raw == -1) {
      run = 0;
      continue;
    }
    const int c = checked_index(raw, where);
    if (run >= 2 && a != b && b != c && a != c) {
      if (triangles_.size() >= kMaxElements)
        fail("has more than " + std::to_string(kMaxElements) + " triangles");
      // Odd triangles of a strip are wound the other way round.
      if (run % 2 == 0)
        triangles_.push_back({a, b, c});
      else
        triangles_.push_back({b, a, c});
    }
    a = b;
    b = c;
    ++run;
  }
}

void SoupBuilder::tick() {
  if (++ticks_ % 4096 != 0) return;
  if (std::chrono::steady_clock::now() > deadline_)
    throw Error(ErrorCode::resource_exhausted,
                "mesh " + label_ + " took longer to parse than the parse time budget allows");
}

Mesh SoupBuilder::build() {
  if (positions_.empty())
    fail("has no vertices (an empty mesh, or the file does not parse as " + format_ + ")");
  if (triangles_.empty()) fail("has no faces");
  try {
    return Mesh(std::move(positions_), std::move(triangles_));
  } catch (const Error& e) {
    throw Error(e.code(), label_ + ": " + e.what());
  }
}

}  // namespace depath::io
