// An order-independent sample of the stream for levelling.
//
// Keeps the k points with the smallest point_hash (a bottom-k sketch). The
// kept set depends only on the set of points pushed, never on their order or
// batching, so the plane fitted on it is the same for a shuffled scan. The
// heap order inside depends on arrival order; canonical() sorts it.
//
// With a membership set (init's set_slots) the k points are distinct: a
// point already kept is not offered again. Without it, copies of a kept
// point enter beside it, so a scan sent five times over keeps a fifth of
// its sample's points distinct, and the plane fitted on so few can tilt
// (a rounded bowl levelled 3.8 deg off and read +9.8 %, its single copy
// -0.4 %). The set holds the kept hashes only (the sample's 64-bit
// hashes: two distinct points share one with probability 2^-64 a pair,
// and then the later is taken for the earlier).
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
  // The membership set's slots for a sample of capacity points: a power of
  // two, at least twice the capacity (linear probing at most half full).
  static uint32_t set_slots_for(uint32_t capacity);
  // storage: caller memory for capacity entries. set: set_slots_for(capacity)
  // words for the membership set, or nullptr for none (copies may enter).
  void init(SampleEntry *storage, uint32_t capacity, uint64_t *set = nullptr);
  void clear();
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
  // A point the sample holds already was offered again (with the
  // membership set): the stream repeats itself beyond the duplicate
  // filter's window.
  bool repeated() const { return repeated_; }

 private:
  void offer_slow(const P3 &p, uint64_t hash);
  void sift_down(uint32_t i);
  void sift_up(uint32_t i);
  // The set: open addressing on the hash's low bits, 0 an empty slot (a
  // hash of 0 is kept as 1).
  static uint64_t set_key(uint64_t hash) { return hash != 0 ? hash : 1; }
  bool set_contains(uint64_t key) const;
  void set_insert(uint64_t key);
  void set_erase(uint64_t key);
  SampleEntry *heap_ = nullptr;  // max-heap on hash
  uint64_t *set_ = nullptr;
  uint32_t set_mask_ = 0;        // slots - 1
  bool repeated_ = false;
  // The largest kept hash once the sample is full, else the largest hash
  // (nothing rejected): the inline test is one compare with no loads of the
  // heap.
  uint64_t reject_above_ = ~uint64_t(0);
  uint32_t capacity_ = 0;
  uint32_t size_ = 0;
};

}  // namespace pv::levelling

#endif
