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

// floor() for |v| < 2^31 without a libm call.
int32_t floor_to_int(float v) {
  const int32_t t = int32_t(v);
  return t - (v < float(t) ? 1 : 0);
}

// False for a point the session rejects (so no cell is computed from it).
bool make_probe(float x, float y, float z, Probe *pr) {
  if (!(std::fabs(x) < kAbsurdMm && std::fabs(y) < kAbsurdMm && std::fabs(z) < kAbsurdMm)) {
    return false;  // also NaN and infinities
  }
  const float v[3] = {x * DuplicateFilter::kCellPerMm, y * DuplicateFilter::kCellPerMm,
                      z * DuplicateFilter::kCellPerMm};  // exact: a power of 2
  bool near = false;
  for (int a = 0; a < 3; ++a) {
    pr->cell.c[a] = floor_to_int(v[a]);
    // Exact for |v| < 2^24 (16 m); coarser beyond, still in [0, 1].
    const float frac = v[a] - float(pr->cell.c[a]);
    // Bitwise, not ||: a branch here is mispredicted at random.
    near |= (frac < DuplicateFilter::kNearCells) | (frac > 1.0f - DuplicateFilter::kNearCells);
  }
  pr->near = near;
  const uint64_t h = block_hash(pr->cell.c[0], pr->cell.c[1], pr->cell.c[2]);
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
  const auto *w = reinterpret_cast<const uint32_t *>(&buckets_[bucket]);
  uint32_t hit = 0;
  for (uint32_t i = 0; i < 16; ++i) hit |= w[i] == f ? 1u : 0u;
  return hit != 0;
}

inline void DuplicateFilter::insert(uint32_t bucket, uint32_t f) {
  Bucket &b = buckets_[bucket];
  b.fp[b.next] = f;
  b.next = b.next + 1 == kWays ? 0 : b.next + 1;
}

// The own cell first; near a boundary also the neighbour cells within the
// tolerance (one to seven more lookups, rare).
bool DuplicateFilter::check_and_record(const Probe &pr, const float *v) {
  if (contains(pr.bucket, pr.fp)) return true;
  if (pr.near) {
    int32_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      const float frac = v[a] * kCellPerMm - float(pr.cell.c[a]);
      lo[a] = pr.cell.c[a] - (frac < kNearCells ? 1 : 0);
      hi[a] = pr.cell.c[a] + (frac > 1.0f - kNearCells ? 1 : 0);
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

uint64_t DuplicateFilter::filter_batch(const pv_point_t *pts, size_t n) {
  Probe probes[kBatch];
  uint64_t valid = 0;
  for (size_t i = 0; i < n; ++i) {
    if (make_probe(pts[i].x_mm, pts[i].y_mm, pts[i].z_mm, &probes[i])) {
      valid |= uint64_t(1) << i;
      __builtin_prefetch(&buckets_[probes[i].bucket]);
    }
  }
  uint64_t dups = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!(valid >> i & 1)) continue;
    const float v[3] = {pts[i].x_mm, pts[i].y_mm, pts[i].z_mm};
    if (check_and_record(probes[i], v)) dups |= uint64_t(1) << i;
  }
  return dups;
}

bool DuplicateFilter::seen_before(const P3 &p) {
  const pv_point_t q{p.x_mm, p.y_mm, p.z_mm};
  return filter_batch(&q, 1) != 0;
}

}  // namespace pv::binning
