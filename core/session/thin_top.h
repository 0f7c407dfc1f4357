// The wall's top seen by one pass only (method surface's thin-top check,
// measure_surface.cpp).
//
// A pass whose tracking slipped along the axis (up, or down) holds the
// wall shifted by the slip: above the other pass's rim only the slipped
// pass saw the wall, below it both did. Where that pass saw little of the
// floor, the floor checks see nothing, and the rim is read on the slipped
// top while the floor stays the other pass's: the pit reads deeper by the
// slip (pitvol-sim sweeps, seeds 1 and 1300-1302: 16 vertical slips read
// +0.5 to +36 % with PV_OK). The stored points per mm of height (each
// counted with its bin's thinning factor) then drop by a step, all round,
// somewhere 6 to 42 mm under the rim, and stay low up to it.
#ifndef PV_SESSION_THIN_TOP_H
#define PV_SESSION_THIN_TOP_H

#include "levelling/levelling.h"
#include "surface/surface_model.h"

struct pv_session;

namespace pv::session {

struct ThinTop {
  // Over the heights k where the points per mm drop by a step (the 6 mm
  // above k against the 6 mm below, pooled over 8 sectors around the axis,
  // under kMaxStepRatio and in 7 of the 8 sectors under kSectorStepRatio):
  // the least ratio of the points per mm from k to 2 mm under the rim to
  // those in the 20 mm below k, each for its slope (thin_top.cpp). 1 where
  // no such step is found.
  double ratio = 1.0;
  double depth_mm = 0.0;  // k's depth under the rim
};

ThinTop thin_top(const pv_session *s, const levelling::Transform &t, double rim_mm,
                 const surface::Axis &axis, const surface::Profile &prof);

}  // namespace pv::session

#endif
