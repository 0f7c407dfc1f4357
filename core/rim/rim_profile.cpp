#include "rim/rim_profile.h"

namespace pv::rim {

namespace {

// The wall under the top: the band kRefLoMm..kRefHiMm about the plane. At
// least kMinRefPoints stored points in it (30 in a densest window: its
// ratio below within 20 %), or the profile cannot tell.
constexpr double kRefLoMm = -5.0;
constexpr double kRefHiMm = -2.0;
constexpr uint32_t kMinRefPoints = 300;
// The densest kPeakWindowMm of height above the band, against the band's
// density: a flat top (a lip 3 mm wide on a 100 mm wall holds its points
// within a few tenths of a millimetre, tens of times the wall's density;
// a lip spread over 1.4 mm by a plane 0.3 deg off it still 3.9 times)
// from kFlatRatio, a bare edge (the wall's density rises toward its top:
// 10-15 % on 1 L cylinders) below kEdgeRatio; between them the profile
// cannot tell.
constexpr double kPeakWindowMm = 0.3;
constexpr double kFlatRatio = 2.0;
constexpr double kEdgeRatio = 1.5;
// A flat top's points: within kPeakReachMm of the densest window, at
// least kMinFlatMm of wall's weight above the wall's density (a 3 mm lip
// holds three).
constexpr double kPeakReachMm = 1.5;
constexpr double kMinFlatMm = 1.0;
constexpr double kMaxShiftMm = 1.5;

int bin_of(double dz_mm) { return int((dz_mm - RimProfile::kLoMm) / RimProfile::kStepMm); }
double height_of(int i) { return RimProfile::kLoMm + (i + 0.5) * RimProfile::kStepMm; }

// A top edge: the wall's density is read just under the edge (it rises
// toward the top, where the scanner sees the wall from more directions:
// 10 % over the last 2 mm of a 1 L cylinder, which read 0.18 mm high from
// the density 2-5 mm down), and the weight from there up is wall of that
// density ending at the edge. The edge's first guess: the highest height
// whose kEdgeWindowMm hold half the density far below.
constexpr double kEdgeWindowMm = 0.2;
constexpr double kLocalLoMm = 1.2;  // the local band: this far under the guess
constexpr double kLocalHiMm = 0.4;  // to this far (clear of the noise's blur)
double edge_mm(const RimProfile &p, double far_per_bin) {
  const int win = int(kEdgeWindowMm / RimProfile::kStepMm + 0.5);
  int guess = -1;
  for (int i = RimProfile::kBins - win; i >= bin_of(kRefHiMm); --i) {
    double w = 0;
    for (int j = i; j < i + win; ++j) w += p.weight[j];
    if (w >= 0.5 * far_per_bin * win) {
      guess = i + win / 2;
      break;
    }
  }
  if (guess < 0) return 0.0;
  const int lo = guess - int(kLocalLoMm / RimProfile::kStepMm + 0.5);
  const int hi = guess - int(kLocalHiMm / RimProfile::kStepMm + 0.5);
  if (lo < 0) return 0.0;
  double local = 0, above = 0;
  for (int i = lo; i < hi; ++i) local += p.weight[i];
  for (int i = hi; i < RimProfile::kBins; ++i) above += p.weight[i];
  if (!(local > 0)) return 0.0;
  const double local_per_bin = local / double(hi - lo);
  return RimProfile::kLoMm + hi * RimProfile::kStepMm + above / local_per_bin * RimProfile::kStepMm;
}

}  // namespace

void RimProfile::add(double dz_mm, double weight_points) {
  if (!(dz_mm >= kLoMm && dz_mm < kHiMm)) return;
  int i = bin_of(dz_mm);
  if (i >= kBins) i = kBins - 1;
  weight[i] += weight_points;
  ++points[i];
}

double rim_offset_mm(const RimProfile &p) {
  const int ref_lo = bin_of(kRefLoMm), ref_hi = bin_of(kRefHiMm);
  double ref = 0;
  uint32_t ref_points = 0;
  for (int i = ref_lo; i < ref_hi; ++i) {
    ref += p.weight[i];
    ref_points += p.points[i];
  }
  if (ref_points < kMinRefPoints) return 0.0;
  const double per_bin = ref / double(ref_hi - ref_lo);  // the wall's weight per bin

  // The densest window above the reference band.
  const int win = int(kPeakWindowMm / RimProfile::kStepMm + 0.5);
  double best = 0;
  int best_at = ref_hi;
  for (int i = ref_hi; i + win <= RimProfile::kBins; ++i) {
    double w = 0;
    for (int j = i; j < i + win; ++j) w += p.weight[j];
    if (w > best) {
      best = w;
      best_at = i + win / 2;
    }
  }
  const double ratio = best / (per_bin * win);
  double offset = 0.0;
  if (ratio >= kFlatRatio) {
    // A flat top: the mean height of the weight above the wall's density.
    const int reach = int(kPeakReachMm / RimProfile::kStepMm + 0.5);
    double sw = 0, swz = 0;
    for (int i = best_at - reach; i <= best_at + reach; ++i) {
      if (i < ref_hi || i >= RimProfile::kBins) continue;
      const double excess = p.weight[i] - per_bin;
      if (excess <= 0) continue;
      sw += excess;
      swz += excess * height_of(i);
    }
    if (!(sw >= kMinFlatMm / RimProfile::kStepMm * per_bin)) return 0.0;
    offset = swz / sw;
  } else if (ratio < kEdgeRatio) {
    offset = edge_mm(p, per_bin);
  }
  return (offset > -kMaxShiftMm && offset < kMaxShiftMm) ? offset : 0.0;
}

}  // namespace pv::rim
