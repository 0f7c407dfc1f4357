#include "binning/layer_bins.h"

#include <cstring>

#include "common/point_hash.h"

namespace pv::binning {

size_t LayerBins::bytes_needed(uint32_t layers, uint32_t capacity, bool ranks) {
  return size_t(layers) * capacity * sizeof(P3) + size_t(layers) * sizeof(uint32_t) +
         size_t(layers) * sizeof(uint8_t) + (ranks ? size_t(layers) * capacity : 0);
}

void LayerBins::init(void *memory, uint32_t layers, uint32_t capacity, bool ranks,
                     uint32_t floor_layers) {
  auto *bytes = static_cast<unsigned char *>(memory);
  slots_ = reinterpret_cast<P3 *>(bytes);
  bytes += size_t(layers) * capacity * sizeof(P3);
  counts_ = reinterpret_cast<uint32_t *>(bytes);
  bytes += size_t(layers) * sizeof(uint32_t);
  levels_ = bytes;
  bytes += size_t(layers) * sizeof(uint8_t);
  ranks_ = ranks ? bytes : nullptr;
  layers_ = layers;
  capacity_ = capacity;
  floor_layers_ = floor_layers;
  clear();
}

void LayerBins::clear() {
  std::memset(counts_, 0, size_t(layers_) * sizeof(uint32_t));
  std::memset(levels_, 0, size_t(layers_));
  stored_ = 0;
  thinned_ = 0;
  floor_ = 0;
}

// A full bin: halve it (raise its level) until the point is rejected or fits.
bool LayerBins::insert_full(uint32_t j, const P3 &p, uint64_t hash) {
  while (true) {
    if (!passes(hash, levels_[j])) {
      ++thinned_;
      return false;
    }
    if (counts_[j] < capacity_) {
      const size_t slot = size_t(j) * capacity_ + counts_[j]++;
      slots_[slot] = p;
      if (ranks_ != nullptr) ranks_[slot] = rank(hash);
      ++stored_;
      return true;
    }
    raise_level(j);  // full: halve the bin, then try again
  }
}

void LayerBins::raise_level(uint32_t j) {
  // Level 63 keeps only hash 0 or 1: a bin that full of identical-hash
  // points is pathological; stop raising and let passes() reject.
  thin_to(j, levels_[j] < 63 ? uint8_t(levels_[j] + 1) : uint8_t(63));
  if (counts_[j] == capacity_ && levels_[j] == 63) {  // cannot thin further: empty
    stored_ -= counts_[j];
    thinned_ += counts_[j];
    counts_[j] = 0;
  }
  if (levels_[j] == floor_ + 1) raise_floor();
}

// Bin j at `level` (not lower than it is): its points below it dropped.
void LayerBins::thin_to(uint32_t j, uint8_t level) {
  if (level <= levels_[j]) return;
  levels_[j] = level;
  P3 *bin = slots_ + size_t(j) * capacity_;
  const uint32_t n = counts_[j];
  uint32_t kept = 0;
  if (ranks_ != nullptr) {
    uint8_t *rk = ranks_ + size_t(j) * capacity_;
    for (uint32_t i = 0; i < n; ++i) {  // branch-free: about half are kept
      const uint8_t r = rk[i];
      bin[kept] = bin[i];
      rk[kept] = r;
      kept += r >= level ? 1 : 0;
    }
  } else {
    for (uint32_t i = 0; i < n; ++i) {
      if (passes(point_hash(bin[i]), level)) bin[kept++] = bin[i];
    }
  }
  const uint32_t dropped = counts_[j] - kept;
  stored_ -= dropped;
  thinned_ += dropped;
  counts_[j] = kept;
}

// The floor is the highest level that floor_layers bins have reached; when
// it rises, every bin below it thins to it. Only a bin reaching floor + 1
// can lift it, so the bins are counted then (no table per level: the MCU
// profile's block has no room).
void LayerBins::raise_floor() {
  if (floor_layers_ == 0) return;
  while (floor_ < 63) {
    const uint8_t next = uint8_t(floor_ + 1);
    uint32_t at_next = 0;
    for (uint32_t j = 0; j < layers_; ++j) at_next += levels_[j] >= next ? 1 : 0;
    if (at_next < floor_layers_) return;
    floor_ = next;
    for (uint32_t j = 0; j < layers_; ++j) thin_to(j, next);
  }
}

}  // namespace pv::binning
