// SPDX-License-Identifier: MIT
// Seeded random analytic cases for the angle energies (issue 12), shared by the tests and
// bench/angle_cases: every case has a known path of (near) zero angle energy between s and t.
//
//  - contour: a grid of random size (31-51 per side, random diagonals, random half size and
//    height axis) lifted to a random sum of 2-4 Gaussians; the field is the height gradient
//    rotated by 90 degrees (--field-from-height --rotate 90), whose field lines are the
//    contour lines. s is a grid vertex on a steep enough spot; the analytic contour through
//    it is traced while the slope stays above a quarter of the bumps' typical slope (away
//    from saddles) (RK4 on the rotated gradient of the analytic height); t is the grid vertex
//    closest to that contour within the traced stretch, nudged onto it (moved in the plane to
//    the contour point, height set to the analytic height there, at most 0.3 spacings).
//    The contour's radius of curvature between s and t is at least kMinContourRadius
//    spacings, so that the mesh resolves it (a path is straight inside each face).
//  - spiral: an open cone with the apex up (random generator slope h / R, rings, sectors,
//    height axis), target slope k and a turn count up to 1.5; s is a ring vertex at angle 0,
//    the analytic constant-slope spiral r = r_s exp(-(R / L) phi cot(alpha)),
//    cos(alpha) = k L / h, climbs from it; t is the vertex at the spiral's end angle on the
//    ring nearest its end radius, nudged along its generator onto the spiral (so it stays
//    on the ideal cone).
// Same seed, same case (own generator arithmetic, no std:: distributions).
#pragma once

#include "depath/generators/surfaces.hpp"
#include "depath/solve/job.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace depath::test {

/// A random case: mesh, the job's energy part, end points, and what describes it.
struct AngleCase {
  Mesh mesh;
  EnergySpec energy;
  int source = -1;
  int target = -1;
  std::string description;
  double nudge = 0.0;  ///< how far t was moved onto the analytic curve (mesh units)
  double resolution = 0.0;  ///< contour: largest curvature x grid spacing between s and t
};

/// splitmix64: a small, portable, seeded generator.
class CaseRandom {
 public:
  // The seed is hashed first: seeded linearly, the streams of nearby seeds are shifts of
  // one another, and two seeds whose rejected draws differ by that shift give one case.
  explicit CaseRandom(uint64_t seed) : state_(mix(seed + 0x632BE59BD9B4E019ull)) {}
  uint64_t next() { return mix(state_ += 0x9E3779B97F4A7C15ull); }
  double uniform(double lo = 0.0, double hi = 1.0) { return lo + (hi - lo) * ((next() >> 11) * 0x1.0p-53); }
  int below(int n) { return static_cast<int>(next() % static_cast<uint64_t>(n)); }

 private:
  static uint64_t mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  uint64_t state_;
};

