// Running a built tool from a CLI test: the command through the shell,
// stdout through popen, stderr through a file, the exit code. Shared by
// test_cli_formats and test_cli_hostile. Include it last (it includes
// pv_cmocka.h, which must come after every other header).
#ifndef PV_TESTS_CLI_RUN_H
#define PV_TESTS_CLI_RUN_H

#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "pv_cmocka.h"

struct Run {
  int exit_code = -1;
  std::string out, err;
};

// The shell's single-quoted form of s.
inline std::string quote(const std::string &s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') q += "'\\''";
    else q += c;
  }
  return q + "'";
}

inline std::string slurp(const std::string &path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs cmd (already quoted) with stderr to errfile, which is read and removed.
inline Run run_command(const std::string &cmd, const std::string &errfile) {
  Run r;
  FILE *p = popen((cmd + " 2>" + quote(errfile)).c_str(), "r");
  assert_non_null(p);
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.err = slurp(errfile);
  std::remove(errfile.c_str());
  return r;
}

#endif
