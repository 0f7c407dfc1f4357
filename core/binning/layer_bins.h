// Per-layer point bins of fixed capacity, all in caller memory.
//
// Points are stored in the raw scanner frame, so that a later, better
// levelling transform can re-assign them to layers without loss (see
// session/finish). A bin that fills up thins itself in place: it raises its
// level, and at level L it keeps only points whose hash has its top L bits
// zero, i.e. a deterministic half, quarter, ... of its points. Which points
// survive depends only on the points, not on their order, and a 10-million
// point scan uses the same memory as a 100-thousand point scan.
//
// A floor under the levels (floor_layers > 0): a bin never keeps points at
// a higher rate than the floor_layers-th densest bin's level. Without it a
// bin that few points reach (far strays above the rim, in layers of their
// own) keeps every one while the wall's bins halve again and again, so a
// scan ten times as long stored ten times the strays against the same wall
// and its rim-plane tops were all strays (a bowl +1.35 % with PV_OK). The
// floor rises only when floor_layers bins have filled at a higher level,
// a function of the points alone: still independent of their order.
//
// Raising a level by hashing every point of the bin again costs 7 % of the
// ingest's instructions. With ranks, the bin keeps one byte per
// slot beside the point, the number of leading zero bits of its hash (the
// highest level it passes), and a raise reads those instead. Without them
// (a configuration that stores few points, where every byte of the block
// counts: the MCU's) the raise hashes again. Both keep the same points in
// the same order.
//
// An index of what the bins hold (index = true at init; start_index() turns
// it on): a scan sent again as a whole, beyond the duplicate filter's
// window, must not be stored twice (the session's repeat mode,
// session/session.cpp). Each bin is sorted by the points' bits once, then
// keeps a sorted prefix and an unsorted tail of the points stored since;
// holds() is a binary search and a short scan. A tail longer than
// tail_max() is sorted on the stack and merged into the prefix (nothing is
// allocated: std::inplace_merge would). Thinning keeps the order, so the
// prefix stays sorted. Off, nothing of it runs.
#ifndef PV_BINNING_LAYER_BINS_H
#define PV_BINNING_LAYER_BINS_H

#include <cstddef>
#include <cstdint>

#include "common/geometry.h"

namespace pv::binning {

class LayerBins {
 public:
  // ranks: keep each slot's rank (one byte more per slot, see above).
  // index: room for the index of what the bins hold (see above).
  static size_t bytes_needed(uint32_t layers, uint32_t capacity, bool ranks = false,
                             bool index = false);
  // memory: bytes_needed() bytes (the same ranks and index), aligned for P3
  // and uint32_t. floor_layers: 0 for no floor (see above).
  void init(void *memory, uint32_t layers, uint32_t capacity, bool ranks = false,
            uint32_t floor_layers = 0, bool index = false);
  void clear();

  // Stores p in bin j (j < layers()). Returns false if the bin's level
  // rejects it (it was thinned away) — not an error.
  // The common case (the level passes, the bin has room) is inline: it is
  // on the ingest path of every point.
  bool insert(uint32_t j, const P3 &p, uint64_t hash) {
    if (!passes(hash, levels_[j])) {
      ++thinned_;
      return false;
    }
    uint32_t &c = counts_[j];
    if (c < capacity_) {
      const size_t slot = size_t(j) * capacity_ + c++;
      slots_[slot] = p;
      if (ranks_ != nullptr) ranks_[slot] = rank(hash);
      ++stored_;
      if (indexed_ && c - sorted()[j] > tail_max()) merge_tail(j);
      return true;
    }
    return insert_full(j, p, hash);
  }

  // Sorts every bin and keeps them so from now on (until clear()). False
  // without the index's memory (init's index).
  bool start_index();
  bool indexed() const { return indexed_; }
  // A full bin was offered a point it holds (insert_full()): the stream
  // repeats itself.
  bool copy_refused() const { return copy_refused_; }
  // A tail a 64th of a bin, 32 to kMaxTail points: a layer bin of 1024
  // merges every 32 new points, the floor store of 65,536 every 256 (256
  // moves a point, where nearly every point is a copy and few are new);
  // holds() scans at most that many. The merge sorts the tail on the stack.
  static constexpr uint32_t kMaxTail = 256;
  uint32_t tail_max() const {
    const uint32_t t = capacity_ / 64;
    if (t < 32) return 32;
    return t > kMaxTail ? kMaxTail : t;
  }
  // Bin j holds a point with p's bits (the index on: a binary search and
  // the tail; off: every point of the bin).
  bool holds(uint32_t j, const P3 &p) const;

  uint32_t layers() const { return layers_; }
  uint32_t capacity() const { return capacity_; }
  uint32_t count(uint32_t j) const { return counts_[j]; }
  uint8_t level(uint32_t j) const { return levels_[j]; }
  const P3 *points(uint32_t j) const { return slots_ + size_t(j) * capacity_; }
  uint64_t stored() const { return stored_; }
  uint64_t thinned() const { return thinned_; }  // dropped by bin levels
  uint8_t floor_level() const { return floor_; }

  // The top `level` bits of the hash are zero (level 0: every hash), as
  // one shift by 63 - level of hash >> 1: no branch on level 0.
  static bool passes(uint64_t hash, uint8_t level) {
    return ((hash >> 1) >> (63 - level)) == 0;
  }
  // The highest level a hash passes: its leading zero bits (64 for 0).
  // passes(hash, level) is rank(hash) >= level.
  static uint8_t rank(uint64_t hash) {
    return hash == 0 ? uint8_t(64) : uint8_t(__builtin_clzll(hash));
  }
  bool has_ranks() const { return ranks_ != nullptr; }

 private:
  bool insert_full(uint32_t j, const P3 &p, uint64_t hash);
  void raise_level(uint32_t j);
  void thin_to(uint32_t j, uint8_t level);
  void raise_floor();
  void sort_bin(uint32_t j);
  void merge_tail(uint32_t j);
  P3 *slots_ = nullptr;
  uint32_t *counts_ = nullptr;
  uint8_t *levels_ = nullptr;
  uint8_t *ranks_ = nullptr;  // per slot, or null
  uint32_t layers_ = 0;
  uint32_t capacity_ = 0;
  uint64_t stored_ = 0;
  uint64_t thinned_ = 0;
  uint32_t floor_layers_ = 0;
  uint8_t floor_ = 0;
  bool has_index_ = false;  // init's index: sorted() is carved
  bool indexed_ = false;
  bool copy_refused_ = false;  // insert_full() refused a point the bin held
  // Per bin, the sorted prefix's length: carved after the counts (no
  // pointer of its own: the MCU profile's session header is at its limit).
  uint32_t *sorted() const { return counts_ + layers_; }
};

}  // namespace pv::binning

#endif
