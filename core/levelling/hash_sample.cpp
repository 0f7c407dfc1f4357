#include "levelling/hash_sample.h"

#include <algorithm>
#include <cstring>

namespace pv::levelling {

// Total order: hash first, then the coordinate bits, so equal hashes of
// different points (astronomically rare) still sort the same way every time.
static bool entry_less(const SampleEntry &a, const SampleEntry &b) {
  if (a.hash != b.hash) return a.hash < b.hash;
  // The bits, not the values: -0 and +0 (and NaN payloads) must order too.
  return std::memcmp(&a.p, &b.p, sizeof a.p) < 0;  // NOLINT(bugprone-suspicious-memory-comparison)
}

void HashSample::init(SampleEntry *storage, uint32_t capacity) {
  heap_ = storage;
  capacity_ = capacity;
  clear();
}

void HashSample::offer_slow(const P3 &p, uint64_t hash) {
  const SampleEntry e{hash, p};
  if (size_ < capacity_) {
    heap_[size_] = e;
    sift_up(size_++);
    if (size_ == capacity_) reject_above_ = heap_[0].hash;
    return;
  }
  if (capacity_ == 0 || !entry_less(e, heap_[0])) return;
  // An exact duplicate of the largest entry would compare equal: skipped
  // above. Duplicates of smaller entries may enter; the set stays a
  // function of the multiset of points pushed.
  heap_[0] = e;
  sift_down(0);
  reject_above_ = heap_[0].hash;
}

// Both sifts move a hole instead of swapping (one copy per level, not
// three) and compare the hashes inline, the bits only on a tie: the same
// heap as swapping with entry_less, in a third of the copies (entries into
// the sample cost 8 % of the ingest's instructions at 400k points with
// swaps).
inline bool less_inline(const SampleEntry &a, const SampleEntry &b) {
  return a.hash != b.hash ? a.hash < b.hash : entry_less(a, b);
}

void HashSample::sift_up(uint32_t i) {
  const SampleEntry e = heap_[i];
  while (i > 0) {
    const uint32_t parent = (i - 1) / 2;
    if (!less_inline(heap_[parent], e)) break;
    heap_[i] = heap_[parent];
    i = parent;
  }
  heap_[i] = e;
}

void HashSample::sift_down(uint32_t i) {
  const SampleEntry e = heap_[i];
  for (;;) {
    const uint32_t l = 2 * i + 1, r = l + 1;
    if (l >= size_) break;
    // The larger child (the left one on a tie, as before).
    const uint32_t c = r < size_ && less_inline(heap_[l], heap_[r]) ? r : l;
    if (!less_inline(e, heap_[c])) break;
    heap_[i] = heap_[c];
    i = c;
  }
  heap_[i] = e;
}

void HashSample::canonical(SampleEntry *out) const {
  std::copy(heap_, heap_ + size_, out);
  std::sort(out, out + size_, entry_less);
}

}  // namespace pv::levelling
