// SPDX-License-Identifier: MIT
#include "depath/decode/fast_marching.hpp"

#include "decode/log_densities.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace depath {
namespace {

std::atomic<uint64_t> vertices_made_final_total{0};

using Update = FastMarchingStencils::Update;

// Two doubles, one per triangle update of a record: SSE2 where there is SSE2 (every
// x86-64), plain scalars elsewhere. Either way every lane sees the same IEEE operations in
// the same order, so both give the same bits.
#if defined(__SSE2__)
using Pair = __m128d;
inline Pair splat(double v) { return _mm_set1_pd(v); }
inline Pair pair(double a, double b) { return _mm_set_pd(b, a); }
inline Pair widen(const float* f) {
  return _mm_cvtps_pd(_mm_castpd_ps(_mm_load_sd(reinterpret_cast<const double*>(f))));
}
inline Pair add(Pair a, Pair b) { return _mm_add_pd(a, b); }
inline Pair sub(Pair a, Pair b) { return _mm_sub_pd(a, b); }
inline Pair mul(Pair a, Pair b) { return _mm_mul_pd(a, b); }
inline Pair div(Pair a, Pair b) { return _mm_div_pd(a, b); }
inline Pair sqrt(Pair a) { return _mm_sqrt_pd(a); }
inline Pair clamp01(Pair a) { return _mm_min_pd(_mm_max_pd(a, _mm_setzero_pd()), _mm_set1_pd(1.0)); }
// All-ones lanes where a > b / a < b (false for NaN), and their conjunction.
inline Pair greater(Pair a, Pair b) { return _mm_cmpgt_pd(a, b); }
inline Pair less(Pair a, Pair b) { return _mm_cmplt_pd(a, b); }
inline Pair both(Pair a, Pair b) { return _mm_and_pd(a, b); }
// Lanes of `a` where `mask`, +infinity elsewhere.
inline Pair or_infinity(Pair mask, Pair a) {
  return _mm_or_pd(_mm_and_pd(mask, a),
                   _mm_andnot_pd(mask, _mm_set1_pd(std::numeric_limits<double>::infinity())));
}
inline double lane0(Pair a) { return _mm_cvtsd_f64(a); }
inline double lane1(Pair a) { return _mm_cvtsd_f64(_mm_unpackhi_pd(a, a)); }
#else
struct Pair {
  double v[2];
};
inline Pair splat(double v) { return {{v, v}}; }
inline Pair pair(double a, double b) { return {{a, b}}; }
inline Pair widen(const float* f) { return {{double(f[0]), double(f[1])}}; }
template <class Op>
inline Pair lanes(Pair a, Pair b, Op op) {
  return {{op(a.v[0], b.v[0]), op(a.v[1], b.v[1])}};
}
inline Pair add(Pair a, Pair b) {
  return lanes(a, b, [](double x, double y) { return x + y; });
}
inline Pair sub(Pair a, Pair b) {
  return lanes(a, b, [](double x, double y) { return x - y; });
}
inline Pair mul(Pair a, Pair b) {
  return lanes(a, b, [](double x, double y) { return x * y; });
}
inline Pair div(Pair a, Pair b) {
  return lanes(a, b, [](double x, double y) { return x / y; });
}
inline Pair sqrt(Pair a) { return {{std::sqrt(a.v[0]), std::sqrt(a.v[1])}}; }
inline Pair clamp01(Pair a) { return {{std::clamp(a.v[0], 0.0, 1.0), std::clamp(a.v[1], 0.0, 1.0)}}; }
// Masks are 1.0 / 0.0 lanes here.
inline Pair greater(Pair a, Pair b) {
  return lanes(a, b, [](double x, double y) { return x > y ? 1.0 : 0.0; });
}
inline Pair less(Pair a, Pair b) {
  return lanes(a, b, [](double x, double y) { return x < y ? 1.0 : 0.0; });
}
inline Pair both(Pair a, Pair b) {
  return lanes(a, b, [](double x, double y) { return x * y; });
}
inline Pair or_infinity(Pair mask, Pair a) {
  return lanes(mask, a,
               [](double m, double x) { return m != 0.0 ? x : std::numeric_limits<double>::infinity(); });
}
inline double lane0(Pair a) { return a.v[0]; }
inline double lane1(Pair a) { return a.v[1]; }
#endif

// Lowers `best` to the record's triangle updates of its target c, in slot order; a slot
// counts where its support is final and the update has an interior minimiser.
// Semi-Lagrangian: minimise u(p) + F |p - c| over p on the support segment x-y, F the mean
// density of the segment p-c, taken at the foot of the perpendicular first and again at
// that pass's minimiser (for rx == ry both passes find the same F). `rcx` is rho[c] + rho[x].
inline void triangle_updates(const Update& g, const double* u, const double* rho, const uint8_t* state,
                             Pair ux, Pair rx, Pair rcx, double& best) {
  const int y0 = g.other[0], y1 = g.other[1];
  const bool final0 = state[y0] == FastMarching::kFinal, final1 = state[y1] == FastMarching::kFinal;
  if (!final0 && !final1) return;
  const Pair delta = sub(pair(u[y0], u[y1]), ux);
  const Pair ryx = sub(pair(rho[y0], rho[y1]), rx);
  const Pair lambda0 = widen(g.lambda0), height = widen(g.height), inv_len2 = widen(g.inv_len2);
  const Pair half = splat(0.5), zero = splat(0.0), one = splat(1.0);
  const Pair delta2 = mul(mul(delta, delta), inv_len2);
  const Pair slope = mul(mul(delta, height), inv_len2);
  // Pass 1: F at the foot of the perpendicular (clamped to the segment).
  Pair F = mul(half, add(rcx, mul(clamp01(lambda0), ryx)));
  Pair q = sub(mul(F, F), delta2);
  Pair ok = greater(q, zero);
  Pair lambda = sub(lambda0, div(slope, sqrt(q)));
  ok = both(ok, both(greater(lambda, zero), less(lambda, one)));
  // Pass 2: F at the minimiser of pass 1.
  F = mul(half, add(rcx, mul(lambda, ryx)));
  q = sub(mul(F, F), delta2);
  ok = both(ok, greater(q, zero));
  const Pair root = sqrt(q);
  // lambda0 - slope / root in (0, 1), without the division (root > 0 where ok).
  ok = both(ok, both(less(slope, mul(lambda0, root)), greater(slope, mul(sub(lambda0, one), root))));
  const Pair value = or_infinity(ok, add(add(ux, mul(lambda0, delta)), mul(height, root)));
  if (final0) best = std::min(best, lane0(value));
  if (final1) best = std::min(best, lane1(value));
}

}  // namespace

