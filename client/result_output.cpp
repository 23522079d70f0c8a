// SPDX-License-Identifier: MIT
#include "result_output.hpp"

#include "depath/io/result_writer.hpp"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>

namespace depath::cli {

void print_summary(const SolveResult& r) {
  std::fprintf(stderr, "method %s%s: energy %.10g  length %.10g  fmm energy %.10g  generations %d  "
                       "evaluations %lld  time %.3fs  (%s)\n",
               method_name(r.method), r.refined ? "+refine" : "", r.energy, r.length, r.fmm_energy, r.generations,
               static_cast<long long>(r.evaluations), r.seconds, r.stop_reason.c_str());
  for (const auto& m : r.metrics) std::fprintf(stderr, "  %s %.6g\n", m.name.c_str(), m.value);
}

void deliver_result(const std::vector<Vec3>& points, const SolveResult& result, const std::string& out, bool json,
                    const std::string& job_id) {
  if (!out.empty()) write_result(out, points, result);
  if (json) {
    nlohmann::json line = nlohmann::json::parse(result_json(points, result));
    line["event"] = "result";
    if (!job_id.empty()) line["job_id"] = job_id;
    std::cout << line.dump() << '\n' << std::flush;
  } else {
    print_summary(result);
    if (!out.empty()) std::fprintf(stderr, "wrote %s\n", out.c_str());
  }
}

}  // namespace depath::cli
