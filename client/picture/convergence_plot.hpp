// SPDX-License-Identifier: MIT
// The convergence plot of `depath plot`: best and mean energy per generation, drawn with Cairo
// into an SVG (or PNG) file.
//
// Inputs: the `--json` progress lines of `depath solve|run|watch` (one JSON object per line;
// lines whose "event" is "progress" are plotted, other events are skipped). Outputs: the
// picture. Guarantees: each series is one stroked polyline with exactly one vertex per progress
// line (Cairo merges collinear runs of it); Error(invalid_argument) naming the file and line for a missing
// file, a line that is not JSON, or no progress at all. With at most 200 generations each one also gets a
// disc marker (one filled path each in the SVG, in the series' colour).
#pragma once

#include <string>
#include <vector>

namespace depath::picture {

struct ConvergencePoint {
  int generation = 0;
  double best_energy = 0;
  double mean_energy = 0;
};

std::vector<ConvergencePoint> read_progress_lines(const std::string& file);

/// Writes the plot to `out`: SVG for a ".svg" name, PNG for ".png"; other names are refused.
/// The y axis is logarithmic when every energy is positive and they span more than 20x.
void write_convergence_plot(const std::vector<ConvergencePoint>& points, const std::string& out, int width,
                            int height);

}  // namespace depath::picture
