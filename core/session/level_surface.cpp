// Levelling for method surface: the volume is defined below the ground, so
// a scan with a ground ring is levelled on it; without one, on the plane of
// the wall's top edge. The paper's floor-plane levelling stays the start
// (and the paper method's only levelling): a bowl or an uneven floor tilts
// it by a degree or more (measured: bowls read +4.7 and +6.7 %, a bowl
// without ground +1.9 %).
#include <Eigen/Geometry>

#include "rim/rim.h"
#include "rim/rim_plane.h"
#include "session/session_impl.h"

namespace pv::session {

namespace {

// Rotation taking unit vector n onto +Z (Rodrigues), applied after t.
void rotate_onto_z(const Eigen::Vector3d &n, levelling::Transform *t) {
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d axis = n.cross(z);
  const double sn = axis.norm(), cs = n.dot(z);
  if (!(sn > 1e-12)) return;
  const Eigen::Vector3d k = axis / sn;
  Eigen::Matrix3d K;
  K << 0, -k.z(), k.y(), k.z(), 0, -k.x(), -k.y(), k.x(), 0;
  const Eigen::Matrix3d Rg = Eigen::Matrix3d::Identity() + sn * K + (1 - cs) * K * K;
  t->R = Rg * t->R;
  t->t = Rg * t->t;
}

bool level_on_ground(pv_session *s, levelling::Transform *t) {
  const uint32_t n = s->sample.size();
  for (uint32_t i = 0; i < n; ++i) s->lv.a[i] = t->apply(s->sample_points[i]);
  rim::Params rp;
  rp.band_ratio = s->cfg.rim_band_ratio;
  static_assert(sizeof(uint32_t) <= sizeof(Eigen::Vector3d), "index scratch fits");
  const rim::GroundPlane gp =
      rim::fit_ground_plane(s->lv.a, n, rp, s->lv.v, reinterpret_cast<uint32_t *>(s->lv.b));
  if (!gp.found) return false;
  rotate_onto_z(gp.normal, t);
  return true;
}

// Sector tops of the stored points (levelled by t) around their centre.
// The floor store holds only the bottom: its points are not needed here.
void sector_tops(const pv_session *s, const levelling::Transform &t, rim::SectorTops *tops) {
  double sx = 0, sy = 0;
  uint64_t n = 0;
  const binning::LayerBins &bins = s->bins;
  for (uint32_t b = 0; b < bins.layers(); ++b) {
    for (uint32_t i = 0; i < bins.count(b); ++i) {
      const Eigen::Vector3d v = t.apply(bins.points(b)[i]);
      sx += v.x();
      sy += v.y();
      ++n;
    }
  }
  if (n == 0) n = 1;
  tops->clear(sx / double(n), sy / double(n));
  for (int round = 0; round <= rim::kRimDigRounds; ++round) {
    if (round > 0 && !tops->dig()) break;
    for (uint32_t b = 0; b < bins.layers(); ++b) {
      for (uint32_t i = 0; i < bins.count(b); ++i) {
        const Eigen::Vector3d v = t.apply(bins.points(b)[i]);
        tops->offer(v.x(), v.y(), v.z());
      }
    }
  }
}

}  // namespace

double level_for_surface(pv_session *s, levelling::Transform *t) {
  if (level_on_ground(s, t)) return -1.0;
  rim::SectorTops tops;
  sector_tops(s, *t, &tops);
  const rim::RimPlane rp = rim::fit_rim_plane(tops);
  if (!rp.found) return -1.0;
  rotate_onto_z(rp.normal, t);
  // The rim plane's height after the rotation: the rotated plane is
  // z = d (its normal is +Z, its offset unchanged by a rotation about the
  // origin).
  return rp.d;
}

}  // namespace pv::session
