#include "binning/layer_bins.h"

#include <algorithm>
#include <cstring>

#include "common/point_hash.h"

namespace pv::binning {

namespace {

// The index's order: the points' bits, x then y then z.
struct Bits {
  uint32_t w[3];
};
inline Bits bits_of(const P3 &p) {
  Bits b;
  std::memcpy(b.w, &p, sizeof b.w);
  return b;
}
inline bool bits_less(const P3 &a, const P3 &b) {
  const Bits x = bits_of(a), y = bits_of(b);
  if (x.w[0] != y.w[0]) return x.w[0] < y.w[0];
  if (x.w[1] != y.w[1]) return x.w[1] < y.w[1];
  return x.w[2] < y.w[2];
}
inline bool same_bits(const P3 &a, const P3 &b) { return std::memcmp(&a, &b, sizeof a) == 0; }

struct TailEntry {  // a tail point and its rank, in the merge buffer
  P3 p;
  uint8_t rank;
};

}  // namespace

size_t LayerBins::bytes_needed(uint32_t layers, uint32_t capacity, bool ranks, bool index) {
  return size_t(layers) * capacity * sizeof(P3) + size_t(layers) * sizeof(uint32_t) +
         (index ? size_t(layers) * sizeof(uint32_t) : 0) + size_t(layers) * sizeof(uint8_t) +
         (ranks ? size_t(layers) * capacity : 0);
}

void LayerBins::init(void *memory, uint32_t layers, uint32_t capacity, bool ranks,
                     uint32_t floor_layers, bool index) {
  auto *bytes = static_cast<unsigned char *>(memory);
  slots_ = reinterpret_cast<P3 *>(bytes);
  bytes += size_t(layers) * capacity * sizeof(P3);
  counts_ = reinterpret_cast<uint32_t *>(bytes);
  bytes += size_t(layers) * sizeof(uint32_t);
  has_index_ = index;  // sorted(): the next layers words
  bytes += index ? size_t(layers) * sizeof(uint32_t) : 0;
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
  indexed_ = false;
  copy_refused_ = false;
}

bool LayerBins::start_index() {
  if (!has_index_) return false;
  if (indexed_) return true;
  for (uint32_t j = 0; j < layers_; ++j) sort_bin(j);
  indexed_ = true;
  return true;
}

// Sorted, the copies stored before the repeat was seen lie side by side:
// one of each stays.
void LayerBins::sort_bin(uint32_t j) {
  P3 *bin = slots_ + size_t(j) * capacity_;
  const uint32_t n = counts_[j];
  std::sort(bin, bin + n, bits_less);
  const uint32_t kept = n == 0 ? 0 : uint32_t(std::unique(bin, bin + n, same_bits) - bin);
  stored_ -= n - kept;
  counts_[j] = kept;
  if (ranks_ != nullptr) {
    uint8_t *rk = ranks_ + size_t(j) * capacity_;
    for (uint32_t i = 0; i < kept; ++i) rk[i] = rank(point_hash(bin[i]));
  }
  sorted()[j] = kept;
}

// The tail sorted on the stack, then merged into the prefix from the back
// (each point moves once; equal bits keep the prefix's first).
void LayerBins::merge_tail(uint32_t j) {
  P3 *bin = slots_ + size_t(j) * capacity_;
  uint8_t *rk = ranks_ != nullptr ? ranks_ + size_t(j) * capacity_ : nullptr;
  const uint32_t n = sorted()[j], m = counts_[j] - n;  // m <= tail_max() + 1
  TailEntry buf[kMaxTail + 1];
  for (uint32_t k = 0; k < m; ++k) buf[k] = TailEntry{bin[n + k], rk != nullptr ? rk[n + k] : uint8_t(0)};
  std::sort(buf, buf + m, [](const TailEntry &a, const TailEntry &b) { return bits_less(a.p, b.p); });
  int64_t i = int64_t(n) - 1, k = int64_t(m) - 1, w = int64_t(n + m) - 1;
  while (k >= 0) {
    if (i >= 0 && bits_less(buf[k].p, bin[i])) {
      bin[w] = bin[i];
      if (rk != nullptr) rk[w] = rk[i];
      --i;
    } else {
      bin[w] = buf[k].p;
      if (rk != nullptr) rk[w] = buf[k].rank;
      --k;
    }
    --w;
  }
  sorted()[j] = counts_[j];
}

bool LayerBins::holds(uint32_t j, const P3 &p) const {
  const P3 *bin = slots_ + size_t(j) * capacity_;
  const uint32_t n = counts_[j];
  uint32_t from = 0;
  if (indexed_) {
    const P3 *end = bin + sorted()[j];
    const P3 *at = std::lower_bound(bin, end, p, bits_less);
    if (at != end && same_bits(*at, p)) return true;
    from = sorted()[j];
  }
  for (uint32_t i = from; i < n; ++i) {
    if (same_bits(bin[i], p)) return true;
  }
  return false;
}

// A full bin: halve it (raise its level) until the point is rejected or fits.
// With the index's memory (the duplicate filter on), a point the full bin
// holds already is a copy from a scan sent again before the repeat mode saw
// it (the levelling sample holds one point in a few hundred): it is
// dropped, the level stays, and copy_refused() tells the session to start
// the repeat mode. Halving for such copies (or for points binned under
// another frame the first time) dropped half of the bin's distinct points
// for good: the floor store of a bowl-shaped container sent twice over,
// nearly full after the first copy, kept half of its floor, -0.65 % from
// its single copy (fresh seed 1310 #144, looked at for this). The look-up
// scans the bin only when it overflows.
bool LayerBins::insert_full(uint32_t j, const P3 &p, uint64_t hash) {
  if (has_index_ && !indexed_ && passes(hash, levels_[j]) && holds(j, p)) {
    copy_refused_ = true;
    return false;
  }
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
      if (indexed_ && counts_[j] - sorted()[j] > tail_max()) merge_tail(j);
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
    if (has_index_) sorted()[j] = 0;
  }
  if (levels_[j] == floor_ + 1) raise_floor();
}

// Bin j at `level` (not lower than it is): its points below it dropped.
void LayerBins::thin_to(uint32_t j, uint8_t level) {
  if (level <= levels_[j]) return;
  levels_[j] = level;
  P3 *bin = slots_ + size_t(j) * capacity_;
  const uint32_t n = counts_[j];
  // The index on: the order is kept, the prefix is what stays of it.
  const uint32_t prefix = indexed_ ? sorted()[j] : 0;
  uint32_t kept = 0, kept_in_prefix = 0;
  if (ranks_ != nullptr) {
    uint8_t *rk = ranks_ + size_t(j) * capacity_;
    for (uint32_t i = 0; i < prefix; ++i) kept_in_prefix += rk[i] >= level ? 1 : 0;
    for (uint32_t i = 0; i < n; ++i) {  // branch-free: about half are kept
      const uint8_t r = rk[i];
      bin[kept] = bin[i];
      rk[kept] = r;
      kept += r >= level ? 1 : 0;
    }
  } else {
    for (uint32_t i = 0; i < n; ++i) {
      if (i == prefix) kept_in_prefix = kept;
      if (passes(point_hash(bin[i]), level)) bin[kept++] = bin[i];
    }
    if (prefix >= n) kept_in_prefix = kept;
  }
  if (indexed_) sorted()[j] = kept_in_prefix;
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
