// pitvol: measure the volume of a scanned test pit.
//
//   pitvol measure FILE [--json] [--units mm|cm|m] [--config FILE]
//                       [--method paper] [--format ply|xyz|asc|csv|pcd]
//                       [--no-progress]
//   pitvol --version | --help
//   pitvol measure --help
#include <cstdio>
#include <cstring>
#include <string>

#include "config_file.h"
#include "measure.h"

namespace {

const char kUsage[] =
    "usage: pitvol measure FILE [options]\n"
    "  Measures the pit volume in a scan file (PLY, PCD, XYZ/ASC/CSV).\n"
    "options:\n"
    "  --json              one JSON object on stdout\n"
    "  --units mm|cm|m     units of the file's coordinates (default mm)\n"
    "  --config FILE       'key = value' settings (docs/method.md)\n"
    "  --method NAME       surface (default), paper or polar (docs/method.md)\n"
    "  --format NAME       ply, pcd, xyz, asc, csv (default: by extension)\n"
    "  --no-progress       no progress line on stderr\n"
    "  --layers FILE       write area against height per layer (CSV)\n"
    "  --export-levelled FILE  write the points levelled (bottom at z = 0,\n"
    "                      binary PLY) with the rim height as a comment\n"
    "  --export DIR        write what a report plots into DIR: levelled points,\n"
    "                      layers, coverage, wall grid, outlines, the result\n"
    "                      (docs/report.md; pitvol-report makes the page)\n"
    "  --help              this text\n"
    "  a FILE starting with '-': write ./-name, or put it after --\n"
    "exit codes: 0 measured, 2 usage, 3 unreadable or invalid input,\n"
    "            4 the scan cannot support a measurement, 5 internal error\n";

// One line: what was wrong and where the options are listed.
int usage_error(const std::string &msg) {
  std::fprintf(stderr, "pitvol: %s (pitvol measure --help lists the options)\n", msg.c_str());
  return pv::tools::kExitUsage;
}

}  // namespace

int main(int argc, char **argv) {
  using namespace pv::tools;
  if (argc >= 2 && (std::strcmp(argv[1], "--version") == 0)) {
    std::printf("pitvol %s\n", PV_VERSION_STRING);
    return 0;
  }
  if (argc >= 2 && (std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0)) {
    std::printf("%s", kUsage);
    return 0;
  }
  if (argc < 2 || std::strcmp(argv[1], "measure") != 0) return usage_error("expected a command: measure");
  for (int i = 2; i < argc && std::strcmp(argv[i], "--") != 0; ++i) {
    if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
      std::printf("%s", kUsage);
      return 0;
    }
  }

  MeasureOptions opt;
  pv_config_default(&opt.cfg);
  std::string config_path, method;
  bool only_files = false;  // after "--", every argument is a file name
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (only_files || a.empty() || a[0] != '-') {
      if (!opt.path.empty()) return usage_error("more than one input file given");
      opt.path = a;
    } else if (a == "--") {
      only_files = true;
    } else if (a == "--json") {
      opt.json = true;
    } else if (a == "--no-progress") {
      opt.progress = false;
    } else if (a == "--units" && has_value) {
      opt.units = argv[++i];
      if (opt.units == "mm") opt.scale_to_mm = 1.0;
      else if (opt.units == "cm") opt.scale_to_mm = 10.0;
      else if (opt.units == "m") opt.scale_to_mm = 1000.0;
      else return usage_error("--units must be mm, cm or m, not '" + opt.units + "'");
    } else if (a == "--layers" && has_value) {
      opt.layers_csv = argv[++i];
    } else if (a == "--export-levelled" && has_value) {
      opt.export_levelled = argv[++i];
    } else if (a == "--export" && has_value) {
      opt.export_dir = argv[++i];
    } else if (a == "--config" && has_value) {
      config_path = argv[++i];
    } else if (a == "--method" && has_value) {
      method = argv[++i];
    } else if (a == "--format" && has_value) {
      const std::string f = argv[++i];
      opt.format = pv::scanio::format_from_name(f);
      if (opt.format == pv::scanio::Format::Auto) return usage_error("unknown --format '" + f + "'");
    } else {
      // A file whose name starts with '-': ./-x or after "--".
      return usage_error("unknown or incomplete option '" + a + "'");
    }
  }
  if (opt.path.empty()) return usage_error("no scan file given");
  if (!config_path.empty()) {
    std::string err;
    if (!load_config_file(config_path, &opt.cfg, &err)) {
      std::fprintf(stderr, "pitvol: %s\n", err.c_str());  // file:line: key = value and the range
      return kExitUsage;
    }
  }
  if (!method.empty() && pv_method_from_name(method.c_str(), &opt.cfg.method) != PV_OK) {
    return usage_error("unknown --method '" + method + "' (known: surface, paper, polar)");
  }
  return run_measure(opt);
}
