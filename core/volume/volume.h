// Volume from the sequence of layer areas (Han et al. 2026, section 4.3).
//
// Decisions (copied into docs/method.md):
//
// V1 Simpson on uneven spacing. Layers are grouped in triples (0,1,2),
//    (2,3,4), ... as in the paper's (27). Cleanup removes layers, so the
//    middle layer is generally not the midpoint; the paper's (25) is then not
//    exact even for a constant-slope cone. We use the 3-point rule that is
//    exact for any quadratic S(z) on arbitrary spacing (h0 = z1 - z0,
//    h1 = z2 - z1):
//      V = (h0+h1)/6 * [(2 - h1/h0) S0 + (h0+h1)^2/(h0 h1) S1 + (2 - h0/h1) S2]
//    which reduces to (25) when h0 = h1. A cone or any solid of revolution
//    with a straight wall has quadratic S(z), so it is integrated exactly.
//    With h1/h0 > 2 an outer weight turns negative (noise is amplified, not
//    biased); cleanup removes isolated layers, so ratios stay near 1..3.
//    On sections that jump many-fold from layer to layer the sum can go
//    negative: measure() refuses a volume outside (0, 1.05 x the largest
//    section x the depth] (PV_PIT_CHECK_SECTIONS, a fuzz finding).
//
// V2 Even count. The first n-1 layers (odd) use V1, the last pair uses the
//    frustum V = h/3 (S1 + S2 + sqrt(S1 S2)) as in the paper's (26); exact for
//    a cone. n == 2 is the frustum alone. Negative areas enter the square
//    root as 0 (cleanup drops them; this only keeps a bad input finite).
//
// V3 Exact limits. Layers are centred on their grid heights, so the first
//    and last layer sit up to a layer (or more after cleanup) inside the true
//    limits (pit bottom z = 0 after levelling, rim height from the rim
//    stage). Integrating only between the first and last layer loses those
//    end slabs (~ S * 1.5 mm at each end for a 0.5 mm grid). volume_between
//    extrapolates S at each limit with a least-squares line through the
//    nearest m layers (default 8: enough to average layer noise, few enough
//    to stay local), clamps it at 0, and integrates the sequence
//    [(z_bottom, S_bot), layers..., (z_rim, S_rim)]. For a quadratic S(z) the
//    only error left is the linear extrapolation's:
//      dS_end = (S''/2) * (var_u - mean_u^2),
//    with u the distances of the m layers from the limit (population
//    variance), weighted by at most max((g+dz)/3, g/2) in the volume
//    (g = gap to the limit, dz = layer spacing).
#ifndef PV_VOLUME_VOLUME_H
#define PV_VOLUME_VOLUME_H

#include <cstddef>
#include <cstdint>

namespace pv {
namespace volume {

// Integral of area over z for layers (z_mm[i], area_mm2[i]), i < n (V1, V2).
// z strictly increasing. Returns 0 for n < 2, null pointers, non-finite input
// or z not strictly increasing (there is no volume to report).
double integrate_mm3(const double *z_mm, const double *area_mm2, size_t n);

struct Limits {
  double z_bottom_mm = 0.0;     // lower integration limit (pit bottom)
  double z_rim_mm = 0.0;        // upper integration limit (rim height)
  uint32_t end_fit_layers = 8;  // layers in each end's extrapolation line (V3), >= 1
};

// Scratch (in doubles) volume_between_mm3() needs for n layers.
size_t scratch_needed_between(size_t n);

// Volume between the exact limits (V3). Layers must lie within
// [z_bottom_mm, z_rim_mm]; a limit closer than 1e-9 mm to the outermost
// layer adds no extra point. Returns false on n < 2, invalid input
// (z not strictly increasing, non-finite, z_bottom >= z_rim, layers outside
// the limits), null pointers, or scratch_cap < scratch_needed_between(n).
bool volume_between_mm3(const double *z_mm, const double *area_mm2, size_t n,
                        const Limits &lim, double *scratch, size_t scratch_cap,
                        double *volume_mm3_out);

}  // namespace volume
}  // namespace pv

#endif
