// An order-independent sample of the stream for levelling.
//
// Keeps the k points with the smallest point_hash (a bottom-k sketch). The
// kept set depends only on the set of points pushed, never on their order or
// batching, so the plane fitted on it is the same for a shuffled scan. The
// heap order inside depends on arrival order; canonical() sorts it.
#ifndef PV_LEVELLING_HASH_SAMPLE_H
#define PV_LEVELLING_HASH_SAMPLE_H

#include <cstddef>
#include <cstdint>

#include "common/geometry.h"

namespace pv::levelling {

struct SampleEntry {
  uint64_t hash;
  P3 p;
};

class HashSample {
 public:
  // storage: caller memory for capacity entries.
  void init(SampleEntry *storage, uint32_t capacity);
  void clear() {
    size_ = 0;
    reject_above_ = ~uint64_t(0);
  }
  // O(1) when the point is rejected (the common case once the sample is
  // full), O(log k) when it enters. The rejection, a hash above the largest
  // kept one, is inline: one compare per pushed point.
  void offer(const P3 &p, uint64_t hash) {
    if (hash > reject_above_) return;
    offer_slow(p, hash);
  }
  uint32_t size() const { return size_; }
  // Copies the sample into out (capacity() entries) sorted by (hash, bits).
  void canonical(SampleEntry *out) const;
  uint32_t capacity() const { return capacity_; }

 private:
  void offer_slow(const P3 &p, uint64_t hash);
  void sift_down(uint32_t i);
  void sift_up(uint32_t i);
  SampleEntry *heap_ = nullptr;  // max-heap on hash
  // The largest kept hash once the sample is full, else the largest hash
  // (nothing rejected): the inline test is one compare with no loads of the
  // heap.
  uint64_t reject_above_ = ~uint64_t(0);
  uint32_t capacity_ = 0;
  uint32_t size_ = 0;
};

}  // namespace pv::levelling

#endif
