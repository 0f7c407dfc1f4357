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

uint32_t HashSample::set_slots_for(uint32_t capacity) {
  uint32_t slots = 1;
  while (slots < 2 * uint64_t(capacity)) slots <<= 1;
  return slots;
}

void HashSample::init(SampleEntry *storage, uint32_t capacity, uint64_t *set) {
  heap_ = storage;
  capacity_ = capacity;
  set_ = set;
  set_mask_ = set != nullptr ? set_slots_for(capacity) - 1 : 0;
  clear();
}

void HashSample::clear() {
  size_ = 0;
  repeated_ = false;
  reject_above_ = ~uint64_t(0);
  if (set_ != nullptr) std::fill(set_, set_ + set_mask_ + 1, uint64_t(0));
}

bool HashSample::set_contains(uint64_t key) const {
  for (uint32_t i = uint32_t(key) & set_mask_;; i = (i + 1) & set_mask_) {
    if (set_[i] == key) return true;
    if (set_[i] == 0) return false;
  }
}

void HashSample::set_insert(uint64_t key) {
  uint32_t i = uint32_t(key) & set_mask_;
  while (set_[i] != 0) i = (i + 1) & set_mask_;
  set_[i] = key;
}

// Backward-shift deletion: the keys after the hole that may move into it
// (their home slot is not between the hole and them) move back, so every
// key stays reachable from its home without tombstones.
void HashSample::set_erase(uint64_t key) {
  uint32_t hole = uint32_t(key) & set_mask_;
  while (set_[hole] != key) hole = (hole + 1) & set_mask_;
  for (uint32_t j = (hole + 1) & set_mask_; set_[j] != 0; j = (j + 1) & set_mask_) {
    const uint32_t home = uint32_t(set_[j]) & set_mask_;
    if (((j - home) & set_mask_) >= ((j - hole) & set_mask_)) {
      set_[hole] = set_[j];
      hole = j;
    }
  }
  set_[hole] = 0;
}

void HashSample::offer_slow(const P3 &p, uint64_t hash) {
  const SampleEntry e{hash, p};
  if (set_ != nullptr && set_contains(set_key(hash))) {  // kept already
    repeated_ = true;
    return;
  }
  if (size_ < capacity_) {
    heap_[size_] = e;
    sift_up(size_++);
    if (set_ != nullptr) set_insert(set_key(hash));
    if (size_ == capacity_) reject_above_ = heap_[0].hash;
    return;
  }
  if (capacity_ == 0 || !entry_less(e, heap_[0])) return;
  // Without the set, an exact duplicate of the largest entry compares
  // equal (skipped above) but duplicates of smaller entries enter; the
  // sample stays a function of the multiset of points pushed.
  if (set_ != nullptr) {
    set_erase(set_key(heap_[0].hash));
    set_insert(set_key(hash));
  }
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
