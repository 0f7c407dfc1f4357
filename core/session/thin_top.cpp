#include "session/thin_top.h"

#include <algorithm>
#include <cmath>

#include "common/angle.h"
#include "session/session_impl.h"

namespace pv::session {

namespace {

constexpr int kSectors = 8;
// 1 mm height bins from kBins + kTopGapMm under the rim to kTopGapMm under
// it: a ground ring or a lip at the rim stays out.
constexpr int kBins = 70;
constexpr double kTopGapMm = 2.0;
// The step: kStepMm above against kStepMm below; the band under it that
// the top is compared with, kBelowMm; the top band at least kMinTopMm.
constexpr int kStepMm = 6;
constexpr int kBelowMm = 20;
constexpr int kMinTopMm = 4;
constexpr int kMaxTopMm = 40;
// The comparison band keeps above this height (the floor's points would
// count as wall: the levelled bottom is at z = 0).
constexpr double kAboveBottomMm = 16.0;
// A step, measured on tuning seeds 1 and 1300-1302: slipped passes drop to
// 0.02-0.33 of the points below within 6 mm; a grooved wall's bands drop as
// sharply, but its top keeps over 0.36 of the band below (whole-top ratio).
constexpr double kMaxStepRatio = 0.35;
constexpr double kSectorStepRatio = 0.6;
constexpr int kMinStepSectors = 7;
// A wall seen from above holds more points per mm of height where it
// slopes (the scanner faces it) than where it stands upright: per mm of
// height, in proportion to its radius x (its outward slope, mm per mm, +
// kUprightShare). The top's ratio is scaled by the band below against the
// top in that measure (never lowered: a top that slopes more than the band
// below is no sign of a pass missing). Rounded bowls and necking pits whose
// upright top meets a sloping bowl at the step were refused at 0.21-0.32
// (tuning seeds 1312 #294, 1314 #052, grooved; 1313 #147, #148 necking);
// 0.35 keeps every slip of seeds 1311-1315 and tilted 10 as refused as
// before (0.05-0.29).
constexpr double kUprightShare = 0.35;

// The mean radius of each 1 mm height bin, from the model's sections.
void bin_radii(const surface::Profile &prof, double lo, double r[kBins]) {
  double sum[kBins] = {}, n[kBins] = {};
  for (size_t i = 0; i < prof.n; ++i) {
    const double z = prof.z_mm[i];
    if (!(z >= lo && z < lo + kBins)) continue;
    const int b = int(z - lo);
    sum[b] += std::sqrt(std::max(0.0, prof.area_mm2[i]) / (0.5 * kTwoPi));
    n[b] += 1;
  }
  for (int b = 0; b < kBins; ++b) r[b] = n[b] > 0 ? sum[b] / n[b] : (b > 0 ? r[b - 1] : 0.0);
}

// Points per mm of height a band [b0, b1) holds for its geometry, up to a
// common factor: its mean radius x (|its least-squares slope| +
// kUprightShare). The slope over the whole band: a groove's flanks cancel.
double band_geometry(const double r[kBins], int b0, int b1) {
  double sz = 0, sr = 0, szz = 0, szr = 0;
  const double n = b1 - b0;
  for (int b = b0; b < b1; ++b) {
    sz += b;
    sr += r[b];
    szz += double(b) * b;
    szr += double(b) * r[b];
  }
  const double den = n * szz - sz * sz;
  const double slope = den > 0 ? (n * szr - sz * sr) / den : 0.0;
  return (sr / n) * (std::fabs(slope) + kUprightShare);
}

}  // namespace

ThinTop thin_top(const pv_session *s, const levelling::Transform &t, double rim_mm,
                 const surface::Axis &axis, const surface::Profile &prof) {
  ThinTop out;
  const double lo = rim_mm - kTopGapMm - kBins;
  // The first step height whose comparison band lies above the bottom.
  const int k_first = std::max(kBins - kMaxTopMm, int(kAboveBottomMm - lo) + kBelowMm + 1);
  if (k_first > kBins - kMinTopMm) return out;
  float h[kSectors][kBins] = {};
  // Both stores: the floor store holds what lay low in the frame the
  // points were binned in, and a scan first levelled upside down sent the
  // wall's top there (level_surface.cpp, floor_on_top). Counted in the
  // layer store alone, such a top read empty and was refused at 0 (seeds
  // 1323 #597, 1324 #397: the top 20 mm of a small pit without surround).
  for (const binning::LayerBins *bins : {&s->bins, &s->floor_bins}) {
    for (uint32_t j = 0; j < bins->layers(); ++j) {
      // Each stored point stands for 2^level points of its bin's layer.
      const auto w = float(uint64_t{1} << bins->level(j));
      for (uint32_t i = 0; i < bins->count(j); ++i) {
        const Eigen::Vector3d v = t.apply(bins->points(j)[i]);
        const double z = v.z();
        if (!(z >= lo && z < rim_mm - kTopGapMm)) continue;
        const int b = std::min(kBins - 1, int(z - lo));
        const double dx = v.x() - axis.cx(z), dy = v.y() - axis.cy(z);
        const int a = sector_of(dy, dx, kSectors);
        h[a][b] += w;
      }
    }
  }
  double r[kBins];
  bin_radii(prof, lo, r);
  for (int k = k_first; k <= kBins - kMinTopMm; ++k) {
    double above = 0, below = 0, top = 0, band = 0;
    int stepped = 0;
    const int step_end = std::min(kBins, k + kStepMm);
    for (int a = 0; a < kSectors; ++a) {
      double ua = 0, da = 0;
      for (int b = k; b < step_end; ++b) ua += h[a][b];
      for (int b = k - kStepMm; b < k; ++b) da += h[a][b];
      ua /= double(step_end - k);
      da /= double(kStepMm);
      above += ua;
      below += da;
      stepped += da > 0 && ua < kSectorStepRatio * da;
      for (int b = k; b < kBins; ++b) top += h[a][b];
      for (int b = k - kBelowMm; b < k; ++b) band += h[a][b];
    }
    if (!(below > 0) || !(band > 0)) continue;
    if (!(above < kMaxStepRatio * below) || stepped < kMinStepSectors) continue;
    const double geometry = band_geometry(r, k - kBelowMm, k) / band_geometry(r, k, kBins);
    const double ratio = (top / double(kBins - k)) / (band / double(kBelowMm)) * std::max(1.0, geometry);
    if (ratio < out.ratio) {
      out.ratio = ratio;
      out.depth_mm = double(kBins - k) + kTopGapMm;
    }
  }
  return out;
}

}  // namespace pv::session
