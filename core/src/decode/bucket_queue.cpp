// SPDX-License-Identifier: MIT
#include "depath/decode/bucket_queue.hpp"

#include <algorithm>
#include <functional>
#include <numeric>

namespace depath {

BucketQueue::BucketQueue(std::size_t num_vertices)
    : num_vertices_(static_cast<int32_t>(num_vertices)),
      next_(num_vertices + kBuckets),
      prev_(num_vertices + kBuckets),
      bits_(kBuckets / 64, 0),
      deferred_(num_vertices, -1) {
  std::iota(next_.begin(), next_.end(), 0);
  std::iota(prev_.begin(), prev_.end(), 0);
}

// The overflow is a min-heap on the bucket (then push order, so that entries of one bucket
// are linked in the order they were pushed, as if they had been in the ring all along).
void BucketQueue::defer(int32_t vertex, uint64_t bucket) {
  next_[vertex] = prev_[vertex] = vertex;
  deferred_[vertex] = next_serial_;
  overflow_.push_back({bucket, next_serial_++, vertex});
  std::push_heap(overflow_.begin(), overflow_.end(), std::greater<>());
}

bool BucketQueue::advance() {
  constexpr uint32_t words = kBuckets / 64;
  for (;;) {
    // The next bucket in use around the ring from the current one.
    const uint32_t from = static_cast<uint32_t>(current_) & kMask;
    uint32_t w = from >> 6;
    uint64_t m = bits_[w] & (~uint64_t{0} << (from & 63));
    for (uint32_t k = 0; m == 0 && k < words; ++k) {
      w = (w + 1) % words;
      m = bits_[w];
    }
    if (m != 0) {
      current_ += ((w * 64 + std::countr_zero(m)) - from) & kMask;
    } else if (!overflow_.empty()) {
      current_ = overflow_.front().bucket;  // the ring is empty: move it to the overflow
    } else {
      return false;
    }
    if (overflow_.empty() || overflow_.front().bucket >= current_ + kBuckets) return true;
    // Part of the overflow fits the ring now: link it, then look again.
    take_in_overflow();
  }
}

// Out of line, so that advance(), called about once per vertex, saves few registers.
void BucketQueue::take_in_overflow() {
  while (!overflow_.empty() && overflow_.front().bucket < current_ + kBuckets) {
    const auto [bucket, serial, v] = overflow_.front();
    std::pop_heap(overflow_.begin(), overflow_.end(), std::greater<>());
    overflow_.pop_back();
    // Stale if deferred again since, popped (deferred_ moved on) or lowered into the ring.
    if (deferred_[v] != serial || next_[v] != v) continue;
    deferred_[v] = -1;
    link(v, bucket);
  }
}

}  // namespace depath
