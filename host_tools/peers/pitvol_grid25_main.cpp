// pitvol-grid25: the reference 2.5D grid volume (grid25.h) of a cloud
// written by `pitvol measure FILE --export-levelled OUT.ply`.
//
//   pitvol-grid25 LEVELLED.ply [--cell-mm 1] [--rim-mm Z] [--median]
// Prints one JSON object; exit 0 measured, 2 usage, 3 unreadable, 4 no volume.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "grid25.h"

int main(int argc, char **argv) {
  std::string path;
  double rim_override = -1;
  pv::peers::Grid25Params p;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--cell-mm" && i + 1 < argc) p.cell_mm = std::atof(argv[++i]);
    else if (a == "--rim-mm" && i + 1 < argc) rim_override = std::atof(argv[++i]);
    else if (a == "--median") p.median = true;
    else if (path.empty() && a.rfind("--", 0) != 0) path = a;
    else {
      std::fprintf(stderr, "usage: pitvol-grid25 LEVELLED.ply [--cell-mm 1] [--rim-mm Z] [--median]\n");
      return 2;
    }
  }
  if (path.empty() || !(p.cell_mm > 0)) {
    std::fprintf(stderr, "usage: pitvol-grid25 LEVELLED.ply [--cell-mm 1] [--rim-mm Z] [--median]\n");
    return 2;
  }
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<pv::peers::LevelledPoint> pts;
  double rim = 0;
  std::string err;
  if (!pv::peers::read_levelled_ply(path, &pts, &rim, &err)) {
    std::fprintf(stderr, "pitvol-grid25: %s\n", err.c_str());
    return 3;
  }
  if (rim_override > 0) rim = rim_override;
  const pv::peers::Grid25Result r = pv::peers::grid25_volume(pts, rim, p);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (!r.ok) {
    std::printf("{\"status\": \"refused\", \"message\": \"%s\", \"volume_cm3\": null, \"ms\": %.1f}\n",
                r.error.c_str(), ms);
    return 4;
  }
  std::printf("{\"status\": \"ok\", \"volume_cm3\": %.6f, \"rim_mm\": %.4f, \"cell_mm\": %g, "
              "\"pit_cells\": %llu, \"filled_cells\": %llu, \"empty_sectors\": %u, \"ms\": %.1f}\n",
              r.volume_cm3, rim, p.cell_mm, (unsigned long long)r.pit_cells,
              (unsigned long long)r.filled_cells, r.empty_sectors, ms);
  return 0;
}
