// SPDX-License-Identifier: MIT
#include "depath/decode/bucket_queue.hpp"

#include <algorithm>
#include <numeric>

namespace depath {

BucketQueue::BucketQueue(std::size_t num_vertices)
    : num_vertices_(static_cast<int32_t>(num_vertices)),
      next_(num_vertices + kBuckets + kBinades),
      prev_(num_vertices + kBuckets + kBinades),
      bits_(kBuckets / 64, 0),
      words_in_use_((kBuckets / 64 + 63) / 64, 0),  // rounded up: a ring under 4,096 slots has one
      waiting_bucket_(num_vertices, 0),
      waiting_bits_(kBinadeWords, 0) {
  std::iota(next_.begin(), next_.end(), 0);
  std::iota(prev_.begin(), prev_.end(), 0);
}

void BucketQueue::defer(int32_t vertex, uint64_t bucket) {
  const uint64_t binade = binade_of(bucket);  // >= the ring's first binade + kRingBinades
  waiting_bucket_[vertex] = static_cast<uint32_t>(bucket);  // 11 exponent + kMantissaBits mantissa bits
  // Last in its binade's list.
  const int32_t head = waiting_head(binade), last = prev_[head];
  next_[vertex] = head;
  prev_[vertex] = last;
  next_[last] = vertex;
  prev_[head] = vertex;
  waiting_bits_[binade >> 6] |= uint64_t{1} << (binade & 63);
  // Due once the front's binade is within kRingBinades - 1 below it.
  take_in_from_ = std::min(take_in_from_, (binade - (kRingBinades - 1)) << kMantissaBits);
}

int32_t BucketQueue::next_word_in_use(uint32_t w) {
  for (uint32_t k = w >> 6; k < words_in_use_.size(); ++k) {
    uint64_t m = words_in_use_[k] & (k == w >> 6 ? ~uint64_t{0} << (w & 63) : ~uint64_t{0});
    for (; m != 0; m &= m - 1) {
      const uint32_t word = k * 64 + std::countr_zero(m);
      if (bits_[word] != 0) return static_cast<int32_t>(word);
      words_in_use_[k] &= ~(uint64_t{1} << (word & 63));  // emptied by front()
    }
  }
  return -1;
}

bool BucketQueue::advance() {
  constexpr uint32_t words = kBuckets / 64;
  for (;;) {
    // The next bucket in use around the ring from the current one.
    const uint32_t from = static_cast<uint32_t>(current_) & kMask;
    uint32_t w = from >> 6;
    uint64_t m = bits_[w] & (~uint64_t{0} << (from & 63));
    if (m == 0) {
      int32_t next = w + 1 < words ? next_word_in_use(w + 1) : -1;
      if (next < 0) next = next_word_in_use(0);  // round the ring (at most back to w)
      if (next >= 0) {
        w = static_cast<uint32_t>(next);
        m = bits_[w];
      }
    }
    if (m != 0) {
      current_ += ((w * 64 + std::countr_zero(m)) - from) & kMask;
    } else if (take_in_from_ != kNever) {
      // The ring is empty: move it to the first binade that has waiting vertices.
      current_ = (binade_of(take_in_from_) + (kRingBinades - 1)) << kMantissaBits;
    } else {
      return false;
    }
    if (current_ < take_in_from_) return true;
    // A waiting binade is within the ring now: link it, then look again.
    take_in_overflow();
  }
}

// Out of line, so that advance(), called about once per vertex, saves few registers.
void BucketQueue::take_in_overflow() {
  const uint64_t end = binade_of(current_) + kRingBinades;  // binades the ring holds end here
  uint64_t binade = binade_of(take_in_from_) + (kRingBinades - 1);
  take_in_from_ = kNever;
  for (uint32_t w = static_cast<uint32_t>(binade >> 6); w < kBinadeWords; ++w) {
    for (uint64_t m = waiting_bits_[w]; m != 0; m &= m - 1) {
      binade = w * 64 + std::countr_zero(m);
      if (binade >= end) {
        take_in_from_ = (binade - (kRingBinades - 1)) << kMantissaBits;
        return;
      }
      const int32_t head = waiting_head(binade);
      for (int32_t v = next_[head]; v != head;) {
        const int32_t after = next_[v];
        link(v, waiting_bucket_[v]);
        v = after;
      }
      next_[head] = prev_[head] = head;
      waiting_bits_[w] &= ~(uint64_t{1} << (binade & 63));
    }
  }
}

}  // namespace depath
