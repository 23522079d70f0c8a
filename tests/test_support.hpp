// SPDX-License-Identifier: MIT
// Helpers shared by the tests: data locations and small builders.
#pragma once

#include <filesystem>
#include <string>

namespace depath::test {

/// Bundled test meshes (always present).
inline std::string test_data(const std::string& name) { return std::string(DEPATH_TEST_DATA) + "/" + name; }

/// The workplace's shared data folder (may be absent outside it).
inline std::string shared_data(const std::string& relative) {
  return std::string(DEPATH_SHARED_DATA) + "/" + relative;
}
inline bool has_shared_data() { return std::filesystem::exists(shared_data("meshes")); }

}  // namespace depath::test

/// Skips the current test when the shared data folder is absent.
#define DEPATH_REQUIRE_SHARED_DATA()                                              \
  do {                                                                            \
    if (!::depath::test::has_shared_data()) GTEST_SKIP() << "../shared/data absent"; \
  } while (0)
