#include "depath/fast_marching.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace depath {

FastMarching::FastMarching(const FastMarchingStencils& stencils) : stencils_(stencils) {
  const int nv = stencils.mesh().num_vertices();
  u_.assign(nv, std::numeric_limits<double>::infinity());
  state_.assign(nv, kFar);
  order_.assign(nv, INT32_MAX);
  heap_pos_.assign(nv, -1);
  heap_.reserve(nv);
}

void FastMarching::push_or_decrease(int v, double value) {
  int i = heap_pos_[v];
  if (i < 0) {
    i = static_cast<int>(heap_.size());
    heap_.push_back({value, v});
    state_[v] = kTrial;
  }
  u_[v] = value;
  // Sift up (values only decrease).
  while (i > 0) {
    const int parent = (i - 1) >> 1;
    if (heap_[parent].key <= value) break;
    heap_[i] = heap_[parent];
    heap_pos_[heap_[i].vertex] = i;
    i = parent;
  }
  heap_[i] = {value, v};
  heap_pos_[v] = i;
}

int FastMarching::pop_min() {
  const int top = heap_[0].vertex;
  heap_pos_[top] = -1;
  const HeapEntry last = heap_.back();
  heap_.pop_back();
  const int n = static_cast<int>(heap_.size());
  if (n > 0) {
    // Sift `last` down from the root.
    int i = 0;
    for (;;) {
      int child = 2 * i + 1;
      if (child >= n) break;
      if (child + 1 < n && heap_[child + 1].key < heap_[child].key) ++child;
      if (heap_[child].key >= last.key) break;
      heap_[i] = heap_[child];
      heap_pos_[heap_[i].vertex] = i;
      i = child;
    }
    heap_[i] = last;
    heap_pos_[last.vertex] = i;
  }
  return top;
}

void FastMarching::run(std::span<const double> density, int source, int stop_vertex) {
  const Mesh& mesh = stencils_.mesh();
  const double* rho = density.data();
  std::fill(u_.begin(), u_.end(), std::numeric_limits<double>::infinity());
  std::fill(state_.begin(), state_.end(), kFar);
  std::fill(order_.begin(), order_.end(), INT32_MAX);
  for (const HeapEntry& e : heap_) heap_pos_[e.vertex] = -1;
  heap_.clear();
  num_final_ = 0;

  push_or_decrease(source, 0.0);
  bool stop_reached = false;
  while (!heap_.empty()) {
    const int x = pop_min();
    state_[x] = kFinal;
    order_[x] = num_final_++;
    const double ux = u_[x];
    const double rx = rho[x];

    for (auto* up = stencils_.updates_begin(x), *end = stencils_.updates_end(x); up != end; ++up) {
      const int c = up->target;
      if (state_[c] == kFinal) continue;
      const double rc = rho[c];
      // Straight segment from x: length times the mean density at its ends.
      double best = ux + 0.5 * (rc + rx) * double(up->len_this);
      const int y = up->other;
      if (y >= 0 && state_[y] == kFinal) {
        const double uy = u_[y];
        const double ry = rho[y];
        const double delta = uy - ux;
        // Semi-Lagrangian triangle update: minimise u(p) + F |p - c| over p on segment x-y,
        // F the mean density of the segment p-c (refined once at the minimiser).
        const double lambda0 = up->lambda0, height = up->height, inv_len2 = up->inv_len2;
        double lambda = std::clamp(lambda0, 0.0, 1.0);
        for (int pass = 0; pass < 2; ++pass) {
          const double F = 0.5 * (rc + rx + lambda * (ry - rx));
          const double q = F * F - delta * delta * inv_len2;
          if (q <= 0.0) break;
          const double root = std::sqrt(q);
          const double l = lambda0 - delta * height * inv_len2 / root;
          if (l <= 0.0 || l >= 1.0) break;
          lambda = l;
          if (pass == 1 || rx == ry) {
            best = std::min(best, ux + lambda0 * delta + height * root);
            break;
          }
        }
        best = std::min(best, uy + 0.5 * (rc + ry) * double(up->len_other));
      }
      // Keep acceptance order monotone (Dijkstra invariant): nothing below what is final.
      best = std::max(best, ux);
      if (best < u_[c]) push_or_decrease(c, best);
    }

    if (x == stop_vertex) stop_reached = true;
    if (stop_reached) {
      bool ring_final = true;
      for (const int* n = mesh.vertex_neighbors_begin(stop_vertex); n != mesh.vertex_neighbors_end(stop_vertex); ++n) {
        if (state_[*n] != kFinal) {
          ring_final = false;
          break;
        }
      }
      if (ring_final) break;
    }
  }
}

}  // namespace depath
