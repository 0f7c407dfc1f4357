#include "session/thin_top.h"

#include <algorithm>

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

}  // namespace

ThinTop thin_top(const pv_session *s, const levelling::Transform &t, double rim_mm,
                 const surface::Axis &axis) {
  ThinTop out;
  const double lo = rim_mm - kTopGapMm - kBins;
  // The first step height whose comparison band lies above the bottom.
  const int k_first = std::max(kBins - kMaxTopMm, int(kAboveBottomMm - lo) + kBelowMm + 1);
  if (k_first > kBins - kMinTopMm) return out;
  float h[kSectors][kBins] = {};
  const binning::LayerBins &bins = s->bins;
  for (uint32_t j = 0; j < bins.layers(); ++j) {
    // Each stored point stands for 2^level points of its bin's layer.
    const auto w = float(uint64_t{1} << bins.level(j));
    for (uint32_t i = 0; i < bins.count(j); ++i) {
      const Eigen::Vector3d v = t.apply(bins.points(j)[i]);
      const double z = v.z();
      if (!(z >= lo && z < rim_mm - kTopGapMm)) continue;
      const int b = std::min(kBins - 1, int(z - lo));
      const double dx = v.x() - axis.cx(z), dy = v.y() - axis.cy(z);
      const int a = std::min(kSectors - 1, int(angle_2pi(dy, dx) * (kSectors / kTwoPi)));
      h[a][b] += w;
    }
  }
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
    const double ratio = (top / double(kBins - k)) / (band / double(kBelowMm));
    if (ratio < out.ratio) {
      out.ratio = ratio;
      out.depth_mm = double(kBins - k) + kTopGapMm;
    }
  }
  return out;
}

}  // namespace pv::session
