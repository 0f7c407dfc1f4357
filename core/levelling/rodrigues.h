// Rotation that carries a unit normal onto +Z (paper 3.2.2, eqs. 1-4).
#ifndef PV_LEVELLING_RODRIGUES_H
#define PV_LEVELLING_RODRIGUES_H

#include <Eigen/Core>

namespace pv::levelling {

// R with R * n = (0, 0, 1). n need not be exactly unit length.
// Rodrigues: R = I + V + V^2 / (1 + c), v = n x k, c = n . k. The paper writes
// (1 - c)/s^2, which equals 1/(1 + c) but loses precision near c = 1.
// When n points (almost) straight down, 1 + c vanishes: the paper switches to
// a fixed 180 degree flip, here a half turn about the X axis.
Eigen::Matrix3d rotation_onto_z(const Eigen::Vector3d &n);

}  // namespace pv::levelling

#endif
