// SPDX-License-Identifier: MIT
#include "refine/points.hpp"

#include "refine/straighten.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace depath::refine {
namespace {

// Finite-difference steps in edge parameter units: at most kMaxStep, and a small
// fraction (kRelativeStep) of the point's distance to its neighbours, since the energy
// bends on that scale (a segment's length is |x|-like near zero). Round-off in second
// differences stays ~1e-16 / kRelativeStep^2 relative to the curvature.
constexpr double kMaxStep = 1e-4;
constexpr double kRelativeStep = 1e-3;
constexpr double kMinStep = 1e-8;

// Symmetric band matrix with half-bandwidth 2, stored as rows of its lower band:
// band[i][k] = A(i, i - k).
using BandRow = std::array<double, 3>;

// Solves M x = rhs where M is A + shift I made positive definite row by row: a pivot
// that is not safely positive (an indefinite or singular direction, e.g. a point
// squeezed against a vertex where finite differences see a kink) is replaced by the
// row's diagonal magnitude (modified Cholesky), so one bad variable damps only itself
// instead of the whole chain. False if the result is not finite.
bool band_solve(const std::vector<BandRow>& a, double shift, const std::vector<double>& rhs,
                std::vector<double>& x) {
  const int n = static_cast<int>(a.size());
  std::vector<BandRow> l(n, BandRow{0.0, 0.0, 0.0});
  for (int i = 0; i < n; ++i) {
    for (int k = std::min(2, i); k >= 0; --k) {
      const int j = i - k;
      double s = a[i][k] + (k == 0 ? shift : 0.0);
      for (int m = std::max(0, i - 2); m < j; ++m) s -= l[i][i - m] * l[j][j - m];
      if (k == 0) {
        const double diag = std::abs(a[i][0]) + shift;
        if (!(s > 1e-8 * diag)) s = diag > 0.0 ? diag : 1.0;
        if (!std::isfinite(s)) return false;
        l[i][0] = std::sqrt(s);
      } else {
        l[i][k] = s / l[j][0];
      }
    }
  }
  x.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    double s = rhs[i];
    for (int m = std::max(0, i - 2); m < i; ++m) s -= l[i][i - m] * x[m];
    x[i] = s / l[i][0];
  }
  for (int i = n - 1; i >= 0; --i) {
    double s = x[i];
    for (int m = i + 1; m <= std::min(n - 1, i + 2); ++m) s -= l[m][m - i] * x[m];
    x[i] = s / l[i][0];
  }
  for (double v : x) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

class NewtonChain {
 public:
  NewtonChain(Evaluator& eval, SurfacePath& path) : eval_(eval), path_(path) {
    const int n = static_cast<int>(path.points.size());
    var_of_point_.assign(n, -1);
    for (int i = 1; i + 1 < n; ++i) {
      if (!path.points[i].is_vertex()) {
        var_of_point_[i] = static_cast<int>(points_.size());
        points_.push_back(i);
      }
    }
  }

  const std::vector<int>& points() const { return points_; }

