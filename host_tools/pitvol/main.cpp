// pitvol: measure the volume of a scanned test pit.
//
//   pitvol measure FILE [--json] [--units mm|cm|m] [--config FILE]
//                       [--method paper] [--format ply|xyz|asc|csv|pcd]
//                       [--no-progress]
//   pitvol --version | --help
//   pitvol measure --help
//
// The command line is parsed by CLI11 (Debian's libcli11-dev); the help
// text is its listing of the options below.
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>

#include "config_file.h"
#include "measure.h"

namespace {

const char kExitCodes[] =
    "A FILE starting with '-': write ./-name, or put it after --.\n"
    "exit codes: 0 measured, 2 usage, 3 unreadable or invalid input,\n"
    "            4 the scan cannot support a measurement, 5 internal error";

// One line: what was wrong and where the options are listed.
int usage_error(const std::string &msg) {
  std::fprintf(stderr, "pitvol: %s (pitvol measure --help lists the options)\n", msg.c_str());
  return pv::tools::kExitUsage;
}

}  // namespace

int main(int argc, char **argv) {
  using namespace pv::tools;
  MeasureOptions opt;
  pv_config_default(&opt.cfg);
  std::string config_path, method, format;

  CLI::App app{"Measures the volume of a scanned test pit.", "pitvol"};
  app.get_formatter()->label("Usage", "usage");
  app.set_version_flag("--version", std::string("pitvol ") + PV_VERSION_STRING);
  app.require_subcommand(1);
  app.footer(kExitCodes);
  CLI::App *m = app.add_subcommand("measure", "Measures the pit volume in a scan file (PLY, PCD, XYZ/ASC/CSV).");
  m->footer(kExitCodes);
  m->add_option("FILE", opt.path, "the scan file")->required();
  m->add_flag("--json", opt.json, "one JSON object on stdout");
  m->add_option("--units", opt.units, "units of the file's coordinates (default mm)")
      ->check(CLI::IsMember({"mm", "cm", "m"}));
  m->add_option("--config", config_path, "'key = value' settings (docs/method.md)")->type_name("FILE");
  m->add_option("--method", method, "surface (default), paper or polar (docs/method.md)")
      ->type_name("NAME")
      ->check(
          [](const std::string &name) {
            pv_method_t unused;
            return pv_method_from_name(name.c_str(), &unused) == PV_OK
                       ? std::string()
                       : "unknown method '" + name + "' (known: surface, paper, polar)";
          },
          "");
  m->add_option("--format", format, "ply, pcd, xyz, asc, csv (default: by extension)")
      ->type_name("NAME")
      ->check(
          [](const std::string &name) {
            return pv::scanio::format_from_name(name) != pv::scanio::Format::Auto
                       ? std::string()
                       : "unknown format '" + name + "' (known: ply, pcd, xyz, asc, csv)";
          },
          "");
  m->add_flag("--no-progress", "no progress line on stderr");
  m->add_option("--layers", opt.layers_csv, "write area against height per layer (CSV)")->type_name("FILE");
  m->add_option("--export-levelled", opt.export_levelled,
                "write the points levelled (bottom at z = 0, binary PLY) with the rim height as a comment")
      ->type_name("FILE");
  m->add_option("--export", opt.export_dir,
                "write what a report plots into DIR: levelled points, layers, coverage, wall grid, "
                "outlines, the result (docs/report.md; pitvol-report makes the page)")
      ->type_name("DIR");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp &e) {
    return app.exit(e);  // the help of the command asked about, on stdout, exit 0
  } catch (const CLI::CallForVersion &e) {
    return app.exit(e);
  } catch (const CLI::ParseError &e) {
    if (app.get_subcommands().empty()) return usage_error("expected a command: measure");
    return usage_error(e.what());
  }
  opt.progress = m->count("--no-progress") == 0;
  if (opt.units == "cm") opt.scale_to_mm = 10.0;
  else if (opt.units == "m") opt.scale_to_mm = 1000.0;
  if (!format.empty()) opt.format = pv::scanio::format_from_name(format);
  if (!config_path.empty()) {
    std::string err;
    if (!load_config_file(config_path, &opt.cfg, &err)) {
      std::fprintf(stderr, "pitvol: %s\n", err.c_str());  // file:line: key = value and the range
      return kExitUsage;
    }
  }
  // --method over the config file's method.
  if (!method.empty() && pv_method_from_name(method.c_str(), &opt.cfg.method) != PV_OK) {
    std::fprintf(stderr, "pitvol: --method: unknown method '%s' (surface, paper or polar)\n",
                 method.c_str());
    return kExitUsage;
  }
  return run_measure(opt);
}
