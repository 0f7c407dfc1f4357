// Per-layer point bins of fixed capacity, all in caller memory.
//
// Points are stored in the raw scanner frame, so that a later, better
// levelling transform can re-assign them to layers without loss (see
// session/finish). A bin that fills up thins itself in place: it raises its
// level, and at level L it keeps only points whose hash has its top L bits
// zero, i.e. a deterministic half, quarter, ... of its points. Which points
// survive depends only on the points, not on their order, and a 10-million
// point scan uses the same memory as a 100-thousand point scan.
#ifndef PV_BINNING_LAYER_BINS_H
#define PV_BINNING_LAYER_BINS_H

#include <cstddef>
#include <cstdint>

#include "common/geometry.h"

namespace pv::binning {

class LayerBins {
 public:
  static size_t bytes_needed(uint32_t layers, uint32_t capacity);
  // memory: bytes_needed() bytes, aligned for P3 and uint32_t.
  void init(void *memory, uint32_t layers, uint32_t capacity);
  void clear();

  // Stores p in bin j (j < layers()). Returns false if the bin's level
  // rejects it (it was thinned away) — not an error.
  // The common case (the level passes, the bin has room) is inline: it is
  // on the ingest path of every point (issue 12).
  bool insert(uint32_t j, const P3 &p, uint64_t hash) {
    if (!passes(hash, levels_[j])) {
      ++thinned_;
      return false;
    }
    uint32_t &c = counts_[j];
    if (c < capacity_) {
      slots_[size_t(j) * capacity_ + c++] = p;
      ++stored_;
      return true;
    }
    return insert_full(j, p, hash);
  }

  uint32_t layers() const { return layers_; }
  uint32_t capacity() const { return capacity_; }
  uint32_t count(uint32_t j) const { return counts_[j]; }
  uint8_t level(uint32_t j) const { return levels_[j]; }
  const P3 *points(uint32_t j) const { return slots_ + size_t(j) * capacity_; }
  uint64_t stored() const { return stored_; }
  uint64_t thinned() const { return thinned_; }  // dropped by bin levels

  static bool passes(uint64_t hash, uint8_t level) {
    return level == 0 || (hash >> (64 - level)) == 0;
  }

 private:
  bool insert_full(uint32_t j, const P3 &p, uint64_t hash);
  void raise_level(uint32_t j);
  P3 *slots_ = nullptr;
  uint32_t *counts_ = nullptr;
  uint8_t *levels_ = nullptr;
  uint32_t layers_ = 0;
  uint32_t capacity_ = 0;
  uint64_t stored_ = 0;
  uint64_t thinned_ = 0;
};

}  // namespace pv::binning

#endif