FastMarching::FastMarching(const FastMarchingStencils& stencils)
    : stencils_(stencils), queue_(static_cast<size_t>(stencils.mesh().num_vertices())) {
  const int nv = stencils.mesh().num_vertices();
  // One more entry for the sentinel that unused update slots name: never final, never
  // reached; the march reads its density too (the value never matters).
  u_.assign(nv + 1, std::numeric_limits<double>::infinity());
  state_.assign(nv + 1, kOpen);
  rho_.assign(nv + 1, 0.0);
  order_.assign(nv, INT32_MAX);
  accepted_.assign(nv, 0);
  open_records_.assign(stencils.record_bits().begin(), stencils.record_bits().end());
  wide_corners_.reserve(16);
}

inline void FastMarching::push_or_decrease(int v, double value) {
  u_[v] = value;
  queue_.push(v, value);
  // v's records are read when it is accepted, mostly soon: start fetching them (on large
  // meshes the table is in L3 or memory). Four lines hold the six records of a typical
  // vertex; fetching the first only, the march on bimba took 1.25x longer.
  const char* records = reinterpret_cast<const char*>(stencils_.updates_begin(v));
  __builtin_prefetch(records);
  __builtin_prefetch(records + 64);
  __builtin_prefetch(records + 128);
  __builtin_prefetch(records + 192);
}

void FastMarching::reset() {
  // The vertices given a value are those made final and those still queued.
  const int nv = static_cast<int>(u_.size()) - 1;
  if (size_t(num_final_) * 4 > size_t(nv)) {
    std::fill(u_.begin(), u_.end(), std::numeric_limits<double>::infinity());
    std::fill(state_.begin(), state_.end(), kOpen);  // the sentinel included
    std::fill(order_.begin(), order_.end(), INT32_MAX);
    std::copy(stencils_.record_bits().begin(), stencils_.record_bits().end(), open_records_.begin());
    queue_.clear();
  } else {
    // Only accepted vertices clear record bits: give back what each cleared.
    for (int i = 0; i < num_final_; ++i) {
      const int x = accepted_[i];
      for (auto* in = stencils_.incoming_begin(x); in != stencils_.incoming_end(x); ++in) {
        open_records_[in->vertex] |= in->records;
      }
    }
    const auto forget = [this](int32_t v) {
      u_[v] = std::numeric_limits<double>::infinity();
      state_[v] = kOpen;
      order_[v] = INT32_MAX;
    };
    std::for_each(accepted_.begin(), accepted_.begin() + num_final_, forget);
    queue_.clear(forget);
  }
  num_final_ = 0;
}

void FastMarching::run(std::span<const double> density, int source, int stop_vertex) {
  const size_t nv = rho_.size() - 1;
  const size_t given = std::min(density.size(), nv);
  std::copy_n(density.begin(), given, rho_.begin());
  std::fill(rho_.begin() + given, rho_.begin() + nv, 0.0);
  march(rho_.data(), source, stop_vertex);
}

void FastMarching::run_log(std::span<const double> log_density, int source, int stop_vertex) {
  // All at once rather than per vertex reached: the vectorised exp costs less for the
  // whole mesh than std::exp for the part an early-stopped march reaches.
  const size_t nv = rho_.size() - 1;
  const size_t given = std::min(log_density.size(), nv);
  densities_from_logs(log_density.first(given), std::span<double>(rho_).first(given));
  std::fill(rho_.begin() + given, rho_.begin() + nv, 0.0);
  march(rho_.data(), source, stop_vertex);
}

