// SPDX-License-Identifier: MIT
// The strategy registry and the sampling helpers the strategies share.
#include "de/strategy.hpp"

#include "depath/util/error.hpp"

#include <algorithm>

namespace depath::de {

// Each strategy's factory, defined in its own file.
std::unique_ptr<Strategy> make_rand1bin(const DeSettings& settings);
std::unique_ptr<Strategy> make_shade(const DeSettings& settings, int population, int dimension);

std::unique_ptr<Strategy> make_strategy(const DeSettings& settings, int population, int dimension) {
  if (settings.strategy == "rand1bin") return make_rand1bin(settings);
  if (settings.strategy == "shade") return make_shade(settings, population, dimension);
  check_strategy_name(settings.strategy);
  throw Error(ErrorCode::internal, "DE strategy '" + settings.strategy + "' has no factory");
}

void check_strategy_name(const std::string& name) {
  const auto& names = de_strategy_names();
  if (std::find(names.begin(), names.end(), name) != names.end()) return;
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  throw Error(ErrorCode::invalid_argument, "unknown DE strategy '" + name + "' (valid strategies: " + list + ")");
}

void Strategy::load(std::span<const double> in) {
  if (!in.empty()) throw Error(ErrorCode::invalid_argument, "checkpoint has strategy memory this strategy does not keep");
}

void pick_distinct(DeRandom& rng, int n, std::span<const int> exclude, std::span<int> out) {
  for (size_t k = 0; k < out.size(); ++k) {
    for (;;) {
      const int r = rng.below(n);
      if (std::find(exclude.begin(), exclude.end(), r) != exclude.end()) continue;
      if (std::find(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(k), r) != out.begin() + static_cast<std::ptrdiff_t>(k)) continue;
      out[k] = r;
      break;
    }
  }
}

}  // namespace depath::de

namespace depath {

const std::vector<std::string>& de_strategy_names() {
  static const std::vector<std::string> names = {"rand1bin", "shade"};
  return names;
}

}  // namespace depath
