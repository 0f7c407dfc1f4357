#include "config_file.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sys/stat.h>

#include <cstdio>
#include <cstring>
#include <sstream>

namespace pv::tools {

namespace {

struct Field {
  const char *name;
  float pv_config_t::*f;
  uint32_t pv_config_t::*u;
};

// Every tunable field, by the name docs/method.md uses.
const Field kFields[] = {
    {"max_layers", nullptr, &pv_config_t::max_layers},
    {"points_per_layer", nullptr, &pv_config_t::points_per_layer},
    {"level_sample_points", nullptr, &pv_config_t::level_sample_points},
    {"warmup_points", nullptr, &pv_config_t::warmup_points},
    {"layer_mm", &pv_config_t::layer_mm, nullptr},
    {"bottom_band_ratio", &pv_config_t::bottom_band_ratio, nullptr},
    {"plane_tol_ratio", &pv_config_t::plane_tol_ratio, nullptr},
    {"ransac_iterations", nullptr, &pv_config_t::ransac_iterations},
    {"rim_band_ratio", &pv_config_t::rim_band_ratio, nullptr},
    {"knn_k", nullptr, &pv_config_t::knn_k},
    {"thin_base_mm", &pv_config_t::thin_base_mm, nullptr},
    {"crescent_range_mm", &pv_config_t::crescent_range_mm, nullptr},
    {"crescent_cross_mm", &pv_config_t::crescent_cross_mm, nullptr},
    {"circle_band_mm", &pv_config_t::circle_band_mm, nullptr},
    {"crescent_relax_mm", &pv_config_t::crescent_relax_mm, nullptr},
    {"mad_window_early", nullptr, &pv_config_t::mad_window_early},
    {"mad_window_late", nullptr, &pv_config_t::mad_window_late},
    {"mad_k_early", &pv_config_t::mad_k_early, nullptr},
    {"mad_k_late", &pv_config_t::mad_k_late, nullptr},
    {"mad_split_mm", &pv_config_t::mad_split_mm, nullptr},
    {"max_unseen_share", &pv_config_t::max_unseen_share, nullptr},
    {"max_opening_tilt_deg", &pv_config_t::max_opening_tilt_deg, nullptr},
    {"duplicate_filter", nullptr, &pv_config_t::duplicate_filter},
    {"surface_floor_points", nullptr, &pv_config_t::surface_floor_points},
    {"surface_theta_bins", nullptr, &pv_config_t::surface_theta_bins},
    {"surface_wall_dz_mm", &pv_config_t::surface_wall_dz_mm, nullptr},
    {"surface_cell_mm", &pv_config_t::surface_cell_mm, nullptr},
    {"surface_max_radius_mm", &pv_config_t::surface_max_radius_mm, nullptr},
    {"surface_band_mm", &pv_config_t::surface_band_mm, nullptr},
    {"surface_coarse_bins", nullptr, &pv_config_t::surface_coarse_bins},
};

std::string trim(const std::string &s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

// "setting 'X' = V is out of range", with the numbers that make it so.
std::string out_of_range_message(const pv_config_t &cfg, const char *bad) {
  const std::string name = bad ? bad : "?";
  std::string value;
  for (const Field &c : kFields) {
    if (name != c.name) continue;
    value = c.u ? std::to_string(cfg.*(c.u)) : number(double(cfg.*(c.f)));
  }
  std::string msg = "setting '" + name + "'" + (value.empty() ? "" : " = " + value) + " is out of range";
  const uint64_t slots = uint64_t(cfg.max_layers) * cfg.points_per_layer;
  if (name == "points_per_layer" && cfg.points_per_layer >= 64 && cfg.points_per_layer <= (1u << 20)) {
    // In range alone: the product with max_layers is what is too large.
    msg += ": max_layers x points_per_layer = " + std::to_string(slots) +
           " point slots would need about " + std::to_string(slots * 16 >> 20) +
           " MiB of session memory; the limit is 67108864 slots (1 GiB): lower one of them";
  } else {
    msg += " (docs/method.md gives the allowed ranges)";
  }
  return msg;
}

// A configuration file is a few dozen short lines. Reading is bounded so
// that /dev/zero, a FIFO or a huge file cannot make the tool grow without
// limit: the first kMaxConfigBytes + 1 bytes decide.
constexpr size_t kMaxConfigBytes = 64 * 1024;
constexpr size_t kMaxLineBytes = 1024;

bool read_bounded(const std::string &path, std::string *text, std::string *error) {
  struct stat st{};
  if (::stat(path.c_str(), &st) != 0) {
    *error = path + ": cannot open the configuration file (" + std::strerror(errno) + ")";
    return false;
  }
  if (S_ISDIR(st.st_mode)) {
    *error = path + ": is a directory, not a configuration file";
    return false;
  }
  FILE *f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) {
    *error = path + ": cannot open the configuration file (" + std::strerror(errno) + ")";
    return false;
  }
  // In small pieces: a configuration is a few hundred bytes, and filling a
  // 64 KiB string for each one was most of the parse.
  text->clear();
  char piece[4096];
  size_t n = 0;
  while (text->size() <= kMaxConfigBytes && (n = std::fread(piece, 1, sizeof piece, f)) > 0) {
    text->append(piece, n);
  }
  const bool read_error = std::ferror(f) != 0;
  std::fclose(f);
  if (read_error) {
    *error = path + ": cannot read the configuration file";
    return false;
  }
  if (text->size() > kMaxConfigBytes) {
    *error = path + ": larger than " + std::to_string(kMaxConfigBytes) +
             " bytes; a configuration file is a few 'key = value' lines";
    return false;
  }
  return true;
}

}  // namespace

bool load_config_file(const std::string &path, pv_config_t *cfg, std::string *error) {
  std::string text;
  if (!read_bounded(path, &text, error)) return false;
  std::istringstream in(text);
  std::string line;
  int lineno = 0;
  auto fail = [&](const std::string &what) {
    *error = path + ":" + std::to_string(lineno) + ": " + what;
    return false;
  };
  while (std::getline(in, line)) {
    ++lineno;
    if (line.size() > kMaxLineBytes) {
      return fail("line longer than " + std::to_string(kMaxLineBytes) + " bytes");
    }
    if (line.find('\0') != std::string::npos) {
      return fail("contains a NUL byte; a configuration file is text");
    }
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    line = trim(line);
    if (line.empty()) continue;
    const size_t eq = line.find('=');
    if (eq == std::string::npos) return fail("expected 'key = value'");
    const std::string key = trim(line.substr(0, eq));
    const std::string val = trim(line.substr(eq + 1));
    if (key == "method") {
      if (pv_method_from_name(val.c_str(), &cfg->method) != PV_OK) {
        return fail("unknown method '" + val + "' (known: surface, paper, polar)");
      }
      continue;
    }
    const Field *f = nullptr;
    for (const Field &c : kFields) {
      if (key == c.name) f = &c;
    }
    if (f == nullptr) return fail("unknown setting '" + key + "' (see docs/method.md)");
    errno = 0;
    char *end = nullptr;
    const double v = std::strtod(val.c_str(), &end);
    if (val.empty() || *end != '\0' || errno != 0 || !std::isfinite(v)) {
      return fail("'" + val + "' is not a number");
    }
    if (f->u != nullptr) {
      if (v < 0 || v > 4294967295.0 || v != std::floor(v)) {
        return fail("'" + key + "' needs a whole number");
      }
      cfg->*(f->u) = uint32_t(v);
    } else {
      cfg->*(f->f) = float(v);
    }
  }
  const char *bad = nullptr;
  if (pv_config_validate(cfg, &bad) != PV_OK) {
    *error = path + ": " + out_of_range_message(*cfg, bad);
    return false;
  }
  return true;
}

}  // namespace pv::tools