  // Runs projected Newton; returns the new energy. `stalled` tells whether it stopped
  // because no step lowered the energy while the gradient was not negligible.
  double run(double energy, int max_iterations, const std::function<bool()>& cancelled, bool& stalled) {
    stalled = false;
    const int n = static_cast<int>(points_.size());
    if (n == 0) return energy;
    std::vector<double> t(n), trial(n), step, rhs(n);
    for (int iteration = 0; iteration < max_iterations; ++iteration) {
      if (is_cancelled(cancelled)) return energy;
      for (int a = 0; a < n; ++a) t[a] = path_.points[points_[a]].t;
      derivatives();
      // Variables at a bound whose gradient pushes outwards stay there (active set).
      double gmax = 0.0, dmax = 0.0;
      std::vector<BandRow> a = hessian_;
      for (int v = 0; v < n; ++v) {
        const bool fixed = (t[v] <= 0.0 && gradient_[v] > 0.0) || (t[v] >= 1.0 && gradient_[v] < 0.0);
        if (fixed) {
          a[v] = BandRow{1.0, 0.0, 0.0};
          for (int k = 1; k <= 2 && v + k < n; ++k) a[v + k][k] = 0.0;
          rhs[v] = 0.0;
        } else {
          rhs[v] = -gradient_[v];
          gmax = std::max(gmax, std::abs(gradient_[v]));
          dmax = std::max(dmax, std::abs(a[v][0]));
        }
      }
      // Converged: the gradient is at round-off level of the energy.
      if (gmax <= 1e-13 * (std::abs(energy) + 1e-300)) return energy;
      // The modified factorisation only fails on non-finite numbers; then a Levenberg
      // shift, and as a last resort steepest descent.
      double shift = 0.0;
      bool solved = false;
      for (int attempt = 0; attempt < 30 && !solved; ++attempt) {
        solved = band_solve(a, shift, rhs, step);
        if (!solved) shift = shift == 0.0 ? std::max(1e-12 * dmax, 1e-300) : shift * 10.0;
      }
      if (!solved) {
        // Fall back to steepest descent with a unit-free scale.
        step = rhs;
        const double smax = gmax;
        for (double& s : step) s /= smax;
      }
      bool accepted = false;
      double alpha = 1.0;
      for (int search = 0; search < 40; ++search, alpha *= 0.5) {
        bool moved = false;
        for (int v = 0; v < n; ++v) {
          trial[v] = std::clamp(t[v] + alpha * step[v], 0.0, 1.0);
          moved = moved || trial[v] != t[v];
        }
        if (!moved) break;
        set(trial);
        const double e = eval_.total(path_);
        if (e < energy) {
          accepted = true;
          const double decrease = energy - e;
          energy = e;
          if (decrease <= 1e-13 * std::abs(energy)) return energy;
          break;
        }
      }
      if (!accepted) {
        set(t);
        stalled = true;
        return energy;
      }
    }
    return energy;
  }

 private:
  void set(const std::vector<double>& t) {
    for (std::size_t a = 0; a < points_.size(); ++a) path_.points[points_[a]].t = t[a];
  }

  // Finite-difference gradient and Hessian of one term over the variables among its
  // points, accumulated into gradient_ / hessian_.
  template <typename Value>
  void add_term(const int* term_points, int count, Value&& value) {
    std::array<int, 3> pts{}, vars{};
    int k = 0;
    for (int c = 0; c < count; ++c) {
      const int v = var_of_point_[term_points[c]];
      if (v >= 0) {
        pts[k] = term_points[c];
        vars[k] = v;
        ++k;
      }
    }
    if (k == 0) return;
    std::array<double, 3> t0{}, center{};
    for (int i = 0; i < k; ++i) {
      t0[i] = path_.points[pts[i]].t;
      // Keep the stencil inside the edge; the Taylor correction below moves it back.
      center[i] = std::clamp(t0[i], step_[vars[i]], 1.0 - step_[vars[i]]);
    }
    auto at = [&](int i, double di, int j, double dj) {
      for (int m = 0; m < k; ++m) path_.points[pts[m]].t = center[m];
      if (i >= 0) path_.points[pts[i]].t += di;
      if (j >= 0) path_.points[pts[j]].t += dj;
      return value();
    };
    std::array<double, 3> h{};
    for (int i = 0; i < k; ++i) h[i] = step_[vars[i]];
    const double f0 = at(-1, 0, -1, 0);
    std::array<double, 3> g{};
    std::array<std::array<double, 3>, 3> hess{};
    std::array<double, 3> fp{}, fm{};
    for (int i = 0; i < k; ++i) {
      fp[i] = at(i, h[i], -1, 0);
      fm[i] = at(i, -h[i], -1, 0);
      g[i] = (fp[i] - fm[i]) / (2 * h[i]);
      hess[i][i] = (fp[i] - 2 * f0 + fm[i]) / (h[i] * h[i]);
    }
    for (int i = 0; i < k; ++i) {
      for (int j = i + 1; j < k; ++j) {
        const double fpp = at(i, h[i], j, h[j]), fpm = at(i, h[i], j, -h[j]);
        const double fmp = at(i, -h[i], j, h[j]), fmm = at(i, -h[i], j, -h[j]);
        hess[i][j] = hess[j][i] = (fpp - fpm - fmp + fmm) / (4 * h[i] * h[j]);
      }
    }
    for (int m = 0; m < k; ++m) path_.points[pts[m]].t = t0[m];
    for (int i = 0; i < k; ++i) {
      double gi = g[i];
      for (int j = 0; j < k; ++j) gi += hess[i][j] * (t0[j] - center[j]);
      if (!std::isfinite(gi)) continue;  // a kink or NaN: leave it to the line search
      gradient_[vars[i]] += gi;
      for (int j = 0; j <= i; ++j) {
        if (std::isfinite(hess[i][j])) hessian_[vars[i]][vars[i] - vars[j]] += hess[i][j];
      }
    }
  }

