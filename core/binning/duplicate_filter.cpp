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

// The fingerprint: the block's part and the cell's place in its block
// (4 bits an axis). Never below 16: a bucket's cursor (0..14) shares its
// cache line.
uint32_t fingerprint_at(uint32_t fp_block, uint32_t place) {
  const uint32_t f = fp_block | place;
  return f < 16 ? f + 16 : f;
}

uint32_t fingerprint_of(uint32_t fp_block, const Cell &k) {
  constexpr int32_t m = (1 << kBlockShift) - 1;
  return fingerprint_at(fp_block, uint32_t(k.c[0] & m) | uint32_t(k.c[1] & m) << 4 |
                                      uint32_t(k.c[2] & m) << 8);
}

// Four points' coordinates of one axis in a 4-lane vector (GCC/Clang vector
// extensions: SSE2 on x86-64, NEON on aarch64, scalar code on Cortex-M7;
// the same IEEE single-precision operations as one point at a time, so the
// same cells): per-axis scalar code was most of the filter's cost.
typedef float V4f __attribute__((vector_size(16)));
typedef int32_t V4i __attribute__((vector_size(16)));
typedef uint32_t V4u __attribute__((vector_size(16)));
// A bucket's words read as vectors (may alias the uint32_t array).
typedef uint32_t V4uLine __attribute__((vector_size(16), may_alias));

// Bit k set where lane k (0..3) of a compare mask is true. x86-64: one
// movmskps; elsewhere the OR of (mask & {1, 2, 4, 8}) over two 64-bit halves
// (no lane extracts). The same bits either way.
inline uint32_t lane_bits4(V4i mask) {
#if defined(__SSE2__)
  return uint32_t(__builtin_ia32_movmskps(reinterpret_cast<V4f>(mask)));
#else
  const V4i m = mask & V4i{1, 2, 4, 8};
  uint64_t q[2];
  std::memcpy(q, &m, sizeof q);
  const uint64_t r = q[0] | q[1];
  return uint32_t(r) | uint32_t(r >> 32);
#endif
}

// Two-vector shuffle (GCC and Clang spell it differently).
#if defined(__clang__)
#define PV_SHUFFLE(a, b, i0, i1, i2, i3) __builtin_shufflevector(a, b, i0, i1, i2, i3)
#else
#define PV_SHUFFLE(a, b, i0, i1, i2, i3) __builtin_shuffle(a, b, V4i{i0, i1, i2, i3})
#endif

// A batch's probes, one array per field (vectors store into them whole).
struct Probes {
  alignas(16) int32_t cell[3][DuplicateFilter::kBatch];
  alignas(16) int32_t near[DuplicateFilter::kBatch];
  alignas(16) uint32_t lo[DuplicateFilter::kBatch];     // pack21() of the block,
  alignas(16) uint32_t hi[DuplicateFilter::kBatch];     // as two 32-bit halves
  alignas(16) uint32_t place[DuplicateFilter::kBatch];  // the cell's in its block
  uint32_t bucket[DuplicateFilter::kBatch];
  uint32_t fp[DuplicateFilter::kBatch];
  uint32_t fp_block[DuplicateFilter::kBatch];
};

