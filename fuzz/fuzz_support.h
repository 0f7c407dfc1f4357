// Shared by the libFuzzer harnesses: a failed invariant aborts with a
// message (libFuzzer then saves the input as a crash), and an input can be
// handed to a reader that wants a file path without touching the disk.
#ifndef PV_FUZZ_SUPPORT_H
#define PV_FUZZ_SUPPORT_H

#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "pitvol/splitmix64.h"

#define PV_FUZZ_CHECK(cond, ...)                                              \
  do {                                                                        \
    if (!(cond)) {                                                            \
      std::fprintf(stderr, "invariant failed: %s (%s:%d): ", #cond, __FILE__, \
                   __LINE__);                                                 \
      std::fprintf(stderr, __VA_ARGS__);                                      \
      std::fprintf(stderr, "\n");                                             \
      std::abort();                                                           \
    }                                                                         \
  } while (0)

namespace pv::fuzz {

// An in-memory file (memfd) reachable by path: /proc/self/fd/N. One per
// process, rewritten for every input.
class MemFile {
 public:
  MemFile() : fd_(memfd_create("pv_fuzz", 0)) {
    if (fd_ < 0) std::abort();
    path_ = "/proc/self/fd/" + std::to_string(fd_);
  }
  const std::string &write(const uint8_t *data, size_t size) {
    if (ftruncate(fd_, 0) != 0) std::abort();
    size_t done = 0;
    while (done < size) {
      const ssize_t n = pwrite(fd_, data + done, size - done, off_t(done));
      if (n <= 0) std::abort();
      done += size_t(n);
    }
    return path_;
  }

 private:
  int fd_;
  std::string path_;
};

// Deterministic draws from the input's own bytes (chunk sizes, batch
// sizes): same input, same run.
struct Draw {
  uint64_t state;
  uint64_t next() { return pv_splitmix64_next(&state); }
  size_t below(size_t n) { return n == 0 ? 0 : size_t(next() % n); }
};

}  // namespace pv::fuzz

#endif
