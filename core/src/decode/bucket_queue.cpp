// SPDX-License-Identifier: MIT
#include "depath/decode/bucket_queue.hpp"

#include <algorithm>
#include <functional>

namespace depath {

BucketQueue::BucketQueue(std::size_t capacity)
    : entries_(capacity), head_(kBuckets, -1), bits_(kBuckets / 64, 0) {}

void BucketQueue::clear() {
  for (size_t w = 0; w < bits_.size(); ++w) {
    for (uint64_t m = bits_[w]; m != 0; m &= m - 1) head_[w * 64 + std::countr_zero(m)] = -1;
    bits_[w] = 0;
  }
  num_entries_ = 0;
  current_ = 0;
  overflow_.clear();
}

// The overflow is a min-heap on the bucket: each entry leaves it once, when the ring
// reaches its bucket (keys more than two binades above the front are few).
void BucketQueue::defer(int32_t e, uint64_t bucket) {
  overflow_.push_back({bucket, e});
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
      current_ = overflow_.front().first;  // the ring is empty: move it to the overflow
    } else {
      return false;
    }
    if (overflow_.empty() || overflow_.front().first >= current_ + kBuckets) return true;
    // Part of the overflow fits the ring now: bucket it, then look again.
    take_in_overflow();
  }
}

// Out of line, so that advance(), called about once per vertex, saves few registers.
void BucketQueue::take_in_overflow() {
  while (!overflow_.empty() && overflow_.front().first < current_ + kBuckets) {
    const auto [bucket, e] = overflow_.front();
    std::pop_heap(overflow_.begin(), overflow_.end(), std::greater<>());
    overflow_.pop_back();
    insert(e, bucket);
  }
}

}  // namespace depath
