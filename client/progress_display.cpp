// SPDX-License-Identifier: MIT
#include "progress_display.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iostream>

namespace depath::cli {
namespace {

std::string format_seconds(double s) {
  char buf[32];
  if (!std::isfinite(s) || s < 0) return "--";
  if (s < 60) std::snprintf(buf, sizeof buf, "%.1fs", s);
  else std::snprintf(buf, sizeof buf, "%dm%02ds", static_cast<int>(s / 60), static_cast<int>(s) % 60);
  return buf;
}

}  // namespace

ProgressDisplay::ProgressDisplay(bool json) : json_(json), terminal_(!json && isatty(STDERR_FILENO)) {}

void ProgressDisplay::emit_json(const nlohmann::json& line) {
  std::cout << line.dump() << '\n';
  std::cout.flush();
}

void ProgressDisplay::update(const Progress& p) {
  if (json_) {
    emit_json({{"event", "progress"},
               {"generation", p.generation},
               {"max_generations", p.max_generations},
               {"best_energy", p.best_energy},
               {"mean_energy", p.mean_energy},
               {"evaluations", p.evaluations},
               {"improvements", p.improvements},
               {"elapsed_seconds", p.elapsed_seconds}});
    return;
  }
  const double fraction =
      p.max_generations > 0 ? std::clamp(double(p.generation) / p.max_generations, 0.0, 1.0) : 1.0;
  const double eta = fraction > 0 ? p.elapsed_seconds * (1.0 - fraction) / fraction : NAN;
  if (!terminal_) {
    // Plain lines every 10% for logs.
    const int percent = static_cast<int>(fraction * 10) * 10;
    if (percent == last_plain_percent_) return;
    last_plain_percent_ = percent;
    std::fprintf(stderr, "generation %d/%d  best %.6g  mean %.6g  evaluations %lld  elapsed %s\n", p.generation,
                 p.max_generations, p.best_energy, p.mean_energy, static_cast<long long>(p.evaluations),
                 format_seconds(p.elapsed_seconds).c_str());
    return;
  }
  const auto now = std::chrono::steady_clock::now();
  if (bar_open_ && fraction < 1.0 && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  constexpr int kWidth = 28;
  const int filled = static_cast<int>(fraction * kWidth);
  std::string bar(filled, '#');
  bar.resize(kWidth, '.');
  std::fprintf(stderr, "\r[%s] gen %d/%d  best %.6g  mean %.6g  ETA %s   ", bar.c_str(), p.generation,
               p.max_generations, p.best_energy, p.mean_energy, format_seconds(eta).c_str());
  std::fflush(stderr);
  bar_open_ = true;
}

void ProgressDisplay::status(const std::string& message) {
  if (json_) {
    emit_json({{"event", "status"}, {"message", message}});
    return;
  }
  finish();
  std::fprintf(stderr, "%s\n", message.c_str());
}

void ProgressDisplay::finish() {
  if (bar_open_) {
    std::fprintf(stderr, "\n");
    bar_open_ = false;
  }
}

}  // namespace depath::cli
