// SPDX-License-Identifier: MIT
#include "depath/decode/fast_marching.hpp"

#include "decode/log_densities.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>

namespace depath {

FastMarching::FastMarching(const FastMarchingStencils& stencils) : stencils_(stencils) {
  const int nv = stencils.mesh().num_vertices();
  u_.assign(nv, std::numeric_limits<double>::infinity());
  state_.assign(nv, kFar);
  order_.assign(nv, INT32_MAX);
  accepted_.assign(nv, 0);
  touched_.reserve(nv);
  heap_pos_.assign(nv, -1);
  heap_store_.resize(nv + 8);
}

void FastMarching::push_or_decrease(int v, double value) {
  int i = heap_pos_[v];
  if (i < 0) {
    i = heap_size_++;
    state_[v] = kTrial;
    touched_.push_back(v);
  }
  u_[v] = value;
  // Sift up (values only decrease).
  while (i > 0) {
    const int parent = (i - 1) >> 2;
    if (heap_[parent].key <= value) break;
    heap_[i] = heap_[parent];
    heap_pos_[heap_[i].vertex] = i;
    i = parent;
  }
  heap_[i] = {value, v};
  heap_pos_[v] = i;
}

int FastMarching::pop_min() {
  HeapEntry* const h = heap_;
  const int top = h[0].vertex;
  heap_pos_[top] = -1;
  const int n = --heap_size_;
  if (n > 0) {
    const HeapEntry last = h[n];
    // Move the hole at the root down to a leaf along the smaller children, then sift
    // `last` up from there (Floyd's bottom-up variant): `last` came from the bottom and
    // rarely climbs, and the walk down ends at a depth the branch predictor knows,
    // instead of after a comparison with `last` that mispredicts once per pop.
    int i = 0;
    for (;;) {
      const int c = 4 * i + 1;
      if (c >= n) break;
      int m;
      if (c + 3 < n) {
        // Index arithmetic instead of ?: so that no jump depends on the (random) keys.
        const int m01 = c + int(h[c + 1].key < h[c].key);
        const int m23 = c + 2 + int(h[c + 3].key < h[c + 2].key);
        m = m01 ^ ((m01 ^ m23) & -int(h[m23].key < h[m01].key));
      } else {
        m = c;
        for (int k = c + 1; k < n; ++k)
          if (h[k].key < h[m].key) m = k;
      }
      h[i] = h[m];
      heap_pos_[h[i].vertex] = i;
      i = m;
    }
    while (i > 0) {
      const int parent = (i - 1) >> 2;
      if (h[parent].key <= last.key) break;
      h[i] = h[parent];
      heap_pos_[h[i].vertex] = i;
      i = parent;
    }
    h[i] = last;
    heap_pos_[last.vertex] = i;
  }
  return top;
}

void FastMarching::reset() {
  const int nv = static_cast<int>(u_.size());
  if (touched_.size() * 4 > size_t(nv)) {
    std::fill(u_.begin(), u_.end(), std::numeric_limits<double>::infinity());
    std::fill(state_.begin(), state_.end(), kFar);
    std::fill(order_.begin(), order_.end(), INT32_MAX);
    std::fill(heap_pos_.begin(), heap_pos_.end(), -1);
  } else {
    for (const int32_t v : touched_) {
      u_[v] = std::numeric_limits<double>::infinity();
      state_[v] = kFar;
      order_[v] = INT32_MAX;
      heap_pos_[v] = -1;
    }
  }
  touched_.clear();
  heap_size_ = 0;
  num_final_ = 0;
  // Align so that the children 4i+1 .. 4i+4 of every node share a cache line.
  const auto addr = reinterpret_cast<uintptr_t>(heap_store_.data() + 1);
  heap_ = heap_store_.data() + ((64 - addr % 64) % 64) / sizeof(HeapEntry);
}

void FastMarching::run(std::span<const double> density, int source, int stop_vertex) {
  march(density.data(), source, stop_vertex);
}

void FastMarching::run_log(std::span<const double> log_density, int source, int stop_vertex) {
  // All at once rather than per vertex reached: the vectorised exp costs less for the
  // whole mesh than std::exp for the part an early-stopped march reaches.
  rho_.resize(u_.size());
  const size_t given = std::min(log_density.size(), rho_.size());
  densities_from_logs(log_density.first(given), rho_);
  std::fill(rho_.begin() + given, rho_.end(), 0.0);
  march(rho_.data(), source, stop_vertex);
}

void FastMarching::march(const double* rho, int source, int stop_vertex) {
  const Mesh& mesh = stencils_.mesh();
  reset();
  const FastMarchingStencils::Tri* const tris = stencils_.tris();
  double* const u = u_.data();
  const uint8_t* const state = state_.data();

  push_or_decrease(source, 0.0);
  bool stop_reached = false;
  while (heap_size_ > 0) {
    const int x = pop_min();
    state_[x] = kFinal;
    accepted_[num_final_] = x;
    order_[x] = num_final_++;
    const double ux = u[x];
    const double rx = rho[x];
    if (heap_size_ > 0) {
      // The next vertex to accept is most likely the new top: fetch its stencil early.
      const auto* next = stencils_.groups_begin(heap_[0].vertex);
      __builtin_prefetch(next);
      __builtin_prefetch(reinterpret_cast<const char*>(next) + 64);
    }

    for (auto* g = stencils_.groups_begin(x), *end = stencils_.groups_end(x); g != end; ++g) {
      const int c = g->target;
      if (state[c] == kFinal) continue;
      const double rc = rho[c];
      // Straight segment from x: length times the mean density at its ends.
      double best = ux + 0.5 * (rc + rx) * double(g->len);
      for (auto* t = tris + g->tri_begin, *tend = tris + g->tri_end; t != tend; ++t) {
        const int y = t->other;
        if (state[y] != kFinal) continue;
        const double uy = u[y];
        const double ry = rho[y];
        const double delta = uy - ux;
        // Semi-Lagrangian triangle update: minimise u(p) + F |p - c| over p on segment x-y,
        // F the mean density of the segment p-c (refined once at the minimiser).
        const double lambda0 = t->lambda0, height = t->height, inv_len2 = t->inv_len2;
        double lambda = std::min(std::max(lambda0, 0.0), 1.0);
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
        // (The straight segment from y was tried when y was accepted.)
      }
      // Keep acceptance order monotone (Dijkstra invariant): nothing below what is final.
      best = std::max(best, ux);
      if (best < u[c]) push_or_decrease(c, best);
    }

    if (x == stop_vertex) stop_reached = true;
    if (stop_reached) {
      bool ring_final = true;
      for (const int* n = mesh.vertex_neighbors_begin(stop_vertex); n != mesh.vertex_neighbors_end(stop_vertex); ++n) {
        if (state[*n] != kFinal) {
          ring_final = false;
          break;
        }
      }
      if (ring_final) break;
    }
  }
}

}  // namespace depath
