// Outlier removal on the layer-area sequence: MAD over sliding windows
// (Han et al. 2026, section 4.2, Algorithm 2).
//
// Decisions (copied into docs/method.md):
//
// C1 Order and segments. Input is ascending height above the pit bottom.
//    The paper's sequence runs from the rim downward (its z is depth), so
//    "z_max - 30 mm" is 30 mm above the deepest layer: that is where the area
//    contracts fast (the paper's late, "gradual" segment). We walk the
//    sequence in the paper's order, rim first. Early/stable segment: layers
//    more than split_mm (30) above the lowest layer -> window_early (10),
//    k_early. Late segment: the lowest split_mm -> window_late (6), k_late.
//    The split is relative to the lowest layer, as the paper's z_max is.
//
// C2 Windows. Default: centred window [j - (W-1)/2, j + W/2], clamped
//    inside the sequence, so the first layers use the first W values and the
//    last ones the last W (the paper's boundary windows fall out of the
//    clamp). Option centred = false: the paper's trailing window [j-W+1, j]
//    with the first 3 / last 3 rule. Why centred: a layer at the end of its
//    window sits (W-1)/2 steps of trend and ~W^2/8 steps^2 of curvature away
//    from the window median; measured with the trailing window, a smooth
//    quadratic contraction into the bottom lost 5 good layers per run.
//
// C3 Threshold. |S - median(W)| > k * sigma rejects, with
//    sigma = max(1.4826 * MAD, mad_floor_ratio * |median|, sigma_global).
//    1.4826 makes sigma the standard deviation for Gaussian noise, so k is in
//    sigmas. The ratio floor (default 1e-4 = 0.01 % of the area, well below
//    the ~0.1 % accuracy of one layer's area fit) keeps a constant sequence
//    (MAD = 0) from rejecting values that differ in the last bits.
//
// C4 k defaults: k_early = 4.5, k_late = 3.5, early high / late low as the
//    paper says. Measured false loss on pure Gaussian noise (300 layers x 200
//    seeds, defaults otherwise): 0.000 % early (W=10, k=4.5) and 0.098 % late
//    (W=6, k=3.5); with the paper's literal algorithm the same k lose 0.7 %
//    and 3.1 %, because a 6-value MAD is often near 0. A spike must exceed
//    ~4.5 sigma of the layer noise to be removed in the stable segment; in the
//    late segment a lower k catches smaller spikes on the steep contraction.
//
// C5 Marks are decided on the original sequence in one pass (not
//    iteratively): a removed layer's neighbours are judged with it still in
//    their windows, the median/MAD being robust to it. Negative or
//    non-finite areas are removed first and are not part of any window.
//
// C6 Detrend (default on). Before median/MAD, the window's robust slope
//    (median of adjacent-pair slopes, area per mm) is removed about the
//    layer's height. Why: on a steep contraction the raw MAD is set by the
//    trend, not the noise (linear step s: MAD = 1.5 s in a 6-window), so a
//    +3 % spike on the cone's bottom passes the paper's test (see the test
//    test_paper_mode_misses_spikes_on_trend). After detrending the MAD is the
//    noise again and the trend itself is never an outlier.
//
// C7 Noise floor (default on). sigma_global = 1.4826 * median|d2| / sqrt(6)
//    over the whole sequence, d2 the second differences (scaled to unit steps
//    on uneven spacing): i.i.d. noise of std sigma gives d2 std sqrt(6) sigma,
//    while a smooth profile's trend and curvature nearly cancel. It stops a
//    window whose 6 values happen to agree closely from rejecting a normal
//    layer (the main cause of false loss with small windows).
//
// Known limit: a sharp kink (slope change >> noise within one layer) is
//    handled by C2 + C6 in the tests (flat wall into a linear contraction),
//    but a curvature much larger than the noise over a few layers can still
//    remove a layer there; such a layer is then bridged by the volume's
//    uneven-spacing Simpson rule.
#ifndef PV_CLEANUP_MAD_FILTER_H
#define PV_CLEANUP_MAD_FILTER_H

#include <cstddef>
#include <cstdint>

namespace pv {
namespace cleanup {

constexpr uint32_t kMaxWindow = 64;  // window buffers live on the stack

struct Params {
  uint32_t window_early = 10;     // W_pre, stable segment (C1), 1..kMaxWindow
  uint32_t window_late = 6;       // W_post, last split_mm above the bottom
  double k_early = 4.5;           // C4
  double k_late = 3.5;            // C4
  double split_mm = 30.0;         // H_split above the lowest layer (C1)
  double mad_floor_ratio = 1e-4;  // sigma floor as a fraction of |median| (C3)
  bool detrend = true;            // remove the window's robust slope first (C6); false = paper
  bool centred = true;            // window centred on the layer (C2); false = paper's trailing
  bool global_noise_floor = true; // sigma >= sequence-wide noise estimate (C7); false = paper
};

// Scratch (in doubles) mad_filter() needs for n layers.
size_t scratch_needed(size_t n);

// Marks keep_out[i] = 1 for layers kept, 0 for removed (negative, non-finite,
// or outside the MAD threshold). z_mm ascending (height above the bottom).
// Returns the number kept; 0 with keep_out all zero when scratch is too
// small, a pointer is null or a window is 0 / above kMaxWindow.
size_t mad_filter(const double *z_mm, const double *area_mm2, size_t n, const Params &p,
                  uint8_t *keep_out, double *scratch, size_t scratch_cap);

}  // namespace cleanup
}  // namespace pv

#endif
