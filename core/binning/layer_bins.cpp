#include "binning/layer_bins.h"

#include <cstring>

#include "common/point_hash.h"

namespace pv::binning {

size_t LayerBins::bytes_needed(uint32_t layers, uint32_t capacity, bool ranks) {
  return size_t(layers) * capacity * sizeof(P3) + size_t(layers) * sizeof(uint32_t) +
         size_t(layers) * sizeof(uint8_t) + (ranks ? size_t(layers) * capacity : 0);
}

void LayerBins::init(void *memory, uint32_t layers, uint32_t capacity, bool ranks) {
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
  clear();
}

void LayerBins::clear() {
  std::memset(counts_, 0, size_t(layers_) * sizeof(uint32_t));
  std::memset(levels_, 0, size_t(layers_));
  stored_ = 0;
  thinned_ = 0;
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
  if (levels_[j] < 63) ++levels_[j];
  P3 *bin = slots_ + size_t(j) * capacity_;
  const uint8_t level = levels_[j];
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
  if (kept == capacity_ && levels_[j] == 63) {  // cannot thin further: empty
    stored_ -= kept;
    thinned_ += kept;
    counts_[j] = 0;
  }
}

}  // namespace pv::binning
