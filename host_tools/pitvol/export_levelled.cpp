#include "export_levelled.h"

#include "out_file.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "scanio/scan_reader.h"

namespace pv::tools {

bool exportable(const pv_point_t &p) {
  constexpr float kAbsurdMm = 1.0e6f;  // as the core's valid_point()
  return std::isfinite(p.x_mm) && std::isfinite(p.y_mm) && std::isfinite(p.z_mm) &&
         std::fabs(p.x_mm) < kAbsurdMm && std::fabs(p.y_mm) < kAbsurdMm &&
         std::fabs(p.z_mm) < kAbsurdMm;
}

bool export_levelled(const MeasureOptions &opt, pv_session_t *session, uint64_t count,
                     const std::string &out_path, std::string *err) {
  pv_transform_t tf{};
  const pv_status_t st = pv_session_transform(session, &tf);
  if (st != PV_OK && st != PV_ERR_NO_RIM) {
    *err = std::string("no levelling to export (") + pv_status_name(st) + ")";
    return false;
  }
  scanio::Error rerr;
  std::unique_ptr<scanio::ScanReader> reader = scanio::open_scan(opt.path, opt.format, &rerr);
  if (!reader) {
    *err = rerr.message;
    return false;
  }
  OutFile f;  // complete or absent
  if (!f.open(out_path, err)) return false;
  std::fprintf(f.get(), "ply\nformat binary_little_endian 1.0\n");
  std::fprintf(f.get(), "comment pitvol %s levelled cloud: bottom plane at z = 0, mm\n",
               PV_VERSION_STRING);
  std::fprintf(f.get(), "comment pitvol_rim_mm %.6f\n", tf.rim_mm);
  std::fprintf(f.get(), "comment pitvol_rim_from_ground %u\n", tf.rim_from_ground);
  std::fprintf(f.get(), "comment pitvol_transform");
  for (double v : tf.rotation) std::fprintf(f.get(), " %.17g", v);
  for (double v : tf.translation_mm) std::fprintf(f.get(), " %.17g", v);
  std::fprintf(f.get(), "\nelement vertex %llu\nproperty float x\nproperty float y\n"
                        "property float z\nend_header\n",
               (unsigned long long)count);
  const double *R = tf.rotation, *t = tf.translation_mm;
  std::vector<pv_point_t> chunk(65536);
  std::vector<float> out;
  out.reserve(3 * chunk.size());
  uint64_t written = 0;
  for (;;) {
    const long n = reader->read(chunk.data(), chunk.size(), &rerr);
    if (n < 0) {
      *err = rerr.message;
      return false;
    }
    if (n == 0) break;
    out.clear();
    for (long i = 0; i < n; ++i) {
      pv_point_t p = chunk[size_t(i)];
      p.x_mm = float(p.x_mm * opt.scale_to_mm);  // as run_measure() pushed it
      p.y_mm = float(p.y_mm * opt.scale_to_mm);
      p.z_mm = float(p.z_mm * opt.scale_to_mm);
      if (!exportable(p)) continue;
      const double v[3] = {p.x_mm, p.y_mm, p.z_mm};
      for (int r = 0; r < 3; ++r) {
        out.push_back(float(R[3 * r] * v[0] + R[3 * r + 1] * v[1] + R[3 * r + 2] * v[2] + t[r]));
      }
    }
    written += out.size() / 3;
    if (written > count) break;  // the file changed under us: caught below
    // The host is little endian (x86-64, aarch64): floats go out as they are.
    if (std::fwrite(out.data(), sizeof(float), out.size(), f.get()) != out.size()) break;
  }
  if (written != count && std::ferror(f.get()) == 0) {
    *err = opt.path + " changed while it was exported";
    return false;
  }
  return f.commit(err);
}

}  // namespace pv::tools
