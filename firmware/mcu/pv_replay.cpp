// pv-replay: streams binary PLY scans through the core and prints every
// result field as its exact bits, so runs on different targets can be
// compared with diff (the same-bits test, docs/targets.md). One portable
// source for every target: hosted Linux (x86-64, aarch64 under qemu-user)
// and the bare-metal Cortex-M7 app (newlib, files and arguments through
// semihosting under qemu-system-arm).
//
//   pv-replay [--mcu-config] [--method NAME] SCAN.ply ...
//   pv-replay [--mcu-config] [--method NAME] --block-size   (pv_session_size,
//                                                         for the size report)
//
// Lines starting with '#' are for people (decimal values, block size);
// every other line is "name hex-bits" and must match across targets.
// The session block is a static array: no heap on any target.
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pitvol/pitvol.h"
#include "ply_points.h"

#ifndef PV_REPLAY_BLOCK_BYTES
#define PV_REPLAY_BLOCK_BYTES (48u * 1024u * 1024u)  // hosted: the default config (30.5 MB)
#endif

#if defined(PV_REPLAY_BARE_METAL)
// The linker script places .pv_block in a region of exactly
// PV_MCU_BLOCK_BYTES: a bigger array fails the link; a configuration that
// needs more than the array is refused by pv_session_init.
#define PV_BLOCK_SECTION __attribute__((section(".pv_block")))
#else
#define PV_BLOCK_SECTION
#endif

