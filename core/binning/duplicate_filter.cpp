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
constexpr float kAbsurdMm = 1.0e6f;  // as the session's validity check

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

// False for a point the session rejects (so no cell is computed from it).
bool make_probe(const pv_point_t &pt, Probe *pr) {
  const V4f v0 = {pt.x_mm, pt.y_mm, pt.z_mm, 0.0f};
  const V4f absurd = {kAbsurdMm, kAbsurdMm, kAbsurdMm, kAbsurdMm};
  const V4i in_range = (v0 < absurd) & (v0 > -absurd);  // |v| < absurd, false for NaN
  if ((in_range[0] & in_range[1] & in_range[2]) == 0) return false;  // also infinities
  const V4f v = v0 * DuplicateFilter::kCellPerMm;  // exact: a power of 2
  // floor() for |v| < 2^31 without a libm call: truncate, one down where
  // the truncation went up (negative non-integers).
  const V4i t = __builtin_convertvector(v, V4i);
  const V4i c = t + (v < __builtin_convertvector(t, V4f));  // true is -1
  // Exact for |v| < 2^24 (16 m); coarser beyond, still in [0, 1].
  const V4f frac = v - __builtin_convertvector(c, V4f);
  const V4i lo = frac < DuplicateFilter::kNearCells;
  const V4i hi = frac > 1.0f - DuplicateFilter::kNearCells;
  pr->cell.c[0] = c[0];
  pr->cell.c[1] = c[1];
  pr->cell.c[2] = c[2];
  pr->near_lo = uint8_t((lo[0] & 1) | (lo[1] & 2) | (lo[2] & 4));
  pr->near_hi = uint8_t((hi[0] & 1) | (hi[1] & 2) | (hi[2] & 4));
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
  return (hit[0] | hit[1] | hit[2] | hit[3]) != 0;
}

inline void DuplicateFilter::insert(uint32_t bucket, uint32_t f) {
  Bucket &b = buckets_[bucket];
  b.fp[b.next] = f;
  b.next = b.next + 1 == kWays ? 0 : b.next + 1;
}

// The own cell first; near a boundary also the neighbour cells within the
// tolerance (one to seven more lookups, rare): the axes flagged in the
// probe step by -1 or +1, every combination of them.
bool DuplicateFilter::check_and_record(const Probe &pr) {
  if (contains(pr.bucket, pr.fp)) return true;
  if ((pr.near_lo | pr.near_hi) != 0) {
    int32_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = pr.cell.c[a] - (pr.near_lo >> a & 1);
      hi[a] = pr.cell.c[a] + (pr.near_hi >> a & 1);
    }
    for (int32_t x = lo[0]; x <= hi[0]; ++x) {
      for (int32_t y = lo[1]; y <= hi[1]; ++y) {
        for (int32_t z = lo[2]; z <= hi[2]; ++z) {
          const Cell n{{x, y, z}};
          if (x == pr.cell.c[0] && y == pr.cell.c[1] && z == pr.cell.c[2]) continue;
          // A neighbour in the same block shares the bucket and the hash.
          const bool same_block = ((x ^ pr.cell.c[0]) | (y ^ pr.cell.c[1]) | (z ^ pr.cell.c[2])) >>
                                      kBlockShift == 0;
          if (same_block) {
            if (contains(pr.bucket, fingerprint_of(pr.fp_block, n))) return true;
            continue;
          }
          const uint64_t h = block_hash(x, y, z);
          if (contains(bucket_of(h), fingerprint_of(fp_block_of(h), n))) return true;
        }
      }
    }
  }
  insert(pr.bucket, pr.fp);
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
  for (uint64_t left = valid; left != 0; left &= left - 1) {
    const int i = __builtin_ctzll(left);
    if (check_and_record(probes[i])) dups |= uint64_t(1) << i;
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
