// SPDX-License-Identifier: MIT
// Showing a job's progress: a live bar on a terminal, JSON lines with --json, and
// occasional plain lines otherwise (logs, pipes).
#pragma once

#include "depath/solve/solve.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <string>

namespace depath::cli {

class ProgressDisplay {
 public:
  /// `json`: JSON lines on stdout; else a bar on stderr if it is a terminal.
  explicit ProgressDisplay(bool json);

  /// One generation's report (throttled: the bar redraws at most 10 times a second).
  void update(const Progress& progress);
  /// A free-form status line ("queued", "running", ...).
  void status(const std::string& message);
  /// Ends the bar line (call before printing anything else).
  void finish();
  /// Prints a JSON object as one line on stdout (JSON mode) — used for the final result.
  void emit_json(const nlohmann::json& line);

  bool json() const { return json_; }

 private:
  bool json_;
  bool terminal_;
  bool bar_open_ = false;
  std::chrono::steady_clock::time_point last_draw_{};
  int last_plain_percent_ = -1;
};

}  // namespace depath::cli
