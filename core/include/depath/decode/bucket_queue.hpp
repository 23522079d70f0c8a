// SPDX-License-Identifier: MIT
// The fast march's priority queue: an "untidy" monotone bucket queue of vertices, with
// buckets of relative width and decrease-key.
//
// Inputs: pushes of (vertex, key), vertex in [0, num_vertices), key >= 0 and never below
// the key last popped (fast marching's monotonicity). Outputs: the vertices in order of
// their keys, up to a relative 2^-8: within one bucket (keys with the same top 8 mantissa
// bits) the last pushed comes first. Guarantees: a vertex is queued at most once (pushing
// a queued vertex moves it to its new key's bucket); O(1) per push and per pop amortised;
// no allocation per run. The queue keeps no keys: the caller keeps the current values.
//
// Why: a 4-ary heap spent a third of the march in sifting, most of it in compares the
// branch predictor cannot learn (DE's densities are random). A bucket's width is 3.9e-3 of
// its keys, below the march's own first-order error (0.5-1.7% on the sphere and cylinder of
// the tests), so accepting keys that close in push order instead of key order changes a
// value by at most that much (measured against buckets of 2^-12 on random densities: 89-94%
// of kitten's and dragon's values the same bits, 99% within 7.4e-4, all within 2.0e-3; the
// tests' fmm errors and the 84 exact geodesic pairs' fmm paths unchanged). Buckets of 2^-8
// keep the ring's heads in 8 KB, within the L1 cache; at 2^-12 (128 KB) a sparse front
// missed it at each push and pop, and decodes and DE runs were 1.04-1.18x slower. Each bucket is a doubly
// linked list threaded through the vertices, so a lowered key moves its vertex instead of
// leaving a stale entry behind that the front would have to test and drop (on bimba that
// made the march 1.08x faster: fewer lines touched, one unpredictable branch fewer).
// Reference: L. Yatziv, A. Bartesaghi, G. Sapiro, "O(N) implementation of the fast marching
// algorithm", J. Comput. Phys. 212 (2006) — the untidy priority queue (there with buckets of
// fixed width; keyed by the bits of a double here, so one queue suits densities that span
// many orders of magnitude). Keys beyond the ring's four binades wait in one unsorted list
// per binade, linked in push order when their binade reaches the ring: no heap anywhere.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace depath {

class BucketQueue {
 public:
  /// An empty queue for vertices 0 .. num_vertices - 1.
  explicit BucketQueue(std::size_t num_vertices);

  /// Empties the queue, calling visit(vertex) once for each vertex still queued. Cost: the
  /// vertices still queued.
  template <class Visit>
  void clear(Visit visit) {
    const auto empty_list = [&](int32_t head) {
      for (int32_t v = next_[head]; v != head;) {
        const int32_t after = next_[v];
        visit(v);
        next_[v] = prev_[v] = v;
        v = after;
      }
      next_[head] = prev_[head] = head;
    };
    for (size_t w = 0; w < bits_.size(); ++w) {
      for (uint64_t m = bits_[w]; m != 0; m &= m - 1) {
        empty_list(head_node(static_cast<uint32_t>(w * 64 + std::countr_zero(m))));
      }
      bits_[w] = 0;
    }
    std::fill(words_in_use_.begin(), words_in_use_.end(), 0);
    for (uint32_t w = 0; w < kBinadeWords; ++w) {
      for (uint64_t m = waiting_bits_[w]; m != 0; m &= m - 1) {
        empty_list(waiting_head(w * 64 + std::countr_zero(m)));
      }
      waiting_bits_[w] = 0;
    }
    take_in_from_ = kNever;
    current_ = 0;
  }
  void clear() {
    clear([](int32_t) {});
  }

  /// Queues `vertex` with `key` >= the key last popped (a lower one is taken as that key),
  /// or moves it there if it is queued already.
  void push(int32_t vertex, double key) {
    unlink(vertex);  // a vertex in no list links to itself: no effect
    uint64_t b = bucket_of(key);
    b = b < current_ ? current_ : b;
    if (binade_of(b) >= binade_of(current_) + kRingBinades) [[unlikely]] {
      defer(vertex, b);
      return;
    }
    link(vertex, b);
  }

  /// The vertex at the front, -1 when the queue is empty. Stays the front until popped or
  /// a push.
  int32_t front() {
    for (;;) {
      const uint32_t slot = static_cast<uint32_t>(current_) & kMask;
      const int32_t head = head_node(slot);
      const int32_t v = next_[head];
      if (v != head) return v;
      bits_[slot >> 6] &= ~(uint64_t{1} << (slot & 63));
      if (!advance()) return -1;
    }
  }
  /// Removes `vertex` = front().
  void pop(int32_t vertex) {
    unlink(vertex);
    next_[vertex] = prev_[vertex] = vertex;
  }