namespace detail {

struct Gaussian {
  double cu, cv, sigma, amplitude;
};

inline double terrain_height(const std::vector<Gaussian>& g, double u, double v) {
  double h = 0.0;
  for (const auto& b : g) h += b.amplitude * std::exp(-((u - b.cu) * (u - b.cu) + (v - b.cv) * (v - b.cv)) / (2 * b.sigma * b.sigma));
  return h;
}

inline void terrain_gradient(const std::vector<Gaussian>& g, double u, double v, double& gu, double& gv) {
  gu = gv = 0.0;
  for (const auto& b : g) {
    const double e = b.amplitude * std::exp(-((u - b.cu) * (u - b.cu) + (v - b.cv) * (v - b.cv)) / (2 * b.sigma * b.sigma));
    gu -= e * (u - b.cu) / (b.sigma * b.sigma);
    gv -= e * (v - b.cv) / (b.sigma * b.sigma);
  }
}

// Curvature of the contour line through (u, v): (h_uu h_v^2 - 2 h_uv h_u h_v + h_vv h_u^2) / |grad h|^3.
inline double contour_curvature(const std::vector<Gaussian>& g, double u, double v) {
  double hu = 0, hv = 0, huu = 0, huv = 0, hvv = 0;
  for (const auto& b : g) {
    const double s2 = b.sigma * b.sigma, du = u - b.cu, dv = v - b.cv;
    const double e = b.amplitude * std::exp(-(du * du + dv * dv) / (2 * s2));
    hu -= e * du / s2;
    hv -= e * dv / s2;
    huu += e * (du * du / s2 - 1) / s2;
    hvv += e * (dv * dv / s2 - 1) / s2;
    huv += e * du * dv / (s2 * s2);
  }
  const double g2 = hu * hu + hv * hv;
  return std::abs(huu * hv * hv - 2 * huv * hu * hv + hvv * hu * hu) / (g2 * std::sqrt(g2));
}

inline Vec3 place(int up, double u, double v, double h) {
  Vec3 p;
  p[(up + 1) % 3] = u;
  p[(up + 2) % 3] = v;
  p[up] = h;
  return p;
}

inline constexpr double kMinContourRadius = 7.0;  // grid spacings (see try_contour_case)

inline std::optional<AngleCase> try_contour_case(CaseRandom& rng) {
  const int n = 31 + rng.below(21);
  const double half = rng.uniform(1.0, 3.0);
  const int up = rng.below(3);
  const double spacing = 2 * half / (n - 1);
  std::vector<Gaussian> bumps(2 + rng.below(3));
  for (auto& b : bumps) {
    b.cu = rng.uniform(-0.7, 0.7) * half;
    b.cv = rng.uniform(-0.7, 0.7) * half;
    // At least 6 grid spacings wide, so that the mesh resolves the contours' curvature (the
    // per-vertex field then stays within a fraction of 0.02 of the contour direction).
    b.sigma = std::max(rng.uniform(0.25, 0.6) * half, 6 * spacing);
    b.amplitude = (rng.uniform() < 0.5 ? -1.0 : 1.0) * rng.uniform(0.3, 1.0) * half;
  }
  GridOptions o;
  o.n = n;
  o.half_size = half;
  o.up_axis = up;
  o.diagonals = rng.uniform() < 0.5 ? GridDiagonals::uniform : GridDiagonals::alternating;
  const Mesh flat = make_grid(o);
  std::vector<Vec3> p = flat.positions();
  const int ua = (up + 1) % 3, va = (up + 2) % 3;
  for (Vec3& x : p) x[up] = terrain_height(bumps, x[ua], x[va]);
  // Steepness floor along the contour: a quarter of the typical slope (amplitude / sigma).
  // It keeps the stretch away from saddles, where the level set branches and the mesh's
  // piecewise-linear contour may join another branch than the analytic one (then no
  // zero-energy path from s to t exists on the mesh).
  double typical = 0.0;
  for (const auto& b : bumps) typical = std::max(typical, std::abs(b.amplitude) / b.sigma);
  const double min_slope = 0.25 * typical;
  // s: a vertex inside the middle of the grid, steep enough.
  int s = -1;
  for (int attempt = 0; attempt < 200 && s < 0; ++attempt) {
    const int i = n / 5 + rng.below(n - 2 * (n / 5)), j = n / 5 + rng.below(n - 2 * (n / 5));
    const int v = j * n + i;
    double gu, gv;
    terrain_gradient(bumps, p[v][ua], p[v][va], gu, gv);
    if (std::hypot(gu, gv) >= 1.6 * min_slope) s = v;
  }
  if (s < 0) return std::nullopt;
  // Trace the contour through s (RK4 on the unit rotated gradient, step a tenth of the
  // spacing), either way round; stop near the border, where the terrain flattens, or
  // when the contour closes (within a spacing of s after leaving it).
  const double dir = rng.uniform() < 0.5 ? 1.0 : -1.0;
  auto velocity = [&](double u, double v, double& du, double& dv) {
    double gu, gv;
    terrain_gradient(bumps, u, v, gu, gv);
    const double g = std::hypot(gu, gv);
    if (!(g >= min_slope)) return false;
    du = -dir * gv / g;
    dv = dir * gu / g;
    return true;
  };
  const double step = 0.1 * spacing, max_length = rng.uniform(0.8, 2.5) * half;
  std::vector<std::array<double, 3>> trace;  // u, v, arc length
  double u = p[s][ua], v = p[s][va], length = 0.0;
  trace.push_back({u, v, 0.0});
  bool left = false;
  while (length < max_length) {
    double k1u, k1v, k2u, k2v, k3u, k3v, k4u, k4v;
    if (!velocity(u, v, k1u, k1v) || !velocity(u + 0.5 * step * k1u, v + 0.5 * step * k1v, k2u, k2v) ||
        !velocity(u + 0.5 * step * k2u, v + 0.5 * step * k2v, k3u, k3v) ||
        !velocity(u + step * k3u, v + step * k3v, k4u, k4v))
      break;
    u += step * (k1u + 2 * k2u + 2 * k3u + k4u) / 6;
    v += step * (k1v + 2 * k2v + 2 * k3v + k4v) / 6;
    length += step;
    if (std::max(std::abs(u), std::abs(v)) > half - 2 * spacing) break;
    const double back = std::hypot(u - trace[0][0], v - trace[0][1]);
    if (back > 3 * spacing) left = true;
    if (left && back < 3 * spacing) break;
    trace.push_back({u, v, length});
  }
  if (length < 12 * spacing) return std::nullopt;
  // t: over the last 60% of the stretch, the point whose nearest grid vertex is closest.
  int best_vertex = -1;
  double best_d = 1e300, best_u = 0, best_v = 0, best_length = 0;
  for (const auto& q : trace) {
    if (q[2] < 0.4 * length || q[2] < 10 * spacing) continue;
    const int i = static_cast<int>(std::lround((q[0] + half) / spacing));
    const int j = static_cast<int>(std::lround((q[1] + half) / spacing));
    if (i < 1 || j < 1 || i > n - 2 || j > n - 2) continue;
    const int w = j * n + i;
    const double d = std::hypot(p[w][ua] - q[0], p[w][va] - q[1]);
    if (d < best_d) {
      best_d = d;
      best_vertex = w;
      best_u = q[0];
      best_v = q[1];
      best_length = q[2];
    }
  }
  if (best_vertex < 0 || best_vertex == s || best_d > 0.3 * spacing) return std::nullopt;
  p[best_vertex] = place(up, best_u, best_v, terrain_height(bumps, best_u, best_v));
  // The grid must resolve the contour between s and t: its radius of curvature at least
  // kMinContourRadius spacings. A path on the mesh is straight inside each face, so even
  // the chords of the mesh's own field line deviate from the field by a mean angle of
  // about curvature x chord / 4 (the field turns along the chord); on the tightest
  // contours (radius 2-5 spacings, near a bump's top) that floor alone is 0.023-0.035, so
  // no path of the mesh meets 0.02 there (measured: guide_paths, then the refinement).
  double resolution = 0.0;
  for (const auto& q : trace)
    if (q[2] <= best_length) resolution = std::max(resolution, contour_curvature(bumps, q[0], q[1]) * spacing);
  if (resolution > 1.0 / kMinContourRadius) return std::nullopt;
  AngleCase c{Mesh(std::move(p), flat.faces()), {}, s, best_vertex, {}, best_d, resolution};
  c.energy.kind = EnergyKind::vector_field;
  c.energy.field_from_height = true;
  c.energy.rotate_degrees = 90.0;
  c.energy.up_axis = up;
  c.description = "contour n=" + std::to_string(n) + " half=" + std::to_string(half).substr(0, 4) +
                  " up=" + std::to_string(up) + " bumps=" + std::to_string(bumps.size()) +
                  " arc=" + std::to_string(length).substr(0, 5);
  return c;
}

}  // namespace detail

