// pitvol-synth: writes a deterministic synthetic pit scan as binary PLY and
// prints its exact volume. Used to make the bundled sample scan at build time.
//
//   pitvol-synth OUT.ply [--points N] [--seed S] [--radius MM] [--depth MM]
//                [--tilt DEG] [--no-ground] [--upside-down]
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "synth/synthetic_pit.h"

namespace {

const char kUsage[] =
    "usage: pitvol-synth OUT.ply [--points N] [--seed S] [--radius MM]\n"
    "                    [--depth MM] [--tilt DEG] [--no-ground] [--upside-down]\n"
    "       pitvol-synth --help\n";

int usage() {
  std::fputs(kUsage, stderr);
  return 2;
}

bool parse_double(const char *s, double *out) {
  char *end = nullptr;
  *out = std::strtod(s, &end);
  return end != s && *end == '\0';
}

}  // namespace

int main(int argc, char **argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
      std::fputs(kUsage, stdout);
      return 0;
    }
  }
  if (argc < 2) return usage();
  const char *path = nullptr;
  long long points = 300000;
  pv::synth::PitSpec spec;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    double v = 0;
    const bool has_value = i + 1 < argc;
    if (a == "--points" && has_value && parse_double(argv[i + 1], &v) && v >= 1) {
      points = (long long)v;
      ++i;
    } else if (a == "--seed" && has_value && parse_double(argv[i + 1], &v) && v >= 0) {
      spec.seed = (uint64_t)v;
      ++i;
    } else if (a == "--radius" && has_value && parse_double(argv[i + 1], &v) && v > 0) {
      spec.radius_bottom_mm = spec.radius_top_mm = v;
      ++i;
    } else if (a == "--depth" && has_value && parse_double(argv[i + 1], &v) && v > 0) {
      spec.depth_mm = v;
      ++i;
    } else if (a == "--tilt" && has_value && parse_double(argv[i + 1], &v)) {
      spec.tilt_deg = v;
      ++i;
    } else if (a == "--no-ground") {
      spec.ground_width_mm = 0;
    } else if (a == "--upside-down") {
      spec.upside_down = true;
    } else if (a[0] != '-' && path == nullptr) {
      path = argv[i];
    } else {
      std::fprintf(stderr, "pitvol-synth: unknown or incomplete option '%s'\n", argv[i]);
      return usage();
    }
  }
  if (path == nullptr) return usage();
  if (!pv::synth::write_scan_ply(path, spec, uint64_t(points))) {
    std::fprintf(stderr, "pitvol-synth: cannot write %s\n", path);
    return 3;
  }
  std::printf("%s: %lld points, exact volume %.3f cm3\n", path, points,
              pv::synth::exact_volume_cm3(spec));
  return 0;
}