  /// Keys in one bucket share their top kMantissaBits mantissa bits: they are less than
  /// this (relative) apart, and may come out in any order.
  static constexpr int kMantissaBits = 8;
  static constexpr double kRelativeWidth = 1.0 / (1 << kMantissaBits);
  /// The bucket of a key (non-negative). Buckets come out in order: once the front is in a
  /// later bucket than key k's, every vertex still queued has a key above k.
  static uint64_t bucket_of(double key) { return std::bit_cast<uint64_t>(key) >> (52 - kMantissaBits); }

 private:
  // A bucket is a key's bits without its low 52 - kMantissaBits mantissa bits (non-negative
  // doubles order as their bit patterns), a binade 2^kMantissaBits consecutive buckets. The
  // ring holds the binade of the front and the three above it (a bucket's slot is its low
  // kMantissaBits + 2 bits); keys in later binades wait in overflow lists, one per binade.
  // Four binades rather than two: on the 41x41 grid's DE trials a tenth of the pops went
  // through the overflow (then a heap), and the march was 1.07x slower.
  static constexpr uint32_t kRingBinades = 4;
  static constexpr uint32_t kBuckets = kRingBinades << kMantissaBits;
  static constexpr uint32_t kMask = kBuckets - 1;
  static constexpr uint32_t kBinades = 1u << 11;  // the exponents of a double
  static constexpr uint32_t kBinadeWords = kBinades / 64;
  static constexpr uint64_t kNever = ~uint64_t{0};
  static uint64_t binade_of(uint64_t bucket) { return bucket >> kMantissaBits; }

  // The list nodes: one per vertex, then one head per slot of the ring, then one per binade
  // for the keys waiting beyond the ring (each list is circular through its head; an empty
  // list's head and a vertex in no list link to themselves).
  int32_t head_node(uint32_t slot) const { return num_vertices_ + static_cast<int32_t>(slot); }
  int32_t waiting_head(uint64_t binade) const {
    return num_vertices_ + static_cast<int32_t>(kBuckets + binade);
  }
  void unlink(int32_t node) {
    const int32_t p = prev_[node], n = next_[node];
    next_[p] = n;
    prev_[n] = p;
  }
  // Inserts `vertex` first in bucket `b` of the ring.
  void link(int32_t vertex, uint64_t b) {
    const uint32_t slot = static_cast<uint32_t>(b) & kMask;
    const int32_t head = head_node(slot), first = next_[head];
    next_[vertex] = first;
    prev_[vertex] = head;
    prev_[first] = vertex;
    next_[head] = vertex;
    bits_[slot >> 6] |= uint64_t{1} << (slot & 63);
    words_in_use_[slot >> 12] |= uint64_t{1} << ((slot >> 6) & 63);
  }
  void defer(int32_t vertex, uint64_t bucket);
  /// Moves current_ to the next bucket in use (taking in the overflow that now fits);
  /// false when nothing is left.
  bool advance();
  /// The first word of bits_ at or after `w` (no wrap) that is non-zero, or -1.
  int32_t next_word_in_use(uint32_t w);
  /// Links the waiting vertices whose binades now fall within the ring.
  [[gnu::noinline]] void take_in_overflow();

  int32_t num_vertices_;
  // List nodes: vertices, then the ring's heads, then the waiting lists' heads.
  std::vector<int32_t> next_, prev_;
  std::vector<uint64_t> bits_;  // slots of the ring that may hold vertices
  // Words of bits_ that may be non-zero: when DE's densities spread the keys over many
  // binades, the ring is sparse and advance() would otherwise read hundreds of empty words.
  std::vector<uint64_t> words_in_use_;
  uint64_t current_ = 0;  // the bucket at the front
  // Keys in binades past the ring's wait in their binade's list, in push order (a vertex
  // pushed again leaves its place and goes last), with their bucket in waiting_bucket_:
  // linked into the ring in that order, each first in its bucket, a bucket's vertices come
  // out last pushed first, as if they had been in the ring all along. Late in a DE run half
  // of the pushes wait here (the evolved densities span many binades): as lists threaded
  // through the vertices, a lowered key moves its vertex, where a vector per binade kept a
  // stale entry for every earlier push to skip when its binade came in.
  std::vector<uint32_t> waiting_bucket_;  // per vertex, while it waits
  std::vector<uint64_t> waiting_bits_;    // binades whose list is not empty
  uint64_t take_in_from_ = kNever;        // the first bucket whose binade brings a list into the ring
};

}  // namespace depath
