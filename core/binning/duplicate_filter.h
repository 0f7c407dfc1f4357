// Drops points that repeat a recently seen point: a scanner that resends
// frames (lost acknowledgements, a replayed buffer) must not move the volume.
//
// Why a window and not a set of every point: the core has fixed memory and
// a 10-million-point scan cannot be remembered. Resent frames arrive close
// behind the original (a few frames of at most 4096 points,
// docs/protocol/usb.md), so the filter remembers recent points in a
// set-associative table: kBuckets buckets of one cache line, each holding
// the last 15 point fingerprints that mapped to it (first in, first out).
// A lookup reads one cache line. A point is forgotten once 15 newer points
// fall into its bucket: with 16384 buckets that happens within the next
// 16,384 points (4 frames) with probability 3e-13 and within 32,768
// (8 frames) with 4e-9 (Poisson tails). Fingerprints are 32 bits of the
// cell key (the other 14 bits pick the bucket): two distinct points are
// taken for one with probability 15 / 2^32 per lookup, about one point in a
// 10-million-point scan every 20 scans; dropping it is harmless.
// One hash per point: the bucket comes from the top bits of the hash of the
// point's block of 16^3 cells, the fingerprint from 20 other bits of that
// hash and the cell's 12-bit place in its block (so cells of one block,
// which share a bucket, never share a fingerprint). A lookup compares the
// whole cache line (cursor included: fingerprints are >= 16) in one
// branch-free sweep.
//
// Near-exact duplicates: a resend that went through another conversion can
// differ in the last bits. Points are keyed by a cell of 2^-7 mm (about
// 8 um, 100 times below any handheld scanner's resolution); a point within
// 2^-12 mm (0.24 um: one float ulp up to 2 m, two up to 1 m) of a cell
// boundary is also looked up in the neighbouring cells (18 % of points).
// So two points closer than that on every axis are always the same point
// to the filter. Distinct points closer than a cell are rare, and dropping
// one of two points that close is harmless (the thinning scale is 1 mm).
#ifndef PV_BINNING_DUPLICATE_FILTER_H
#define PV_BINNING_DUPLICATE_FILTER_H

#include <cstddef>
#include <cstdint>

#include "common/geometry.h"
#include "pitvol/pitvol.h"

namespace pv::binning {

class DuplicateFilter {
 public:
  static constexpr uint32_t kBuckets = 16384;
  static constexpr uint32_t kWays = 15;  // + one FIFO cursor = 64 bytes
  static constexpr float kCellPerMm = 128.0f;      // cell 2^-7 mm
  static constexpr float kNearCells = 1.0f / 32;   // 2^-12 mm in cells

  struct Cell {  // a point's cell: floor(coordinate * kCellPerMm) per axis
    int32_t c[3];
  };

  struct Probe {  // a point's cell, bucket and fingerprint
    Cell cell;
    uint32_t bucket;
    uint32_t fp;
    uint32_t fp_block;  // the block's part of the fingerprint (20 bits << 12)
    // Axes on which the point lies within the tolerance of its cell's
    // lower (bit a) / upper (bit a + 3) boundary: the neighbours to look up.
    uint8_t near;
  };

  static size_t bytes_needed() { return size_t(kBuckets) * sizeof(Bucket); }
  // memory: bytes_needed() bytes, aligned to 64 bytes (PV_BLOCK_ALIGN).
  void init(void *memory);
  void clear();

  static constexpr size_t kBatch = 64;
  // Bit i of the result is set if pts[i] repeats a point of the window or
  // an earlier point of the batch (drop it); the other points are recorded.
  // n <= kBatch. Points that are not finite or beyond 1e6 mm are skipped
  // (bit clear, not recorded): the caller rejects them; *valid gets bit i
  // set for the others (the session's validity check). A batch first
  // computes every point's bucket and asks for its cache line, then looks
  // them up: the table's cache misses overlap instead of stalling in turn.
  uint64_t filter_batch(const pv_point_t *pts, size_t n, uint64_t *valid);
  // One point (tests): true if it is a duplicate.
  bool seen_before(const P3 &p);

 private:
  struct Bucket {
    uint32_t next;  // FIFO cursor: the way the next fingerprint replaces (< 16)
    uint32_t fp[kWays];  // 0: empty
  };
  static_assert(sizeof(Bucket) == 64, "one bucket, one cache line");
  bool contains(uint32_t bucket, uint32_t fingerprint) const;
  bool neighbour_seen(const Probe &probe) const;
  void insert(uint32_t bucket, uint32_t fingerprint);
  Bucket *buckets_ = nullptr;
};

}  // namespace pv::binning

#endif
