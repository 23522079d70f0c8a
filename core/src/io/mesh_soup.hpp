// Internal: what every format reader fills from the bytes of one file, with the checks they share
// (element caps against the byte size, index ranges, finite coordinates, the parse deadline).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "depath/mesh/mesh.hpp"

namespace depath::io {

/// Collects vertices (file order) and triangles while a reader walks a file. Every error is an
/// Error(invalid_argument) whose message starts with "mesh <label>"; the deadline gives
/// Error(resource_exhausted). No state outlives one read.
class SoupBuilder {
 public:
  SoupBuilder(std::string label, std::string format, std::chrono::steady_clock::time_point deadline);

  /// "mesh <label> <what>": the one way readers report a problem.
  [[noreturn]] void fail(const std::string& what) const;
  /// "mesh <label> is truncated or malformed: <what>".
  [[noreturn]] void truncated(const std::string& what) const;
  /// Refuses a declared count that the remaining bytes cannot hold at `min_bytes_each` bytes per
  /// element, before anything is allocated for it.
  void check_count(uint64_t count, uint64_t min_bytes_each, uint64_t bytes_left,
                   const std::string& what) const;

  void reserve(uint64_t vertices, uint64_t triangles);
  /// Adds a vertex; `where` ("line 4", "record 2") names it if a coordinate is not finite.
  void add_vertex(double x, double y, double z, const std::string& where);
  /// Adds a polygon of 0-based indices, fan-triangulated as (i0, ik, ik+1). Checks the indices.
  void add_polygon(std::span<const int64_t> indices, const std::string& where);
  /// Adds a triangle strip with -1 restarts; triangles alternate orientation and those repeating a
  /// vertex (the strip's joints) are dropped.
  void add_strip(std::span<const int64_t> indices, const std::string& where);
  /// Checks the deadline now and then; readers call it once per element.
  void tick();

  int num_vertices() const { return static_cast<int>(positions_.size()); }
  /// The mesh (throws the messages for no vertices / no faces, or Mesh's own checks).
  Mesh build();

 private:
  int checked_index(int64_t index, const std::string& where) const;

  std::string label_, format_;
  std::chrono::steady_clock::time_point deadline_;
  uint32_t ticks_ = 0;
  std::vector<Vec3> positions_;
  std::vector<std::array<int, 3>> triangles_;
};

/// One reader per format (read_<format>.cpp); each parses only `bytes` and opens nothing.
void read_obj(std::string_view bytes, SoupBuilder& soup);
void read_off(std::string_view bytes, SoupBuilder& soup);
void read_ply(std::string_view bytes, SoupBuilder& soup);
void read_stl(std::string_view bytes, SoupBuilder& soup);

}  // namespace depath::io