void FastMarching::gather_wide_corners(int t) {
  // The back-trace leaves t down an edge to a lower neighbour or across a face whose
  // corner at t holds the descent direction. A face with a neighbour above t and one below
  // holds it only if its corner at t is wider than a right angle (the descent direction
  // points away from the one above); a face with both above never does (u rises into it).
  const Mesh& mesh = stencils_.mesh();
  wide_corners_.clear();
  for (const int* f = mesh.vertex_faces_begin(t); f != mesh.vertex_faces_end(t); ++f) {
    const auto& corners = mesh.face(*f);
    const int c = mesh.corner_of(*f, t);
    const int a = corners[(c + 1) % 3], b = corners[(c + 2) % 3];
    if ((mesh.position(a) - mesh.position(t)).dot(mesh.position(b) - mesh.position(t)) < 0.0) {
      wide_corners_.push_back({a, b});
    }
  }
}

// Makes x, the queue's front, final and updates its neighbours from it.
inline void FastMarching::accept(int x, const double* rho) {
  double* const u = u_.data();
  const uint8_t* const state = state_.data();
  queue_.pop(x);
  state_[x] = kFinal;
  accepted_[num_final_] = x;
  order_[x] = num_final_++;
  const double ux = u[x];
  const double rx = rho[x];

  const Pair vux = splat(ux), vrx = splat(rx);
  // Two passes over x's records: first every candidate value, then the pushes. The push
  // test is the branch the predictor misses most, and it waits on the longest chain (two
  // square roots and a division); taken in the first loop, each miss threw away the
  // records after it that were in flight. Pushing cannot change what the first pass reads:
  // it reads final supports only, and pushes touch vertices that are not final.
  constexpr int kChunk = 16;
  double best[kChunk];
  int32_t target[kChunk];
  // x is final now: its neighbours skip their records targeting it from here on.
  uint64_t* const open = open_records_.data();
  for (auto* in = stencils_.incoming_begin(x); in != stencils_.incoming_end(x); ++in) {
    open[in->vertex] &= ~in->records;
  }
  const Update* const first = stencils_.updates_begin(x);
  const Update* const end = stencils_.updates_end(x);
  const auto candidate = [&](const Update& g, int& n) {
    const int c = g.target;
    __builtin_prefetch(&u[c]);  // the push test reads it (a cache miss on large meshes)
    const double rc = rho[c];
    // Straight segment from x: length times the mean density at its ends.
    double b = ux + 0.5 * (rc + rx) * double(g.len);
    triangle_updates(g, u, rho, state, vux, vrx, splat(rc + rx), b);
    // Keep acceptance order monotone (Dijkstra invariant): nothing below what is final.
    best[n] = std::max(b, ux);
    target[n++] = c;
  };
  const auto push_all = [&](int n) {
    for (int i = 0; i < n; ++i) {
      if (best[i] < u[target[i]]) push_or_decrease(target[i], best[i]);
    }
  };
  // The masked records whose target is not final, a chunk at a time.
  for (uint64_t m = open[x]; m != 0;) {
    int n = 0;
    for (; m != 0 && n < kChunk; m &= m - 1) candidate(first[std::countr_zero(m)], n);
    push_all(n);
  }
  // Records past the masked ones (vertices of very high degree): each target tested.
  for (const Update* g = first + std::min<ptrdiff_t>(end - first, FastMarchingStencils::kMaskedRecords); g != end;) {
    const Update* const chunk_end = end - g > kChunk ? g + kChunk : end;
    int n = 0;
    for (; g != chunk_end; ++g) {
      if (state[g->target] != kFinal) candidate(*g, n);
    }
    push_all(n);
  }
}

void FastMarching::march(const double* density, int source, int stop_vertex) {
  reset();
  push_or_decrease(source, 0.0);
  int x = queue_.front();
  for (; x >= 0 && x != stop_vertex; x = queue_.front()) accept(x, density);
  if (x >= 0) {
    accept(x, density);
    // Go on until every vertex below the stop vertex is final: the queue is exact between
    // buckets, so once its front is in a later bucket than the stop vertex's, whatever is
    // still open lies above it. A face across a wide corner with one neighbour final and
    // the other open needs that one's final value too. (Marching on until the stop
    // vertex's whole ring was final went far into DE's walls of high density.)
    gather_wide_corners(stop_vertex);
    const uint64_t stop_bucket = BucketQueue::bucket_of(u_[stop_vertex]);
    const auto done = [&](int front) {
      return BucketQueue::bucket_of(u_[front]) > stop_bucket &&
             std::all_of(wide_corners_.begin(), wide_corners_.end(),
                         [&](const auto& ab) { return state_[ab[0]] == state_[ab[1]]; });
    };
    for (x = queue_.front(); x >= 0 && !done(x); x = queue_.front()) accept(x, density);
  }
  vertices_made_final_total.fetch_add(static_cast<uint64_t>(num_final_), std::memory_order_relaxed);
}

uint64_t FastMarching::vertices_made_final() {
  return vertices_made_final_total.load(std::memory_order_relaxed);
}

}  // namespace depath