// The cells, near bits and block keys of points at..at+3 of a batch, one
// axis of four points per vector (one point's three axes per vector left
// a quarter of each vector idle and paid a mask extraction per point).
// Every lane does what the one-point code did, in the same IEEE
// single-precision operations, so the same cells and near bits. Returns
// bit k set where point k is valid (|coordinate| < kAbsurdMm on every axis:
// false for NaN and infinities); an invalid point's lanes are computed from
// zeros and not used.
uint32_t make_probes4(const pv_point_t *pt, Probes *pr, size_t at) {
  static_assert(sizeof(pv_point_t) == 3 * sizeof(float), "points are packed xyz");
  V4f a, b, c;  // x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3
  std::memcpy(&a, &pt[0], sizeof a);
  std::memcpy(&b, reinterpret_cast<const unsigned char *>(pt) + 16, sizeof b);
  std::memcpy(&c, reinterpret_cast<const unsigned char *>(pt) + 32, sizeof c);
  // The transpose in shuffles that take two lanes of each input (one
  // shufps each on x86-64).
  const V4f x = PV_SHUFFLE(a, PV_SHUFFLE(b, c, 2, 2, 5, 5), 0, 3, 4, 6);
  const V4f y = PV_SHUFFLE(PV_SHUFFLE(a, b, 1, 1, 4, 4), PV_SHUFFLE(b, c, 3, 3, 6, 6), 0, 2, 4, 6);
  const V4f z = PV_SHUFFLE(PV_SHUFFLE(a, b, 2, 2, 5, 5), c, 0, 2, 4, 7);
  // |v| < absurd, as v < absurd && v > -absurd: false for NaN.
  const V4i abs_mask = {0x7fffffff, 0x7fffffff, 0x7fffffff, 0x7fffffff};
  const V4f absurd = {kAbsurdMm, kAbsurdMm, kAbsurdMm, kAbsurdMm};
  const V4i ok = (reinterpret_cast<V4f>(reinterpret_cast<V4i>(x) & abs_mask) < absurd) &
                 (reinterpret_cast<V4f>(reinterpret_cast<V4i>(y) & abs_mask) < absurd) &
                 (reinterpret_cast<V4f>(reinterpret_cast<V4i>(z) & abs_mask) < absurd);
  const uint32_t valid = lane_bits4(ok);
  V4i cell[3];
  V4i near = {0, 0, 0, 0};
  const V4f axes[3] = {x, y, z};
  for (int k = 0; k < 3; ++k) {
    // An invalid lane is zeroed: no conversion of NaN or out-of-range values.
    const V4f v = reinterpret_cast<V4f>(reinterpret_cast<V4i>(axes[k]) & ok) *
                  DuplicateFilter::kCellPerMm;  // exact: a power of 2
    // floor() for |v| < 2^31 without a libm call: truncate, one down where
    // the truncation went up (negative non-integers).
    const V4i t = __builtin_convertvector(v, V4i);
    cell[k] = t + (v < __builtin_convertvector(t, V4f));  // true is -1
    // Exact for |v| < 2^24 (16 m); coarser beyond, still in [0, 1].
    const V4f frac = v - __builtin_convertvector(cell[k], V4f);
    near |= ((frac < DuplicateFilter::kNearCells) & (1 << k)) |
            ((frac > 1.0f - DuplicateFilter::kNearCells) & (8 << k));
    std::memcpy(&pr->cell[k][at], &cell[k], sizeof cell[k]);
  }
  std::memcpy(&pr->near[at], &near, sizeof near);
  // pack21() of the blocks (cells >> 4, arithmetic: floor division) as two
  // 32-bit halves, and the cells' places in their blocks (fingerprint_at()).
  constexpr uint32_t m21 = (1u << 21) - 1;
  const V4u bx = reinterpret_cast<V4u>(cell[0] >> kBlockShift) & m21;
  const V4u by = reinterpret_cast<V4u>(cell[1] >> kBlockShift) & m21;
  const V4u bz = reinterpret_cast<V4u>(cell[2] >> kBlockShift) & m21;
  const V4u lo = bx | by << 21;
  const V4u hi = by >> 11 | bz << 10;
  constexpr int32_t m4 = (1 << kBlockShift) - 1;
  const V4u place =
      reinterpret_cast<V4u>((cell[0] & m4) | (cell[1] & m4) << 4 | (cell[2] & m4) << 8);
  std::memcpy(&pr->lo[at], &lo, sizeof lo);
  std::memcpy(&pr->hi[at], &hi, sizeof hi);
  std::memcpy(&pr->place[at], &place, sizeof place);
  return valid;
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
  // The line is 64-byte aligned: aligned vector loads, which x86-64 folds
  // into the compares (unaligned copies and a reduction through general
  // registers were half of a lookup's instructions).
  const V4uLine *w = reinterpret_cast<const V4uLine *>(&buckets_[bucket]);
  const V4u fv = {f, f, f, f};
  return lane_bits4((w[0] == fv) | (w[1] == fv) | (w[2] == fv) | (w[3] == fv)) != 0;
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
  Probes pr;
  uint64_t valid = 0;
  size_t at = 0;
  for (; at + 4 <= n; at += 4) valid |= uint64_t(make_probes4(pts + at, &pr, at)) << at;
  if (at < n) {  // the last one to three points, padded with zeros
    pv_point_t tail[4] = {};
    std::memcpy(tail, pts + at, (n - at) * sizeof *pts);
    const uint32_t v = make_probes4(tail, &pr, at) & ((1u << (n - at)) - 1);
    valid |= uint64_t(v) << at;
  }
  // Each valid point's block hash (as block_hash()), bucket and
  // fingerprint; ask for the bucket's line.
  for (uint64_t left = valid; left != 0; left &= left - 1) {
    const int i = __builtin_ctzll(left);
    const uint64_t h = mix64(uint64_t(pr.hi[i]) << 32 | pr.lo[i]);
    pr.bucket[i] = bucket_of(h);
    pr.fp_block[i] = fp_block_of(h);
    pr.fp[i] = fingerprint_at(pr.fp_block[i], pr.place[i]);
    __builtin_prefetch(&buckets_[pr.bucket[i]]);
  }
  uint64_t dups = 0;
  // The own cell first, then (near a boundary) its neighbours; a point
  // seen in neither is recorded.
  for (uint64_t left = valid; left != 0; left &= left - 1) {
    const int i = __builtin_ctzll(left);
    bool seen = contains(pr.bucket[i], pr.fp[i]);
    if (!seen && pr.near[i] != 0) {
      // Most points near a boundary are near one (94 %), and their
      // neighbour is in the same block (15 in 16): the same bucket, its
      // place one step along that axis. That case inline, as
      // neighbour_seen() would look it up; the others there.
      const uint32_t nr = uint32_t(pr.near[i]);
      const uint32_t axes = (nr | nr >> 3) & 7u;
      const uint32_t shift = 4u * uint32_t(__builtin_ctz(axes));  // the axis's place nibble
      const uint32_t at_axis = pr.place[i] >> shift & 15u;
      const bool down = (nr & 7u) != 0;  // the lower boundary: the cell below
      if ((axes & (axes - 1)) == 0 && (down ? at_axis != 0 : at_axis != 15)) {
        const uint32_t step = 1u << shift;
        const uint32_t place = down ? pr.place[i] - step : pr.place[i] + step;
        seen = contains(pr.bucket[i], fingerprint_at(pr.fp_block[i], place));
      } else {
        const Probe q{{{pr.cell[0][i], pr.cell[1][i], pr.cell[2][i]}},
                      pr.bucket[i],
                      pr.fp[i],
                      pr.fp_block[i],
                      uint8_t(nr)};
        seen = neighbour_seen(q);
      }
    }
    if (seen) {
      dups |= uint64_t(1) << i;
    } else {
      insert(pr.bucket[i], pr.fp[i]);
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
