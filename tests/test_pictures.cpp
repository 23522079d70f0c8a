// SPDX-License-Identifier: MIT
// `depath render` / `depath plot` drawing (client/picture): the picture has the requested size,
// the path and its endpoints are where the camera projects them, results from another mesh and
// broken inputs are refused with a message naming the problem, plots have one vertex per
// progress line; `depath render --field` (the binary) draws the field's segments along the
// field's direction at the vertices and leaves the picture as it was elsewhere.
#include <cairo.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "depath/generators/surfaces.hpp"
#include "depath/io/mesh_reader.hpp"
#include "depath/io/result_writer.hpp"
#include "depath/solve/solve.hpp"
#include "depath/util/error.hpp"
#include "picture/camera.hpp"
#include "picture/convergence_plot.hpp"
#include "picture/drawing_caches.hpp"
#include "picture/result_path.hpp"
#include "picture/scene_painter.hpp"

namespace depath {
namespace {

namespace fs = std::filesystem;

struct Rgb {
  int r, g, b;
};

Rgb pixel(cairo_surface_t* s, double x, double y) {
  const unsigned char* data = cairo_image_surface_get_data(s);
  const int stride = cairo_image_surface_get_stride(s);
  const uint32_t v = *reinterpret_cast<const uint32_t*>(data + int(y) * stride + 4 * int(x));
  return {int(v >> 16 & 0xff), int(v >> 8 & 0xff), int(v & 0xff)};
}

void expect_colour(const Rgb& got, const picture::Colour& want, const std::string& what) {
  EXPECT_NEAR(got.r, want[0] * 255, 2) << what;
  EXPECT_NEAR(got.g, want[1] * 255, 2) << what;
  EXPECT_NEAR(got.b, want[2] * 255, 2) << what;
}

class Pictures : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("depath-pictures-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }

  // The classic geodesic on an 11 x 11 flat grid over [-3, 3]^2 from (1, 1) to (9, 7).
  std::string grid_result(const Mesh& grid) const {
    JobSpec job;
    job.source = 1 * 11 + 1;
    job.target = 7 * 11 + 9;
    job.method = Method::fmm;
    const std::string out = file("grid.json");
    write_result(out, grid, solve(grid, job));
    return out;
  }

  fs::path dir_;
};

Mesh flat_grid(int n) {
  GridOptions options;
  options.n = n;
  return make_grid(options);
}

TEST_F(Pictures, PathAndEndpointsAreWhereTheCameraProjectsThem) {
  const Mesh grid = flat_grid(11);
  const std::vector<Vec3> path = picture::read_result_path(grid_result(grid), grid);
  ASSERT_GE(path.size(), 3u);
  EXPECT_EQ(path.front(), grid.position(12));
  EXPECT_EQ(path.back(), grid.position(86));

  const picture::OrthoCamera camera = picture::frame_on_path(grid, path, 640, 480);
  // A flat z-up grid is seen from above, x to the right and y up.
  EXPECT_NEAR(camera.view().z(), 1.0, 1e-12);
  EXPECT_NEAR(camera.right().x(), 1.0, 1e-12);
  EXPECT_NEAR(camera.up().y(), 1.0, 1e-12);
  // Framed: the path spans 4.8 x 3.6 units and fills 1/1.25 of the picture's limiting side.
  const auto s = camera.project(path.front()), t = camera.project(path.back());
  EXPECT_NEAR(t.x - s.x, 640 / 1.25, 1e-6);
  EXPECT_NEAR(s.y - t.y, 3.6 * camera.pixels_per_unit(), 1e-6);
  EXPECT_NEAR((s.x + t.x) / 2, 320, 1e-6);
  EXPECT_NEAR((s.y + t.y) / 2, 240, 1e-6);

  const std::string png = file("grid.png");
  picture::render_png(grid, camera, path, {}, png);
  cairo_surface_t* image = cairo_image_surface_create_from_png(png.c_str());
  ASSERT_EQ(cairo_surface_status(image), CAIRO_STATUS_SUCCESS);
  EXPECT_EQ(cairo_image_surface_get_width(image), 640);
  EXPECT_EQ(cairo_image_surface_get_height(image), 480);
  expect_colour(pixel(image, s.x, s.y), picture::kSourceColour, "source disc");
  expect_colour(pixel(image, t.x, t.y), picture::kTargetColour, "target disc");
  // The middle of the path's middle segment, far from both discs.
  const size_t k = path.size() / 2;
  const Vec3 mid = (path[k - 1] + path[k]) / 2;
  const auto m = camera.project(mid);
  expect_colour(pixel(image, m.x, m.y), picture::kPathColour, "path line");
  // Off the path: the grey shaded surface (seen head on), not the path colour.
  const Rgb surface = pixel(image, s.x + 30, s.y - 60);
  EXPECT_LT(std::abs(surface.r - surface.g), 10);
  EXPECT_GT(surface.g, 150);
  cairo_surface_destroy(image);
}

TEST_F(Pictures, FieldOverlayIsDrawnAndCheckedAgainstTheMesh) {
  const Mesh grid = flat_grid(11);
  const std::vector<Vec3> path = picture::read_result_path(grid_result(grid), grid);
  const picture::OrthoCamera camera = picture::frame_on_path(grid, path, 320, 240);
  const std::vector<Vec3> field(grid.num_vertices(), Vec3(1, 0, 0));
  picture::render_png(grid, camera, path, field, file("plain.png"));
  picture::render_png(grid, camera, path, {}, file("bare.png"));
  std::ifstream a(file("plain.png"), std::ios::binary), b(file("bare.png"), std::ios::binary);
  std::stringstream sa, sb;
  sa << a.rdbuf(), sb << b.rdbuf();
  EXPECT_NE(sa.str(), sb.str()) << "the field overlay changed nothing";
}

// `depath render MESH RESULT --field FILE` as users run it: on an 11 x 11 flat grid, a field
// along x draws a short horizontal segment at each vertex (teal over the grey surface), a
// field along y a vertical one, and without --field the same pixels are plain surface.
TEST_F(Pictures, RenderCommandDrawsTheFieldAlongItsDirection) {
  const std::string mesh_file = file("grid11.obj");
  ASSERT_EQ(std::system((std::string(DEPATH_BIN) + " generate grid --n 11 --half-size 3 --out " + mesh_file +
                         " 2>/dev/null")
                            .c_str()),
            0);
  const Mesh grid = load_mesh(mesh_file);
  ASSERT_EQ(grid.num_vertices(), 121);
  const std::string result = grid_result(grid);
  const std::vector<Vec3> path = picture::read_result_path(result, grid);
  const picture::OrthoCamera camera =
      picture::frame_on_path(grid, path, 640, 480);  // as the command frames it
  auto render = [&](const std::string& name, const std::string& field_flag) {
    const std::string png = file(name);
    const std::string command = std::string(DEPATH_BIN) + " render " + mesh_file + " " + result + " --out " +
                                png + " --width 640 --height 480" + field_flag + " 2>/dev/null";
    EXPECT_EQ(std::system(command.c_str()), 0) << command;
    cairo_surface_t* image = cairo_image_surface_create_from_png(png.c_str());
    EXPECT_EQ(cairo_surface_status(image), CAIRO_STATUS_SUCCESS) << png;
    return image;
  };
  auto field_file = [&](const std::string& name, const char* vector) {
    std::ofstream out(file(name));
    for (int v = 0; v < grid.num_vertices(); ++v) out << vector << "\n";
    return " --field " + file(name);
  };
  cairo_surface_t* bare = render("bare.png", "");
  cairo_surface_t* along_x = render("field-x.png", field_file("x.field", "1 0 0"));
  cairo_surface_t* along_y = render("field-y.png", field_file("y.field", "0 1 0"));
  // Teal: green and blue well above red (the surface is grey, the path red).
  auto teal = [](const Rgb& c) { return c.g - c.r > 15 && c.b - c.r > 15; };
  auto grey = [](const Rgb& c) { return std::abs(c.r - c.g) < 10 && std::abs(c.g - c.b) < 20 && c.g > 150; };
  // Vertices (i, j) = j * 11 + i away from the path (which runs from (1, 1) to (9, 7)).
  int checked = 0;
  for (const auto& [i, j] :
       {std::pair{8, 2}, std::pair{7, 1}, std::pair{2, 6}, std::pair{3, 7}, std::pair{9, 3}}) {
    const auto p = camera.project(grid.position(j * 11 + i));
    if (p.x < 8 || p.y < 8 || p.x > 632 || p.y > 472) continue;
    ++checked;
    const std::string at = "vertex (" + std::to_string(i) + ", " + std::to_string(j) + ")";
    for (const double d : {-4.0, 4.0}) {
      EXPECT_TRUE(teal(pixel(along_x, p.x + d, p.y)))
          << at << ": no x-field segment " << d << " px beside it";
      EXPECT_TRUE(grey(pixel(along_x, p.x, p.y + d))) << at << ": x-field drawn across x";
      EXPECT_TRUE(teal(pixel(along_y, p.x, p.y + d)))
          << at << ": no y-field segment " << d << " px beside it";
      EXPECT_TRUE(grey(pixel(along_y, p.x + d, p.y))) << at << ": y-field drawn across y";
      EXPECT_TRUE(grey(pixel(bare, p.x + d, p.y)) && grey(pixel(bare, p.x, p.y + d)))
          << at << ": bare picture";
    }
  }
  EXPECT_GE(checked, 4) << "too few test vertices inside the picture";
  cairo_surface_destroy(bare);
  cairo_surface_destroy(along_x);
  cairo_surface_destroy(along_y);
}

TEST_F(Pictures, ResultFromAnotherMeshIsRefused) {
  const Mesh big = flat_grid(11);
  const std::string result = grid_result(big);
  const Mesh small = flat_grid(5);
  try {
    picture::read_result_path(result, small);
    FAIL() << "a result with vertex 86 accepted on a 25-vertex mesh";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not on this mesh"), std::string::npos) << e.what();
  }
  // Same vertex count, other geometry: points are away from the vertices they name.
  GridOptions wide;
  wide.n = 11;
  wide.half_size = 5;
  try {
    picture::read_result_path(result, make_grid(wide));
    FAIL() << "a result accepted on a mesh of other coordinates";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not on this mesh"), std::string::npos) << e.what();
  }
}

TEST_F(Pictures, BrokenResultFilesNameTheProblem) {
  const Mesh grid = flat_grid(5);
  const auto message = [&](const std::string& name) {
    try {
      picture::read_result_path(file(name), grid);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message("missing.json").find("cannot open"), std::string::npos);
  std::ofstream(file("junk.json")) << "{not json";
  EXPECT_NE(message("junk.json").find("not JSON"), std::string::npos);
  std::ofstream(file("other.json")) << R"({"energy": 1})";
  EXPECT_NE(message("other.json").find("not a depath result"), std::string::npos);
}

TEST_F(Pictures, PlotHasOneVertexPerProgressLineInEachSeries) {
  std::ofstream lines(file("progress.jsonl"));
  lines << R"({"event":"status","message":"queued"})" << '\n';
  for (int g = 1; g <= 7; ++g)
    lines << R"({"event":"progress","generation":)" << g << R"(,"max_generations":7,"best_energy":)"
          << 10.0 - g << R"(,"mean_energy":)" << 20.0 - g
          << R"(,"evaluations":1,"improvements":0,"elapsed_seconds":0.1})" << '\n';
  lines << R"({"event":"result","energy":3})" << '\n';
  lines.close();
  const auto points = picture::read_progress_lines(file("progress.jsonl"));
  ASSERT_EQ(points.size(), 7u);
  EXPECT_EQ(points.front().generation, 1);
  EXPECT_EQ(points.back().best_energy, 3.0);
  picture::write_convergence_plot(points, file("plot.svg"), 800, 480);
  std::ifstream in(file("plot.svg"));
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string svg = buffer.str();
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  // One filled disc per generation in each series' colour (best red, mean blue).
  const auto count = [&](const std::string& needle) {
    int n = 0;
    for (size_t at = svg.find(needle); at != std::string::npos; at = svg.find(needle, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("fill:rgb(86%,8%,8%)"), 7);
  EXPECT_EQ(count("fill:rgb(20%,40%,85%)"), 7);
}

TEST_F(Pictures, PlotRefusesFilesWithoutProgress) {
  std::ofstream(file("empty.jsonl")) << R"({"event":"status","message":"queued"})" << '\n';
  EXPECT_THROW(picture::read_progress_lines(file("empty.jsonl")), Error);
  std::ofstream(file("bad.jsonl")) << "generation 3\n";
  try {
    picture::read_progress_lines(file("bad.jsonl"));
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("line 1"), std::string::npos) << e.what();
  }
  EXPECT_THROW(picture::read_progress_lines(file("missing.jsonl")), Error);
}

// Frees Cairo's and fontconfig's font caches after the last test (LeakSanitizer).
class DrawingCaches : public ::testing::Environment {
 public:
  void TearDown() override { picture::release_drawing_caches(); }
};
const auto* const kDrawingCaches = ::testing::AddGlobalTestEnvironment(new DrawingCaches);

}  // namespace
}  // namespace depath