  void derivatives() {
    const int n = static_cast<int>(points_.size());
    const Mesh& mesh = eval_.mesh();
    step_.resize(n);
    for (int v = 0; v < n; ++v) {
      const int i = points_[v];
      const SurfacePoint& p = path_.points[i];
      const Vec3 x = p.position(mesh);
      const double edge = (mesh.position(p.v1) - mesh.position(p.v0)).norm();
      const double near = std::min((x - path_.points[i - 1].position(mesh)).norm(),
                                   (x - path_.points[i + 1].position(mesh)).norm());
      step_[v] = edge > 0.0 ? std::clamp(kRelativeStep * near / edge, kMinStep, kMaxStep) : kMaxStep;
    }
    gradient_.assign(n, 0.0);
    hessian_.assign(n, BandRow{0.0, 0.0, 0.0});
    const int np = static_cast<int>(path_.points.size());
    for (int s = 0; s + 1 < np; ++s) {
      const int pts[2] = {s, s + 1};
      add_term(pts, 2, [&] { return eval_.segment(path_, s); });
    }
    if (eval_.smooth()) {
      for (int i = 1; i + 1 < np; ++i) {
        const int pts[3] = {i - 1, i, i + 1};
        add_term(pts, 3, [&] { return eval_.turn(path_, i); });
      }
    }
  }

  Evaluator& eval_;
  SurfacePath& path_;
  std::vector<int> var_of_point_;
  std::vector<int> points_;
  std::vector<double> step_;
  std::vector<double> gradient_;
  std::vector<BandRow> hessian_;
};

}  // namespace

double golden_pass(Evaluator& eval, SurfacePath& path, const std::vector<int>& points) {
  constexpr double kInvPhi = 0.6180339887498949;
  double total_decrease = 0.0;
  for (const int i : points) {
    SurfacePoint& p = path.points[i];
    if (p.is_vertex()) continue;
    const double t_start = p.t;
    auto local = [&](double t) {
      p.t = t;
      return eval.window(path, i - 1, i + 1);
    };
    const double f_start = local(t_start);
    double best_t = t_start, best_f = f_start;
    auto consider = [&](double t, double f) {
      if (f < best_f) {
        best_f = f;
        best_t = t;
      }
    };
    consider(0.0, local(0.0));
    consider(1.0, local(1.0));
    double lo = 0.0, hi = 1.0;
    double x1 = hi - kInvPhi * (hi - lo), x2 = lo + kInvPhi * (hi - lo);
    double f1 = local(x1), f2 = local(x2);
    consider(x1, f1);
    consider(x2, f2);
    for (int iteration = 0; iteration < 40; ++iteration) {
      if (f1 < f2) {
        hi = x2;
        x2 = x1;
        f2 = f1;
        x1 = hi - kInvPhi * (hi - lo);
        f1 = local(x1);
        consider(x1, f1);
      } else {
        lo = x1;
        x1 = x2;
        f1 = f2;
        x2 = lo + kInvPhi * (hi - lo);
        f2 = local(x2);
        consider(x2, f2);
      }
    }
    p.t = best_t;
    total_decrease += f_start - best_f;
  }
  return total_decrease;
}

double optimize_edge_points(Evaluator& eval, SurfacePath& path, double energy, int max_newton_iterations,
                            const std::function<bool()>& cancelled) {
  if (eval.energy().length_factor() > 0.0) {
    // A length: the optimum is known exactly (and Newton's finite differences would cost
    // some twenty segment evaluations per point per iteration to approach it).
    const SurfacePath before = path;
    const int left_alone = straighten_runs(eval.mesh(), path);
    const double straightened = eval.total(path);
    if (straightened <= energy) {
      energy = straightened;
    } else {
      path = before;  // already straight up to round-off
    }
    if (left_alone == 0) return energy;
  }
  NewtonChain chain(eval, path);
  if (chain.points().empty()) return energy;
  bool stalled = false;
  energy = chain.run(energy, max_newton_iterations, cancelled, stalled);
  if (stalled && !is_cancelled(cancelled)) {
    // Newton could not descend (kinked energy, or a point squeezed against a vertex):
    // derivative-free per-point minimisation still makes progress there.
    if (golden_pass(eval, path, chain.points()) > 0.0) energy = eval.total(path);
  }
  return energy;
}

}  // namespace depath::refine