/// A constant-slope spiral case on a cone (see the file comment): generator slope h / R
/// (R = 1), target slope k, turns (rounded to whole sectors), start ring; nullopt when the
/// spiral would end within 3 rings of its start or inside a quarter of the radius.
struct SpiralParams {
  double generator_slope = 1.0;
  double k = 0.2;
  double turns = 0.5;
  int rings = 20;
  int sectors = 64;
  int start_ring = 20;
  int up_axis = 2;
};

inline std::optional<AngleCase> spiral_case(const SpiralParams& s) {
  ConeOptions o;
  o.radius = 1.0;
  o.height = s.generator_slope * o.radius;
  o.rings = s.rings;
  o.sectors = s.sectors;
  o.up_axis = s.up_axis;
  const double L = std::hypot(o.height, o.radius);
  const int end_sectors = std::max(1, static_cast<int>(std::lround(s.turns * o.sectors)));
  const double phi = 2 * std::numbers::pi * end_sectors / o.sectors;
  const double r_s = o.radius * s.start_ring / o.rings;
  const double cos_alpha = s.k * L / o.height;
  if (!(cos_alpha > 0.0 && cos_alpha < 1.0)) return std::nullopt;
  const double cot_alpha = cos_alpha / std::sqrt(1 - cos_alpha * cos_alpha);
  const double r_t = r_s * std::exp(-(o.radius / L) * phi * cot_alpha);
  const double ring_width = o.radius / o.rings;
  if (r_t < 0.25 * o.radius || r_t > r_s - 3 * ring_width) return std::nullopt;
  const int end_ring = static_cast<int>(std::lround(r_t / ring_width));
  const int t = cone_vertex(o, end_ring, end_sectors % o.sectors);
  Mesh cone = make_cone(o);
  std::vector<Vec3> p = cone.positions();
  const double nudge = std::abs(end_ring * ring_width - r_t);
  p[t] = detail::place(o.up_axis, r_t * std::cos(phi), r_t * std::sin(phi), o.height * (1 - r_t / o.radius));
  AngleCase c{Mesh(std::move(p), cone.faces()), {}, cone_vertex(o, s.start_ring, 0), t, {}, nudge};
  c.energy.kind = EnergyKind::constant_slope;
  c.energy.slope = s.k;
  c.energy.up_axis = o.up_axis;
  c.description = "spiral h/R=" + std::to_string(s.generator_slope).substr(0, 4) +
                  " k=" + std::to_string(s.k).substr(0, 5) +
                  " turns=" + std::to_string(phi / (2 * std::numbers::pi)).substr(0, 4) +
                  " rings=" + std::to_string(o.rings) + " sectors=" + std::to_string(o.sectors) +
                  " up=" + std::to_string(o.up_axis);
  return c;
}

namespace detail {

inline std::optional<AngleCase> try_spiral_case(CaseRandom& rng) {
  SpiralParams s;
  s.generator_slope = rng.uniform(0.6, 1.6);
  s.rings = 16 + rng.below(9);
  s.sectors = 48 + 8 * rng.below(4);
  s.up_axis = rng.below(3);
  const double L = std::hypot(s.generator_slope, 1.0);
  s.k = rng.uniform(0.05, std::min(0.45, 0.8 * s.generator_slope / L));
  s.turns = rng.uniform(0.2, 1.5);
  s.start_ring = s.rings - rng.below(std::max(1, s.rings / 4));
  return spiral_case(s);
}

}  // namespace detail

/// Which family of random cases.
enum class AngleFamily { contour, spiral };

/// The random case of `family` for `seed` (deterministic; draws until one is valid).
inline AngleCase random_angle_case(AngleFamily family, uint64_t seed) {
  CaseRandom rng(seed * 2 + (family == AngleFamily::spiral ? 1 : 0));
  for (;;) {
    auto c = family == AngleFamily::contour ? detail::try_contour_case(rng) : detail::try_spiral_case(rng);
    if (c) return std::move(*c);
  }
}

}  // namespace depath::test