namespace {

alignas(PV_BLOCK_ALIGN) PV_BLOCK_SECTION unsigned char g_block[PV_REPLAY_BLOCK_BYTES];

constexpr size_t kBatchPoints = 4096;
pv_point_t g_batch[kBatchPoints];
pv_layer_info_t g_layers[2048];  // max_layers of both configurations (1920, 200)

// Hex printing by hand: newlib's printf may lack %a and long long.
void put_hex(const char *name, uint64_t v, int digits) {
  char buf[17];
  for (int i = digits - 1; i >= 0; --i) {
    buf[i] = "0123456789abcdef"[v & 0xf];
    v >>= 4;
  }
  buf[digits] = '\0';
  printf("%s %s\n", name, buf);
}

void put_double(const char *name, double d) {
  uint64_t bits;
  memcpy(&bits, &d, sizeof bits);
  put_hex(name, bits, 16);
}

void put_float(const char *name, float f) {
  uint32_t bits;
  memcpy(&bits, &f, sizeof bits);
  put_hex(name, bits, 8);
}

// FNV-1a over the per-layer detail, field by field (no padding bytes).
struct Fnv {
  uint64_t h = 1469598103934665603ull;
  void add(const void *p, size_t n) {
    const unsigned char *b = static_cast<const unsigned char *>(p);
    for (size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  }
};

uint64_t layers_hash(const pv_session_t *s, uint32_t *count_out) {
  Fnv f;
  size_t n = 0;
  const pv_status_t st = pv_session_layers(s, g_layers, sizeof g_layers / sizeof g_layers[0], &n);
  if (st != PV_OK) printf("# layers: %s\n", pv_status_message(st));
  for (size_t i = 0; i < n; ++i) {
    const pv_layer_info_t &li = g_layers[i];
    f.add(&li.z_mm, sizeof li.z_mm);
    f.add(&li.area_mm2, sizeof li.area_mm2);
    f.add(&li.points, sizeof li.points);
    f.add(&li.kept, sizeof li.kept);
    f.add(&li.shape, sizeof li.shape);
  }
  *count_out = static_cast<uint32_t>(n);
  return f.h;
}

void print_result(const pv_result_t &r) {
  printf("# status %s volume_cm3 %.6f depth_mm %.3f layers %u interval_cm3 %.6f\n",
         pv_status_name(r.status), r.volume_cm3, r.depth_mm, static_cast<unsigned>(r.layers_used),
         r.interval_cm3);
  put_hex("status", static_cast<uint32_t>(r.status), 8);
  put_double("volume_cm3", r.volume_cm3);
  put_double("depth_mm", r.depth_mm);
  put_double("tilt_deg", r.tilt_deg);
  put_double("rim_area_mm2", r.rim_area_mm2);
  put_double("gap_from_mm", r.gap_from_mm);
  put_double("gap_to_mm", r.gap_to_mm);
  put_hex("layers_used", r.layers_used, 8);
  put_hex("layers_rejected", r.layers_rejected, 8);
  put_hex("points_in", r.points_in, 16);
  put_hex("points_invalid", r.points_invalid, 16);
  put_hex("points_out_of_range", r.points_out_of_range, 16);
  put_hex("points_stored", r.points_stored, 16);
  put_hex("points_used", r.points_used, 16);
  put_hex("warnings", r.warnings, 8);
  put_double("interval_cm3", r.interval_cm3);
  put_double("unseen_share", r.unseen_share);
  put_hex("coverage_bands", r.coverage_bands, 8);
  char name[32];
  for (int b = 0; b < PV_COVERAGE_BANDS; ++b) {
    snprintf(name, sizeof name, "coverage[%d]", b);
    put_float(name, r.coverage[b]);
  }
  put_hex("failed_check", r.failed_check, 8);
  put_double("check_value", r.check_value);
  put_double("check_limit", r.check_limit);
}

const char *base_name(const char *path) {
  const char *b = strrchr(path, '/');
  return b ? b + 1 : path;
}

// Replays one scan; returns false when the file cannot be read.
bool replay(const char *path, const pv_config_t &cfg) {
  pv::firmware::PlyPoints ply;
  if (!ply.open(path)) {
    printf("# %s: %s\n", path, ply.error());
    return false;
  }
  pv_session_t *s = nullptr;
  const pv_status_t st = pv_session_init(&cfg, g_block, sizeof g_block, &s);
  if (st != PV_OK) {
    printf("# session init: %s\n", pv_status_message(st));
    return false;
  }
  size_t n;
  while ((n = ply.read(g_batch, kBatchPoints)) > 0) {
    const pv_status_t pst = pv_session_push(s, g_batch, n);
    if (pst != PV_OK) {
      printf("# %s: push: %s\n", path, pv_status_message(pst));
      return false;
    }
  }
  if (ply.error() != nullptr) {
    printf("# %s: %s\n", path, ply.error());
    return false;
  }
  // A refused scan is a result like a measured one: its status is printed
  // with it. Only a call the session could not take leaves r unset.
  pv_result_t r{};
  const pv_status_t fst = pv_session_finish(s, &r);
  if (fst != r.status) {
    printf("# %s: finish: %s\n", path, pv_status_message(fst));
    return false;
  }
  printf("scan %s\n", base_name(path));
  print_result(r);
  uint32_t layers = 0;
  const uint64_t h = layers_hash(s, &layers);
  put_hex("layer_detail_fnv", h, 16);
  put_hex("layer_detail_count", layers, 8);
  return true;
}

}  // namespace

int main(int argc, char **argv) {
  pv_config_t cfg;
  pv_config_default(&cfg);
  int first = 1;
  if (argc > 1 && strcmp(argv[1], "--mcu-config") == 0) {
    pv_config_mcu(&cfg);
    first = 2;
  }
  // The per-layer methods too: every method's bits must match (no libm in
  // the core, toolchain/check-core-libm.sh).
  if (first + 1 < argc && strcmp(argv[first], "--method") == 0) {
    if (pv_method_from_name(argv[first + 1], &cfg.method) != PV_OK) {
      printf("pv-replay: unknown method '%s' (surface, paper or polar)\n", argv[first + 1]);
      return 2;
    }
    first += 2;
  }
  if (first >= argc) {
    printf("usage: pv-replay [--mcu-config] [--method NAME] SCAN.ply ... | --block-size\n");
    return 2;
  }
  size_t need = 0;
  const pv_status_t sst = pv_session_size(&cfg, &need);
  if (sst != PV_OK) {
    printf("pv-replay: the configuration has no block size: %s\n", pv_status_message(sst));
    return 2;
  }
  if (strcmp(argv[first], "--block-size") == 0) {
    printf("block_bytes %lu\n", static_cast<unsigned long>(need));
    return 0;
  }
  printf("# block %lu bytes of %lu\n", static_cast<unsigned long>(need),
         static_cast<unsigned long>(sizeof g_block));
  int failed = 0;
  for (int i = first; i < argc; ++i)
    if (!replay(argv[i], cfg)) ++failed;
  printf("# done, %d failed\n", failed);
  return failed == 0 ? 0 : 1;
}
