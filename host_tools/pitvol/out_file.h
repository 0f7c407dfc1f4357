// An output file that is either complete or absent: written under a
// temporary name beside it and renamed over it when closed without error,
// removed otherwise (a disk that fills, a failed measurement, an
// exception). A target that exists and is not a regular file (/dev/stdout,
// a FIFO) is written in place: it cannot be renamed over.
#ifndef PV_TOOLS_OUT_FILE_H
#define PV_TOOLS_OUT_FILE_H

#include <cstdio>
#include <string>

namespace pv::tools {

class OutFile {
 public:
  OutFile() = default;
  OutFile(const OutFile &) = delete;
  OutFile &operator=(const OutFile &) = delete;
  ~OutFile() { discard(); }

  // Opens for writing; false with *err ("cannot write PATH: reason").
  bool open(const std::string &path, std::string *err);
  FILE *get() const { return f_; }
  explicit operator bool() const { return f_ != nullptr; }
  // Flushes, closes and puts the file in place; false with *err ("cannot
  // write PATH: No space left on device") and nothing left behind.
  bool commit(std::string *err);
  // Closes and removes what was written (nothing if committed).
  void discard();

 private:
  FILE *f_ = nullptr;
  std::string path_, tmp_;  // tmp_ empty: written in place
};

}  // namespace pv::tools

#endif
