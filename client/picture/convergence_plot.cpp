// SPDX-License-Identifier: MIT
#include "picture/convergence_plot.hpp"

#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>

#include "depath/util/error.hpp"

namespace depath::picture {

std::vector<ConvergencePoint> read_progress_lines(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(ErrorCode::invalid_argument, "progress file " + file + ": cannot open the file");
  std::vector<ConvergencePoint> points;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = "progress file " + file + " line " + std::to_string(number) + ": ";
    nlohmann::json j = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded() || !j.is_object())
      throw Error(ErrorCode::invalid_argument, where + "not a JSON object");
    if (j.value("event", "") != "progress") continue;
    const auto number_field = [&](const char* key) {
      if (!j.contains(key) || !j[key].is_number() || !std::isfinite(j[key].get<double>()))
        throw Error(ErrorCode::invalid_argument, where + "progress without a finite \"" + key + "\"");
      return j[key].get<double>();
    };
    points.push_back({static_cast<int>(number_field("generation")), number_field("best_energy"),
                      number_field("mean_energy")});
  }
  if (points.empty())
    throw Error(ErrorCode::invalid_argument,
                "progress file " + file + ": no progress lines (write them with `depath solve ... --json`)");
  return points;
}

namespace {

constexpr size_t kMaxMarkers = 200;

struct Axis {
  double lo = 0, hi = 1;
  bool log = false;
  double to_unit(double v) const {
    return log ? (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo)) : (v - lo) / (hi - lo);
  }
};

std::string tick_label(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

void draw(cairo_t* cr, const std::vector<ConvergencePoint>& points, int width, int height) {
  const double left = 78, right = 24, top = 36, bottom = 52;
  const double pw = width - left - right, ph = height - top - bottom;
  Axis x{double(points.front().generation), double(points.back().generation)};
  if (x.hi <= x.lo) x.hi = x.lo + 1;
  Axis y{INFINITY, -INFINITY};
  for (const auto& p : points)
    y.lo = std::min({y.lo, p.best_energy, p.mean_energy}),
    y.hi = std::max({y.hi, p.best_energy, p.mean_energy});
  y.log = y.lo > 0 && y.hi / y.lo > 20;
  if (!y.log) {
    const double pad = y.hi > y.lo ? 0.05 * (y.hi - y.lo) : std::max(1e-9, 0.05 * std::abs(y.hi));
    y.lo -= pad, y.hi += pad;
  }
  const auto sx = [&](double v) { return left + pw * x.to_unit(v); };
  const auto sy = [&](double v) { return top + ph * (1 - y.to_unit(v)); };

  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, 12);

  // Grid and tick labels: 5 steps on each axis (decades on a log axis).
  cairo_set_line_width(cr, 1);
  for (int i = 0; i <= 5; ++i) {
    const double gx = x.lo + (x.hi - x.lo) * i / 5;
    const double gy = y.log ? std::pow(10, std::log10(y.lo) + (std::log10(y.hi) - std::log10(y.lo)) * i / 5)
                            : y.lo + (y.hi - y.lo) * i / 5;
    cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
    cairo_move_to(cr, sx(gx), top), cairo_line_to(cr, sx(gx), top + ph);
    cairo_move_to(cr, left, sy(gy)), cairo_line_to(cr, left + pw, sy(gy));
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    const std::string lx = tick_label(std::round(gx)), ly = tick_label(gy);
    cairo_text_extents_t ext;
    cairo_text_extents(cr, lx.c_str(), &ext);
    cairo_move_to(cr, sx(gx) - ext.width / 2, top + ph + 18), cairo_show_text(cr, lx.c_str());
    cairo_text_extents(cr, ly.c_str(), &ext);
    cairo_move_to(cr, left - 8 - ext.width, sy(gy) + 4), cairo_show_text(cr, ly.c_str());
  }
  cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
  cairo_rectangle(cr, left, top, pw, ph);
  cairo_stroke(cr);
  cairo_move_to(cr, left + pw / 2 - 30, height - 12), cairo_show_text(cr, "generation");
  cairo_move_to(cr, left, 22), cairo_show_text(cr, y.log ? "energy (log scale)" : "energy");

  // The two series, one polyline each, clipped to the plot area.
  const auto series = [&](double r, double g, double b,
                          const std::function<double(const ConvergencePoint&)>& value, const char* name,
                          double legend_x) {
    cairo_save(cr);
    cairo_rectangle(cr, left, top, pw, ph);
    cairo_clip(cr);
    cairo_set_source_rgb(cr, r, g, b);
    cairo_set_line_width(cr, 2);
    for (size_t i = 0; i < points.size(); ++i) {
      const double px = sx(points[i].generation), py = sy(value(points[i]));
      if (i == 0)
        cairo_move_to(cr, px, py);
      else
        cairo_line_to(cr, px, py);
    }
    cairo_stroke(cr);
    // One disc per generation (a separate filled path each), while they stay readable.
    if (points.size() <= kMaxMarkers) {
      for (const auto& p : points) {
        cairo_arc(cr, sx(p.generation), sy(value(p)), 2.5, 0, 2 * M_PI);
        cairo_fill(cr);
      }
    }
    cairo_restore(cr);
    cairo_set_source_rgb(cr, r, g, b);
    cairo_set_line_width(cr, 3);
    cairo_move_to(cr, legend_x, 15), cairo_line_to(cr, legend_x + 16, 15), cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    cairo_move_to(cr, legend_x + 20, 20), cairo_show_text(cr, name);
  };
  series(
      0.86, 0.08, 0.08, [](const ConvergencePoint& p) { return p.best_energy; }, "best", left + pw - 150);
  series(
      0.20, 0.40, 0.85, [](const ConvergencePoint& p) { return p.mean_energy; }, "mean", left + pw - 70);
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

void write_convergence_plot(const std::vector<ConvergencePoint>& points, const std::string& out, int width,
                            int height) {
  if (points.empty()) throw Error(ErrorCode::invalid_argument, "nothing to plot");
  if (width < 200 || height < 150 || width > 10000 || height > 10000)
    throw Error(ErrorCode::invalid_argument, "plot size must be between 200x150 and 10000x10000");
  const bool svg = ends_with(out, ".svg"), png = ends_with(out, ".png");
  if (!svg && !png) throw Error(ErrorCode::invalid_argument, "plot output " + out + ": name it .svg or .png");
  std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface(
      svg ? cairo_svg_surface_create(out.c_str(), width, height)
          : cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height),
      cairo_surface_destroy);
  if (cairo_surface_status(surface.get()) != CAIRO_STATUS_SUCCESS)
    throw Error(ErrorCode::invalid_argument,
                "cannot write " + out + ": " + cairo_status_to_string(cairo_surface_status(surface.get())));
  {
    std::unique_ptr<cairo_t, decltype(&cairo_destroy)> cr(cairo_create(surface.get()), cairo_destroy);
    draw(cr.get(), points, width, height);
  }
  cairo_status_t status;
  if (svg) {
    cairo_surface_finish(surface.get());
    status = cairo_surface_status(surface.get());
  } else {
    status = cairo_surface_write_to_png(surface.get(), out.c_str());
  }
  if (status != CAIRO_STATUS_SUCCESS)
    throw Error(ErrorCode::invalid_argument, "cannot write " + out + ": " + cairo_status_to_string(status));
}

}  // namespace depath::picture
