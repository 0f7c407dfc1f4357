// The same points give the same statuses and volumes whatever the block held
// before pv_session_init() (a reused block, an earlier scan's values): the
// core must read only what it wrote.
//
// The regression input (fuzz/corpus/session/regression-stale-wall-values,
// a finding of fuzz_session_surface, issue 9): a cloud whose sparse wall
// bins were all rejected as outliers left the wall grid with no seen bin,
// and the volume was integrated from values no build had written. Its first
// live estimate read PV_ERR_NOT_A_PIT on a zeroed block and PV_ERR_WALL_GAP
// on one filled with 50.0f, and the batching invariant failed on one filled
// with 20.0f.
#include <cstdio>
#include <cstring>
#include <vector>

#include "session_support.h"
#include "pv_cmocka.h"  // last: see pv_cmocka.h

namespace {

// The fuzz harness's fine-grid configuration (fuzz/fuzz_session.cpp).
void fine_grids(pv_config_t *c) {
  c->max_layers = 64;
  c->layer_mm = 2.0f;
  c->points_per_layer = 64;
  c->level_sample_points = 256;
  c->warmup_points = 256;
  c->ransac_iterations = 16;
  c->surface_theta_bins = 90;
  c->surface_cell_mm = 4.0f;
  c->surface_max_radius_mm = 160.0f;
  c->surface_floor_points = 4096;
}

// Every estimate and the finish, in order.
struct Outcome {
  std::vector<pv_status_t> status;
  std::vector<double> volume;
};

// A block filled with value (as floats) before init, then the points with
// an estimate after the first estimate_at[i] of them, then the finish.
Outcome run(void (*tweak)(pv_config_t *), float value, const std::vector<pv_point_t> &pts,
            const std::vector<size_t> &estimate_at) {
  pv_config_t cfg;
  pv_config_default(&cfg);
  if (tweak != nullptr) tweak(&cfg);
  size_t bytes = 0;
  assert_int_equal(pv_session_size(&cfg, &bytes), PV_OK);
  std::vector<float> mem((bytes + PV_BLOCK_ALIGN) / sizeof(float) + PV_BLOCK_ALIGN, value);
  auto addr = reinterpret_cast<uintptr_t>(mem.data());
  void *block = reinterpret_cast<void *>((addr + PV_BLOCK_ALIGN - 1) / PV_BLOCK_ALIGN * PV_BLOCK_ALIGN);
  pv_session_t *s = nullptr;
  assert_int_equal(pv_session_init(&cfg, block, bytes, &s), PV_OK);
  Outcome o;
  size_t at = 0;
  for (size_t until : estimate_at) {
    assert_int_equal(pv_session_push(s, pts.data() + at, until - at), PV_OK);
    at = until;
    pv_result_t r{};
    o.status.push_back(pv_session_estimate(s, &r));
    o.volume.push_back(r.volume_cm3);
  }
  assert_int_equal(pv_session_push(s, pts.data() + at, pts.size() - at), PV_OK);
  pv_result_t r{};
  o.status.push_back(pv_session_finish(s, &r));
  o.volume.push_back(r.volume_cm3);
  return o;
}

void expect_same(const Outcome &a, const Outcome &b, float value) {
  assert_int_equal(a.status.size(), b.status.size());
  for (size_t i = 0; i < a.status.size(); ++i) {
    if (a.status[i] != b.status[i] ||
        std::memcmp(&a.volume[i], &b.volume[i], sizeof(double)) != 0) {
      fail_msg("call %zu: %s %.9f on a zeroed block, %s %.9f on one filled with %g", i,
               pv_status_name(a.status[i]), a.volume[i], pv_status_name(b.status[i]),
               b.volume[i], double(value));
    }
  }
}

std::vector<pv_point_t> regression_points() {
  std::FILE *f = std::fopen(PV_REGRESSION_INPUT, "rb");
  assert_non_null(f);
  std::vector<unsigned char> bytes;
  unsigned char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) bytes.insert(bytes.end(), buf, buf + n);
  std::fclose(f);
  assert_true(bytes.size() > 8);
  // The harness's input: 8 bytes of seed, then three raw floats a point.
  std::vector<pv_point_t> pts((bytes.size() - 8) / 12);
  std::memcpy(pts.data(), bytes.data() + 8, pts.size() * 12);
  return pts;
}

void test_rejected_wall_reads_no_stale_values(void **) {
  const std::vector<pv_point_t> pts = regression_points();
  assert_int_equal(pts.size(), 3689);
  // Where the harness estimated (its seed's draws), and every 500 points.
  std::vector<size_t> every;
  for (size_t at = 500; at < pts.size(); at += 500) every.push_back(at);
  for (const std::vector<size_t> &at : {std::vector<size_t>{1256, 2691}, every}) {
    const Outcome zero = run(fine_grids, 0.0f, pts, at);
    for (float value : {20.0f, 50.0f, 100.0f, -1.0f}) {
      expect_same(zero, run(fine_grids, value, pts, at), value);
    }
  }
}

// A real pit, default configuration: the same figures on a dirty block.
void test_pit_same_on_a_dirty_block(void **) {
  pv::synth::PitSpec spec;
  const std::vector<pv_point_t> pts = scan_points(spec, 120000);
  const std::vector<size_t> at = {40000, 80000};
  const Outcome zero = run(nullptr, 0.0f, pts, at);
  assert_int_equal(zero.status.back(), PV_OK);
  for (float value : {50.0f, 250.0f}) expect_same(zero, run(nullptr, value, pts, at), value);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_rejected_wall_reads_no_stale_values),
      cmocka_unit_test(test_pit_same_on_a_dirty_block),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
