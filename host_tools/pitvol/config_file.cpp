#include "config_file.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sys/stat.h>

#include <cstdio>
#include <cstring>
#include <map>
#include <sstream>

#include "pitvol/config_fields.h"

namespace pv::tools {

namespace {

std::string trim(const std::string &s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

// "setting 'X' = V is out of range", with the numbers that make it so: the
// one check the table of ranges cannot make alone (a product of two).
std::string out_of_range_message(const pv_config_t &cfg, const char *bad) {
  const std::string name = bad ? bad : "?";
  const uint64_t slots = uint64_t(cfg.max_layers) * cfg.points_per_layer;
  if (name == "points_per_layer") {
    return "points_per_layer = " + std::to_string(cfg.points_per_layer) + ": max_layers x points_per_layer = " +
           std::to_string(slots) + " point slots would need about " + std::to_string(slots * 16 >> 20) +
           " MiB of session memory; the limit is 67108864 slots (1 GiB): lower one of them";
  }
  return "setting '" + name + "' is out of range (docs/method.md gives the allowed ranges)";
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
  std::map<std::string, int> line_of;  // key -> the line that set it
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
    char why[256];
    if (pv_config_field_set(cfg, key.c_str(), val.c_str(), why, sizeof why) != PV_UI_OK) return fail(why);
    line_of[key] = lineno;
  }
  const char *bad = nullptr;
  if (pv_config_validate(cfg, &bad) != PV_OK) {
    // The line that set the field (points_per_layer: or max_layers, its
    // partner in the product).
    const std::string name = bad ? bad : "";
    lineno = line_of.count(name) ? line_of[name] : line_of.count("max_layers") ? line_of["max_layers"] : 0;
    *error = path + (lineno ? ":" + std::to_string(lineno) : "") + ": " + out_of_range_message(*cfg, bad);
    return false;
  }
  return true;
}

}  // namespace pv::tools
