// SPDX-License-Identifier: MIT
// The fast march's priority queue: an "untidy" monotone bucket queue with buckets of
// relative width.
//
// Inputs: (vertex, key) pushes with keys >= 0 that never fall below the key last popped
// (fast marching's monotonicity). Outputs: the vertices in order of their keys, up to a
// relative 2^-12: within one bucket (keys k with the same top 12 mantissa bits) the last
// pushed comes first. Guarantees: O(1) per push and per pop amortised, no allocation per
// run once grown; no decrease-key: a vertex whose key falls is pushed again, and its older
// entries, which lie in its bucket or later ones, come to the front only after the newer
// one, when the caller refuses them (the vertex is final by then). Entries hold no key, so
// the caller keeps the current values.
//
// Why: a 4-ary heap spent a third of the march in sifting, most of it in compares the
// branch predictor cannot learn (DE's densities are random). A bucket's width is 2.4e-4 of
// its keys, far below the march's own first-order error (~1e-2), so accepting keys that
// close in push order instead of key order changes a value by at most that much (measured:
// the sum of 64 DE agents' target values moved by 3e-7 relative).
// Reference: L. Yatziv, A. Bartesaghi, G. Sapiro, "O(N) implementation of the fast marching
// algorithm", J. Comput. Phys. 212 (2006) — the untidy priority queue (there with buckets of
// fixed width; keyed by the bits of a double here, so one queue suits densities that span
// many orders of magnitude).
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace depath {

class BucketQueue {
 public:
  /// Room for `capacity` pushes between two clear() calls before it grows.
  explicit BucketQueue(std::size_t capacity);

  /// Empties the queue (cost: the buckets still in use).
  void clear();

  /// Adds `vertex` with `key` >= the key last popped (a lower one is taken as that key).
  void push(int32_t vertex, double key) {
    if (static_cast<std::size_t>(num_entries_) == entries_.size()) [[unlikely]]
      entries_.resize(2 * entries_.size() + 64);
    const int32_t e = num_entries_++;
    entries_[e].vertex = vertex;
    insert(e, bucket_of(key));
  }

  /// The front entry whose vertex `is_live(vertex)` accepts, dropping those it refuses
  /// (for a fast march: final vertices); -1 when the queue is empty. Stays the front until
  /// popped or a push.
  template <class IsLive>
  int32_t front(IsLive is_live) {
    for (;;) {
      const uint32_t b = static_cast<uint32_t>(current_) & kMask;
      const int32_t e = head_[b];
      if (e < 0) {
        bits_[b >> 6] &= ~(uint64_t{1} << (b & 63));
        if (!advance()) return -1;
        continue;
      }
      if (is_live(entries_[e].vertex)) return e;
      head_[b] = entries_[e].next;
    }
  }
  /// Removes entry `e` = front(...) and returns its vertex.
  int32_t pop(int32_t e) {
    head_[static_cast<uint32_t>(current_) & kMask] = entries_[e].next;
    return entries_[e].vertex;
  }

 private:
  struct Entry {
    int32_t vertex;
    int32_t next;  // next entry of the same bucket, -1 at its end
  };
  // A bucket is a key's bits without its low 52 - 12 mantissa bits (non-negative doubles
  // order as their bit patterns); kBuckets consecutive buckets (two binades) are held in a
  // ring, later keys wait in overflow_.
  static constexpr int kMantissaBits = 12;
  static constexpr uint32_t kBuckets = 1u << 13;
  static constexpr uint32_t kMask = kBuckets - 1;
  static uint64_t bucket_of(double key) { return std::bit_cast<uint64_t>(key) >> (52 - kMantissaBits); }

  void insert(int32_t e, uint64_t b) {
    b = b < current_ ? current_ : b;
    if (b >= current_ + kBuckets) [[unlikely]] {
      defer(e, b);
      return;
    }
    const uint32_t slot = static_cast<uint32_t>(b) & kMask;
    entries_[e].next = head_[slot];
    head_[slot] = e;
    bits_[slot >> 6] |= uint64_t{1} << (slot & 63);
  }
  void defer(int32_t e, uint64_t bucket);
  /// Moves current_ to the next bucket in use (taking in the overflow that now fits);
  /// false when nothing is left.
  bool advance();
  /// Buckets the overflow entries that now fall within the ring.
  [[gnu::noinline]] void take_in_overflow();

  std::vector<Entry> entries_;
  int32_t num_entries_ = 0;
  std::vector<int32_t> head_;   // first entry of each bucket of the ring, -1 when empty
  std::vector<uint64_t> bits_;  // buckets of the ring that may hold entries
  uint64_t current_ = 0;        // the bucket at the front
  std::vector<std::pair<uint64_t, int32_t>> overflow_;  // (bucket, entry), a min-heap
};

}  // namespace depath
