// The --config parser (host_tools/pitvol/config_file.cpp) on arbitrary
// bytes.
//
// Invariants: a configuration it accepts passes pv_config_validate and gives
// a session size; a refusal names the file and says what is wrong; parsing
// the same bytes twice gives the same verdict, message and settings.
#include <cstring>

#include "fuzz_support.h"
#include "pitvol/config_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  static pv::fuzz::MemFile file;
  const std::string &path = file.write(data, size);
  pv_config_t a, b;
  pv_config_default(&a);
  pv_config_default(&b);
  std::string ea, eb;
  const bool ok_a = pv::tools::load_config_file(path, &a, &ea);
  const bool ok_b = pv::tools::load_config_file(path, &b, &eb);
  PV_FUZZ_CHECK(ok_a == ok_b && ea == eb, "verdict differs: '%s' vs '%s'", ea.c_str(), eb.c_str());
  if (ok_a) {
    PV_FUZZ_CHECK(std::memcmp(&a, &b, sizeof a) == 0, "settings differ between two parses");
    const char *bad = nullptr;
    PV_FUZZ_CHECK(pv_config_validate(&a, &bad) == PV_OK, "accepted but invalid: %s", bad ? bad : "?");
    size_t bytes = 0;
    PV_FUZZ_CHECK(pv_session_size(&a, &bytes) == PV_OK && bytes > 0, "no session size");
    PV_FUZZ_CHECK(bytes < (size_t(3) << 30), "accepted a %zu-byte session", bytes);
  } else {
    PV_FUZZ_CHECK(ea.rfind(path, 0) == 0 && ea.size() > path.size() + 2, "message '%s'", ea.c_str());
  }
  return 0;
}
