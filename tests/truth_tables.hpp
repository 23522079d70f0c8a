// SPDX-License-Identifier: MIT
// Readers for the reference tables in ../shared/data/truth/ (one CSV reader for every truth
// test), and the shared meshes they name, loaded once per test binary.
#pragma once

#include "depath/io/mesh_reader.hpp"
#include "test_support.hpp"

#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace depath::test {

struct ExactGeodesic {
  std::string mesh;
  int source, target;
  double length;
};

struct WeightedReference {
  std::string mesh, density;
  int source, target;
  double cost_k16, cost_k8;
};

inline std::vector<std::vector<std::string>> read_csv_rows(const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

inline std::vector<ExactGeodesic> read_exact_geodesics(const std::string& path) {
  std::vector<ExactGeodesic> out;
  for (const auto& r : read_csv_rows(path)) out.push_back({r[0], std::stoi(r[1]), std::stoi(r[2]), std::stod(r[3])});
  return out;
}

inline std::vector<WeightedReference> read_weighted_references(const std::string& path) {
  std::vector<WeightedReference> out;
  for (const auto& r : read_csv_rows(path))
    out.push_back({r[0], r[1], std::stoi(r[2]), std::stoi(r[3]), std::stod(r[4]), std::stod(r[5])});
  return out;
}

/// The shared mesh `name` (under meshes/), loaded on first use and kept.
inline const Mesh& shared_mesh(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Mesh>> cache;
  auto& slot = cache[name];
  if (!slot) slot = std::make_unique<Mesh>(load_mesh(shared_data("meshes/" + name)));
  return *slot;
}

}  // namespace depath::test
