#include "export_report.h"

#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "export_levelled.h"
#include "out_file.h"
#include "pitvol/json.h"
#include "scanio/scan_reader.h"

namespace pv::tools {

namespace {

// Heights of outline.csv, as shares of the rim height.
constexpr double kOutlineShares[] = {0.1, 0.3, 0.5, 0.7, 0.9};

// Each export file is complete or absent (out_file.h).
bool open_out(const MeasureOptions &opt, const char *name, OutFile *f, std::string *err) {
  return f->open(opt.export_dir + "/" + name, err);
}

const char *state_name(uint8_t s) {
  switch (s) {
    case PV_WALL_SEEN: return "seen";
    case PV_WALL_FLOOR: return "floor";
    case PV_WALL_SHORT_BRIDGE: return "short_bridge";
    case PV_WALL_UNSEEN: return "unseen";
    default: return "none";
  }
}

struct WallGrid {
  bool have = false;
  pv_wall_grid_t g{};
  std::vector<float> radius;
  std::vector<uint8_t> state;
  double axis_x(double z) const { return g.axis_x_mm + g.axis_dx * z; }
  double axis_y(double z) const { return g.axis_y_mm + g.axis_dy * z; }
  // Row of height z (clamped), as the model reads it.
  uint32_t row(double z) const {
    const double u = std::floor((z - g.z0_mm) / g.dz_mm);
    if (u < 0) return 0;
    return u >= g.z_bins ? g.z_bins - 1 : uint32_t(u);
  }
  // R(theta bin t, z), linear between row centres (as the model integrates).
  double radius_at(uint32_t t, double z) const {
    const double u = (z - g.z0_mm) / g.dz_mm - 0.5;
    if (u <= 0) return radius[t];
    if (u >= g.z_bins - 1) return radius[size_t(g.z_bins - 1) * g.theta_bins + t];
    const auto b = uint32_t(u);
    const double f = u - b;
    return (1 - f) * radius[size_t(b) * g.theta_bins + t] + f * radius[size_t(b + 1) * g.theta_bins + t];
  }
  // Share of a row's bins the scan did not see (bridged over a long gap).
  double unseen_share(double z) const {
    const uint32_t k = row(z);
    uint32_t n = 0;
    for (uint32_t t = 0; t < g.theta_bins; ++t) {
      const uint8_t s = state[size_t(k) * g.theta_bins + t];
      n += s == PV_WALL_UNSEEN || s == PV_WALL_NONE;
    }
    return double(n) / g.theta_bins;
  }
};

WallGrid read_wall_grid(pv_session_t *s) {
  WallGrid w;
  if (pv_session_wall_grid(s, &w.g, nullptr, nullptr, 0) != PV_OK) return w;
  const size_t n = size_t(w.g.theta_bins) * w.g.z_bins;
  w.radius.resize(n);
  w.state.resize(n);
  w.have = pv_session_wall_grid(s, &w.g, w.radius.data(), w.state.data(), n) == PV_OK;
  return w;
}

bool write_points(const MeasureOptions &opt, const pv_transform_t &tf, uint64_t count,
                  uint64_t stride, uint64_t *written, std::string *err) {
  scanio::Error rerr;
  std::unique_ptr<scanio::ScanReader> reader = scanio::open_scan(opt.path, opt.format, &rerr);
  if (!reader) {
    *err = rerr.message;
    return false;
  }
  OutFile f;
  if (!open_out(opt, "points.csv", &f, err)) return false;
  std::fprintf(f.get(), "x_mm,y_mm,z_mm\n");
  const double *R = tf.rotation, *t = tf.translation_mm;
  std::vector<pv_point_t> chunk(65536);
  uint64_t index = 0;  // among the exportable points
  *written = 0;
  for (;;) {
    const long n = reader->read(chunk.data(), chunk.size(), &rerr);
    if (n < 0) {
      *err = rerr.message;
      return false;
    }
    if (n == 0) break;
    for (long i = 0; i < n; ++i) {
      pv_point_t p = chunk[size_t(i)];
      p.x_mm = float(p.x_mm * opt.scale_to_mm);  // as run_measure() pushed it
      p.y_mm = float(p.y_mm * opt.scale_to_mm);
      p.z_mm = float(p.z_mm * opt.scale_to_mm);
      if (!exportable(p)) continue;
      if (index++ % stride != 0) continue;
      const double v[3] = {p.x_mm, p.y_mm, p.z_mm};
      double o[3];
      for (int r = 0; r < 3; ++r) o[r] = R[3 * r] * v[0] + R[3 * r + 1] * v[1] + R[3 * r + 2] * v[2] + t[r];
      std::fprintf(f.get(), "%.3f,%.3f,%.3f\n", o[0], o[1], o[2]);
      ++*written;
    }
  }
  if (index != count) {
    *err = opt.path + " changed while it was exported";
    return false;
  }
  return f.commit(err);
}

bool write_layers(const MeasureOptions &opt, const pv_session_t *s, const WallGrid &w,
                  std::string *err) {
  OutFile f;
  if (!open_out(opt, "layers.csv", &f, err)) return false;
  write_layers_rows(f.get(), s, w.have ? &w : nullptr);
  return f.commit(err);
}

bool write_coverage(const MeasureOptions &opt, const pv_result_t &r, std::string *err) {
  OutFile f;
  if (!open_out(opt, "coverage.csv", &f, err)) return false;
  std::fprintf(f.get(), "band,z_from_mm,z_to_mm,seen_share\n");
  const double h = r.depth_mm / (r.coverage_bands ? r.coverage_bands : 1);
  for (uint32_t b = 0; b < r.coverage_bands; ++b) {
    std::fprintf(f.get(), "%u,%.3f,%.3f,%.4f\n", b, b * h, (b + 1) * h, double(r.coverage[b]));
  }
  return f.commit(err);
}

bool write_wall(const MeasureOptions &opt, const WallGrid &w, std::string *err) {
  OutFile f;
  if (!open_out(opt, "wall_grid.csv", &f, err)) return false;
  std::fprintf(f.get(), "z_mm,theta_deg,radius_mm,x_mm,y_mm,state\n");
  const uint32_t T = w.g.theta_bins;
  for (uint32_t k = 0; k < w.g.z_bins; ++k) {
    const double z = w.g.z0_mm + (k + 0.5) * w.g.dz_mm;
    for (uint32_t t = 0; t < T; ++t) {
      const double th = (t + 0.5) * 2 * M_PI / T;
      const double R = w.radius[size_t(k) * T + t];
      std::fprintf(f.get(), "%.3f,%.3f,%.3f,%.3f,%.3f,%s\n", z, th * 180 / M_PI, R,
                   w.axis_x(z) + R * std::cos(th), w.axis_y(z) + R * std::sin(th),
                   state_name(w.state[size_t(k) * T + t]));
    }
  }
  if (!f.commit(err)) return false;

  if (!open_out(opt, "outline.csv", &f, err)) return false;
  std::fprintf(f.get(), "height_mm,theta_deg,radius_mm,x_mm,y_mm,state\n");
  for (double share : kOutlineShares) {
    const double z = share * w.g.rim_mm;
    const uint32_t k = w.row(z);
    for (uint32_t t = 0; t <= T; ++t) {  // closed: the first angle again
      const uint32_t tt = t % T;
      const double th = (tt + 0.5) * 2 * M_PI / T;
      const double R = w.radius_at(tt, z);
      std::fprintf(f.get(), "%.3f,%.3f,%.3f,%.3f,%.3f,%s\n", z, th * 180 / M_PI, R,
                   w.axis_x(z) + R * std::cos(th), w.axis_y(z) + R * std::sin(th),
                   state_name(w.state[size_t(k) * T + tt]));
    }
  }
  return f.commit(err);
}

bool write_model(const MeasureOptions &opt, const pv_transform_t &tf, pv_status_t tst,
                 const WallGrid &w, uint64_t count, uint64_t stride, uint64_t written,
                 std::string *err) {
  Json m = {{"method", pv_method_name(opt.cfg.method)},
            {"levelling", pv_status_name(tst)},
            {"rim_mm", tf.rim_mm},
            {"rim_from_ground", tf.rim_from_ground},
            {"rotation", tf.rotation},
            {"translation_mm", tf.translation_mm},
            {"points_exportable", count},
            {"points_stride", stride},
            {"points_written", written}};
  m["wall_grid"] = nullptr;
  if (w.have) {
    m["wall_grid"] = {{"axis_x_mm", w.g.axis_x_mm}, {"axis_y_mm", w.g.axis_y_mm},
                      {"axis_dx", w.g.axis_dx},     {"axis_dy", w.g.axis_dy},
                      {"z0_mm", w.g.z0_mm},         {"dz_mm", w.g.dz_mm},
                      {"rim_mm", w.g.rim_mm},       {"theta_bins", w.g.theta_bins},
                      {"z_bins", w.g.z_bins}};
  }
  m["outline_shares"] = kOutlineShares;
  OutFile f;
  if (!open_out(opt, "model.json", &f, err)) return false;
  std::fprintf(f.get(), "%s\n", json_lines(m).c_str());
  return f.commit(err);
}

}  // namespace

void write_layers_rows(FILE *f, const pv_session_t *s, const void *wall_grid) {
  const WallGrid *w = static_cast<const WallGrid *>(wall_grid);
  size_t n = 0;
  std::vector<pv_layer_info_t> layers(8192);
  if (pv_session_layers(s, layers.data(), layers.size(), &n) != PV_OK) n = 0;
  // The per-layer methods fit each layer's points; the surface model's
  // layers are sections of its wall grid (no points of their own, no
  // shape): their columns say what they have.
  if (w != nullptr) {
    std::fprintf(f, "z_mm,area_mm2,kept,unseen_share,bridged\n");
  } else {
    std::fprintf(f, "z_mm,area_mm2,points,kept,shape,bridged\n");
  }
  for (size_t i = 0; i < n; ++i) {
    const pv_layer_info_t &l = layers[i];
    // Bridged: the layer's section rests on wall the scan did not see
    // (surface: half its wall unseen; paper, polar: a removed layer, which
    // the volume interpolates across).
    if (w != nullptr) {
      const double u = w->unseen_share(double(l.z_mm));
      std::fprintf(f, "%.3f,%.3f,%u,%.4f,%d\n", double(l.z_mm), double(l.area_mm2), unsigned(l.kept), u,
                   u >= 0.5 ? 1 : 0);
    } else {
      std::fprintf(f, "%.3f,%.3f,%u,%u,%s,%d\n", double(l.z_mm), double(l.area_mm2), l.points,
                   unsigned(l.kept), l.shape ? "crescent" : "circular", l.kept ? 0 : 1);
    }
  }
}

bool write_layers_file(const MeasureOptions &opt, pv_session_t *s, FILE *f) {
  WallGrid w;
  pv_transform_t tf{};
  if (opt.cfg.method == PV_METHOD_SURFACE && pv_session_transform(s, &tf) == PV_OK) w = read_wall_grid(s);
  write_layers_rows(f, s, w.have ? &w : nullptr);
  return std::ferror(f) == 0;
}

bool prepare_export_dir(const std::string &dir, std::string *err) {
  if (::mkdir(dir.c_str(), 0777) == 0 || errno == EEXIST) {
    struct stat st;
    if (::stat(dir.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) return true;
    *err = dir + " exists and is not a directory";
    return false;
  }
  *err = "cannot make " + dir + ": " + std::strerror(errno);
  return false;
}

bool export_report(const MeasureOptions &opt, pv_session_t *session, const pv_result_t &r,
                   uint64_t count, const std::string &result_json, std::string *err) {
  OutFile f;
  if (!open_out(opt, "result.json", &f, err)) return false;
  std::fprintf(f.get(), "%s\n", result_json.c_str());
  if (!f.commit(err)) return false;

  pv_transform_t tf{};
  const pv_status_t tst = pv_session_transform(session, &tf);
  const bool levelled = tst == PV_OK || tst == PV_ERR_NO_RIM;
  const uint64_t stride = count <= kMaxExportPoints ? 1 : (count + kMaxExportPoints - 1) / kMaxExportPoints;
  uint64_t written = 0;
  // Without a levelling there is no frame to plot the points in.
  if (levelled && !write_points(opt, tf, count, stride, &written, err)) return false;
  // A file this export does not write must not survive from an earlier one.
  if (!levelled) std::remove((opt.export_dir + "/points.csv").c_str());
  // The wall grid exists once the surface model could be built (also for
  // a refused measurement, e.g. a wall gap: the report shows where).
  WallGrid w;
  if (opt.cfg.method == PV_METHOD_SURFACE && tst == PV_OK) w = read_wall_grid(session);
  if (!write_layers(opt, session, w, err)) return false;
  if (!write_coverage(opt, r, err)) return false;
  if (w.have && !write_wall(opt, w, err)) return false;
  if (!w.have) {
    std::remove((opt.export_dir + "/wall_grid.csv").c_str());
    std::remove((opt.export_dir + "/outline.csv").c_str());
  }
  return write_model(opt, tf, tst, w, count, stride, written, err);
}

}  // namespace pv::tools
