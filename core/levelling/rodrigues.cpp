#include "levelling/rodrigues.h"

namespace pv::levelling {

Eigen::Matrix3d rotation_onto_z(const Eigen::Vector3d &n_in) {
  const Eigen::Vector3d n = n_in.normalized();
  const double c = n.z();
  // For a normal in the lower hemisphere 1/(1+c) amplifies rounding and is
  // undefined at -Z. Compose instead: a half turn first (the paper's flip),
  // then Rodrigues on the flipped normal, which is then well conditioned.
  if (c < -0.5) {
    Eigen::Matrix3d flip;  // half turn about X: (x, y, z) -> (x, -y, -z)
    flip << 1, 0, 0, 0, -1, 0, 0, 0, -1;
    return rotation_onto_z(flip * n) * flip;
  }
  const Eigen::Vector3d v(n.y(), -n.x(), 0.0);  // n x k
  Eigen::Matrix3d V;
  V << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return Eigen::Matrix3d::Identity() + V + V * V / (1.0 + c);
}

}  // namespace pv::levelling
