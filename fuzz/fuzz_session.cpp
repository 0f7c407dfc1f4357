// The core session on arbitrary floats, batch sizes and estimate/finish
// points.
//
// Two binaries: fuzz_session (methods paper and polar, bit 0 of the seed
// picks one) and fuzz_session_surface (PV_FUZZ_SURFACE: the default method
// surface, in its own binary so that it gets its own budget and figures;
// bit 0 of the seed picks its fine or its coarse grids:
// fuzz_session_config.h).
//
// Input: 8 bytes of seed (draws batch sizes and where estimate() is
// called), then 12 bytes per point (three raw floats: NaN, infinities and
// denormals included). A small configuration (fuzz_session_config.h) keeps
// an execution short and its bins thinning.
//
// Invariants beyond "no crash":
// - batching does not matter: the same points with estimate() at the same
//   places but other batch boundaries give the same statuses and the same
//   volumes, bit for bit;
// - a PV_OK result (estimate or finish) has a finite, positive volume no
//   larger than 6 x the cube of the points' extent, and at least 12 layers;
// - a refusal carries no volume;
// - after finish(), push/estimate/finish answer PV_ERR_WRONG_STATE.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "fuzz_session_config.h"
#include "fuzz_support.h"
#include "pitvol/pitvol.h"

namespace {

using pv::fuzz::Grids;

struct Block {
  pv_config_t cfg;
  void *mem = nullptr;
  pv_session_t *s = nullptr;
  explicit Block(pv_method_t m, Grids grids = Grids::Default) {
    pv::fuzz::session_config(&cfg, m, grids);
    size_t bytes = 0;
    if (pv_session_size(&cfg, &bytes) != PV_OK) std::abort();
    mem = std::aligned_alloc(PV_BLOCK_ALIGN, (bytes + PV_BLOCK_ALIGN - 1) / PV_BLOCK_ALIGN * PV_BLOCK_ALIGN);
    if (mem == nullptr || pv_session_init(&cfg, mem, bytes, &s) != PV_OK) std::abort();
  }
};

struct Run {
  std::vector<pv_status_t> statuses;
  std::vector<double> volumes;
};

double g_bound_cm3 = 0;

void check_result(pv_status_t st, const pv_result_t &r) {
  if (st == PV_OK) {
    PV_FUZZ_CHECK(std::isfinite(r.volume_cm3) && r.volume_cm3 > 0, "PV_OK volume %g", r.volume_cm3);
    PV_FUZZ_CHECK(r.volume_cm3 <= g_bound_cm3, "volume %g cm3 beyond the bound %g", r.volume_cm3,
                  g_bound_cm3);
    PV_FUZZ_CHECK(std::isfinite(r.depth_mm) && r.depth_mm > 0, "PV_OK depth %g", r.depth_mm);
    PV_FUZZ_CHECK(r.layers_used >= 12, "PV_OK with %u layers", r.layers_used);
  } else {
    PV_FUZZ_CHECK(r.volume_cm3 == 0, "status %s with volume %g", pv_status_name(st), r.volume_cm3);
  }
}

// Pushes pts with estimate() before the points listed in estimate_at; the
// batch sizes come from draw (max_batch 0: one batch per segment).
Run run(pv_session_t *s, const std::vector<pv_point_t> &pts, const std::vector<size_t> &estimate_at,
        pv::fuzz::Draw draw, size_t max_batch) {
  Run out;
  PV_FUZZ_CHECK(pv_session_reset(s) == PV_OK, "reset failed");
  size_t at = 0, next_est = 0;
  while (at < pts.size() || next_est < estimate_at.size()) {
    if (next_est < estimate_at.size() && estimate_at[next_est] == at) {
      pv_result_t r{};
      const pv_status_t st = pv_session_estimate(s, &r);
      check_result(st, r);
      out.statuses.push_back(st);
      out.volumes.push_back(r.volume_cm3);
      ++next_est;
      continue;
    }
    const size_t seg_end = next_est < estimate_at.size() ? estimate_at[next_est] : pts.size();
    size_t n = seg_end - at;
    if (max_batch > 0) n = std::min(n, 1 + draw.below(max_batch));
    PV_FUZZ_CHECK(pv_session_push(s, pts.data() + at, n) == PV_OK, "push failed");
    at += n;
  }
  pv_result_t r{};
  const pv_status_t st = pv_session_finish(s, &r);
  check_result(st, r);
  out.statuses.push_back(st);
  out.volumes.push_back(r.volume_cm3);
  pv_result_t again{};
  PV_FUZZ_CHECK(pv_session_finish(s, &again) == PV_ERR_WRONG_STATE, "finish twice");
  PV_FUZZ_CHECK(pv_session_estimate(s, &again) == PV_ERR_WRONG_STATE, "estimate after finish");
  PV_FUZZ_CHECK(pv_session_push(s, pts.data(), 0) == PV_ERR_WRONG_STATE, "push after finish");
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
#ifdef PV_FUZZ_SURFACE
  static Block fine(PV_METHOD_SURFACE, Grids::Fine), coarse(PV_METHOD_SURFACE, Grids::Coarse);
#else
  // The fine grids for the surface model that paper's and polar's
  // plausibility checks build (the default's would double an execution).
  static Block paper(PV_METHOD_PAPER, Grids::Fine), polar(PV_METHOD_POLAR, Grids::Fine);
#endif
  if (size < 8) return 0;
  uint64_t seed;
  const std::vector<pv_point_t> pts = pv::fuzz::input_points(data, size, &seed);

  // The bound for a PV_OK volume: 6 x the cube of the largest extent of the
  // points the core would accept.
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (const pv_point_t &p : pts) {
    const float v[3] = {p.x_mm, p.y_mm, p.z_mm};
    bool ok = true;
    for (float c : v) ok = ok && std::isfinite(c) && std::fabs(c) < 1.0e6f;
    if (!ok) continue;
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::fmin(lo[a], double(v[a]));
      hi[a] = std::fmax(hi[a], double(v[a]));
    }
  }
  double extent = 0;
  for (int a = 0; a < 3; ++a) extent = std::fmax(extent, hi[a] - lo[a]);
  g_bound_cm3 = 6.0 * extent * extent * extent / 1000.0;

  pv::fuzz::Draw draw{seed};
  std::vector<size_t> estimate_at;
  for (int k = int(draw.below(4)); k > 0; --k) estimate_at.push_back(draw.below(pts.size() + 1));
  std::sort(estimate_at.begin(), estimate_at.end());
#ifdef PV_FUZZ_SURFACE
  pv_session_t *s = (seed & 1) ? coarse.s : fine.s;
#else
  pv_session_t *s = (seed & 1) ? polar.s : paper.s;
#endif
  const Run a = run(s, pts, estimate_at, pv::fuzz::Draw{seed ^ 0x1234}, 1 + draw.below(500));
  const Run b = run(s, pts, estimate_at, pv::fuzz::Draw{seed}, 0);
  PV_FUZZ_CHECK(a.statuses == b.statuses, "statuses differ with other batch sizes");
  PV_FUZZ_CHECK(std::memcmp(a.volumes.data(), b.volumes.data(), a.volumes.size() * sizeof(double)) == 0,
                "volumes differ with other batch sizes");
  return 0;
}
