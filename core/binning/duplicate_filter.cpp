#include "binning/duplicate_filter.h"

#include <cmath>
#include <cstring>

#include "common/point_hash.h"

namespace pv::binning {

namespace {

using Cell = DuplicateFilter::Cell;
using Probe = DuplicateFilter::Probe;

constexpr int kBucketBits = 14;
static_assert(DuplicateFilter::kBuckets == 1u << kBucketBits, "bucket index is the hash's top bits");
// A bucket serves a block of 16^3 cells (2^-3 mm on a side): a point's
// neighbour cells almost always share its bucket, so a lookup near a cell
// boundary still reads the cache line already loaded.
constexpr int kBlockShift = 4;

// 21 bits per axis in one word, one mix: cells alias only 2^21 cells
// (2 m) apart, and then also need the same bucket to be confused.
uint64_t pack21(int32_t x, int32_t y, int32_t z) {
  constexpr uint64_t m = (1u << 21) - 1;
  return (uint64_t(uint32_t(x)) & m) | ((uint64_t(uint32_t(y)) & m) << 21) |
         ((uint64_t(uint32_t(z)) & m) << 42);
}

// The hash of a cell's block (cells >> 4, arithmetic shift: floor division,
// also for negative cells).
uint64_t block_hash(int32_t x, int32_t y, int32_t z) {
  return mix64(pack21(x >> kBlockShift, y >> kBlockShift, z >> kBlockShift));
}

uint32_t bucket_of(uint64_t block_hash) { return uint32_t(block_hash >> (64 - kBucketBits)); }

// Bits 12..31 of the fingerprint: hash bits the bucket does not use.
uint32_t fp_block_of(uint64_t block_hash) { return uint32_t(block_hash >> 12) & 0xFFFFF000u; }

// The fingerprint: the block's part and the cell's place in its block.
// Never below 16: a bucket's cursor (0..14) shares its cache line.
uint32_t fingerprint_of(uint32_t fp_block, const Cell &k) {
  constexpr int32_t m = (1 << kBlockShift) - 1;
  const uint32_t f = fp_block | uint32_t(k.c[0] & m) | uint32_t(k.c[1] & m) << 4 |
                     uint32_t(k.c[2] & m) << 8;
  return f < 16 ? f + 16 : f;
}

// The three coordinates in one 4-lane vector (GCC/Clang vector extensions:
// SSE2 on x86-64, NEON on aarch64, scalar code on Cortex-M7; the same IEEE
// single-precision operations as one axis at a time, so the same cells).
// Issue 12: the per-axis scalar code was most of the filter's cost.
typedef float V4f __attribute__((vector_size(16)));
typedef int32_t V4i __attribute__((vector_size(16)));
typedef uint32_t V4u __attribute__((vector_size(16)));

// Bit a set where lane a (0..2) of a compare mask is true. x86-64: one
// movmskps; elsewhere the OR of (mask & {1, 2, 4, 0}) over two 64-bit halves
// (no lane extracts). The same bits either way.
inline uint32_t lane_bits(V4i mask) {
#if defined(__SSE2__)
  return uint32_t(__builtin_ia32_movmskps(reinterpret_cast<V4f>(mask))) & 7u;
#else
  const V4i m = mask & V4i{1, 2, 4, 0};
  uint64_t q[2];
  std::memcpy(q, &m, sizeof q);
  const uint64_t r = q[0] | q[1];
  return uint32_t(r) | uint32_t(r >> 32);
#endif
}

// False for a point the session rejects (so no cell is computed from it).
bool make_probe(const pv_point_t &pt, Probe *pr) {
  const V4f v0 = {pt.x_mm, pt.y_mm, pt.z_mm, 0.0f};
  const V4f absurd = {kAbsurdMm, kAbsurdMm, kAbsurdMm, kAbsurdMm};
  // |v| < absurd on every axis; false for NaN and infinities.
  if (lane_bits((v0 < absurd) & (v0 > -absurd)) != 7) return false;
  const V4f v = v0 * DuplicateFilter::kCellPerMm;  // exact: a power of 2
  // floor() for |v| < 2^31 without a libm call: truncate, one down where
  // the truncation went up (negative non-integers).
  const V4i t = __builtin_convertvector(v, V4i);
  const V4i c = t + (v < __builtin_convertvector(t, V4f));  // true is -1
  // Exact for |v| < 2^24 (16 m); coarser beyond, still in [0, 1].
  const V4f frac = v - __builtin_convertvector(c, V4f);
  pr->near = uint8_t(lane_bits(frac < DuplicateFilter::kNearCells) |
                     lane_bits(frac > 1.0f - DuplicateFilter::kNearCells) << 3);
  pr->cell.c[0] = c[0];
  pr->cell.c[1] = c[1];
  pr->cell.c[2] = c[2];
  const uint64_t h = block_hash(c[0], c[1], c[2]);
  pr->bucket = bucket_of(h);
  pr->fp_block = fp_block_of(h);
  pr->fp = fingerprint_of(pr->fp_block, pr->cell);
  return true;
}

}  // namespace

void DuplicateFilter::init(void *memory) {
  buckets_ = static_cast<Bucket *>(memory);
  clear();
}

void DuplicateFilter::clear() { std::memset(buckets_, 0, bytes_needed()); }

inline bool DuplicateFilter::contains(uint32_t bucket, uint32_t f) const {
  // All 16 words of the line, cursor included (fingerprints are >= 16 and
  // the cursor < 15): four vector compares, no branch.
  V4u w[4];
  std::memcpy(w, &buckets_[bucket], sizeof w);
  const V4u fv = {f, f, f, f};
  const V4i hit = (w[0] == fv) | (w[1] == fv) | (w[2] == fv) | (w[3] == fv);
  uint64_t q[2];
  std::memcpy(q, &hit, sizeof q);
  return (q[0] | q[1]) != 0;
}

inline void DuplicateFilter::insert(uint32_t bucket, uint32_t f) {
  Bucket &b = buckets_[bucket];
  b.fp[b.next] = f;
  b.next = b.next + 1 == kWays ? 0 : b.next + 1;
}

// Near a boundary, the neighbour cells within the tolerance (one to seven
// lookups, rare). An axis is near one boundary at most (the tolerance is
// below half a cell), so the neighbours are the cell moved by -1 or +1 along
// every non-empty subset of the flagged axes.
bool DuplicateFilter::neighbour_seen(const Probe &pr) const {
  const uint32_t axes = (pr.near | pr.near >> 3) & 7u;
  int32_t step[3];
  for (int a = 0; a < 3; ++a) step[a] = (pr.near >> a & 1) ? -1 : 1;
  for (uint32_t sub = axes; sub != 0; sub = (sub - 1) & axes) {
    const Cell n{{pr.cell.c[0] + ((sub & 1) ? step[0] : 0), pr.cell.c[1] + ((sub & 2) ? step[1] : 0),
                  pr.cell.c[2] + ((sub & 4) ? step[2] : 0)}};
    // A neighbour in the same block shares the bucket and the hash.
    const bool same_block = ((n.c[0] ^ pr.cell.c[0]) | (n.c[1] ^ pr.cell.c[1]) |
                             (n.c[2] ^ pr.cell.c[2])) >> kBlockShift == 0;
    if (same_block) {
      if (contains(pr.bucket, fingerprint_of(pr.fp_block, n))) return true;
      continue;
    }
    const uint64_t h = block_hash(n.c[0], n.c[1], n.c[2]);
    if (contains(bucket_of(h), fingerprint_of(fp_block_of(h), n))) return true;
  }
  return false;
}

uint64_t DuplicateFilter::filter_batch(const pv_point_t *pts, size_t n, uint64_t *valid_out) {
  Probe probes[kBatch];
  uint64_t valid = 0;
  for (size_t i = 0; i < n; ++i) {
    if (make_probe(pts[i], &probes[i])) {
      valid |= uint64_t(1) << i;
      __builtin_prefetch(&buckets_[probes[i].bucket]);
    }
  }
  uint64_t dups = 0;
  // The own cell first, then (near a boundary) its neighbours; a point
  // seen in neither is recorded.
  for (uint64_t left = valid; left != 0; left &= left - 1) {
    const int i = __builtin_ctzll(left);
    const Probe &pr = probes[i];
    if (contains(pr.bucket, pr.fp) || (pr.near != 0 && neighbour_seen(pr))) {
      dups |= uint64_t(1) << i;
    } else {
      insert(pr.bucket, pr.fp);
    }
  }
  *valid_out = valid;
  return dups;
}

bool DuplicateFilter::seen_before(const P3 &p) {
  const pv_point_t q{p.x_mm, p.y_mm, p.z_mm};
  uint64_t valid = 0;
  return filter_batch(&q, 1, &valid) != 0;
}

}  // namespace pv::binning
