// SPDX-License-Identifier: MIT
// `depath plot PROGRESS.jsonl --out convergence.svg`: best and mean energy per generation from
// the `--json` progress lines of solve/run/watch (client/picture/convergence_plot).
#include <cstdio>
#include <memory>

#include "commands.hpp"
#include "picture/convergence_plot.hpp"
#include "picture/drawing_caches.hpp"

namespace depath::cli {
namespace {

struct PlotOptions {
  std::string progress, out;
  int width = 800, height = 480;
};

void run_plot(const PlotOptions& o) {
  const auto points = picture::read_progress_lines(o.progress);
  picture::write_convergence_plot(points, o.out, o.width, o.height);
  picture::release_drawing_caches();  // the plot's fonts: no drawing follows in this process
  std::fprintf(stderr, "wrote %s (%zu generations)\n", o.out.c_str(), points.size());
}

}  // namespace

void add_plot_command(CLI::App& app) {
  auto o = std::make_shared<PlotOptions>();
  CLI::App* cmd =
      app.add_subcommand("plot", "Plot best and mean energy per generation from --json progress lines");
  cmd->add_option("progress", o->progress, "JSON lines written by depath solve|run|watch --json")->required();
  cmd->add_option("--out", o->out, "Plot to write (.svg or .png)")->required();
  cmd->add_option("--width", o->width, "Width, pixels")->capture_default_str();
  cmd->add_option("--height", o->height, "Height, pixels")->capture_default_str();
  cmd->callback([o] { run_plot(*o); });
}

}  // namespace depath::cli
