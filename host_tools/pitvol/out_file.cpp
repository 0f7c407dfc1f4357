#include "out_file.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace pv::tools {

bool OutFile::open(const std::string &path, std::string *err) {
  discard();
  path_ = path;
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
    *err = "cannot write " + path + ": it is a directory";
    return false;
  }
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    f_ = std::fopen(path.c_str(), "w");
  } else {
    // Beside the target, so that the rename stays on one file system.
    std::string t = path + ".tmp-XXXXXX";
    const int fd = ::mkstemp(t.data());
    if (fd >= 0) {
      ::fchmod(fd, 0644);
      f_ = ::fdopen(fd, "w");
      if (f_ == nullptr) ::close(fd);
      tmp_ = t;
    }
  }
  if (f_ == nullptr) {
    *err = "cannot write " + path + ": " + std::strerror(errno);
    if (!tmp_.empty()) ::unlink(tmp_.c_str());
    tmp_.clear();
    return false;
  }
  return true;
}

bool OutFile::commit(std::string *err) {
  if (f_ == nullptr) {
    *err = "cannot write " + path_ + ": not open";
    return false;
  }
  errno = 0;
  const bool bad = std::fflush(f_) != 0 || std::ferror(f_) != 0;
  const int flush_errno = errno;
  FILE *f = f_;
  f_ = nullptr;
  const bool close_failed = std::fclose(f) != 0;
  const int why = bad ? flush_errno : errno;
  if (bad || close_failed) {
    *err = "cannot write " + path_ + ": " + std::strerror(why != 0 ? why : EIO);
    if (!tmp_.empty()) ::unlink(tmp_.c_str());
    tmp_.clear();
    return false;
  }
  if (!tmp_.empty() && std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    *err = "cannot write " + path_ + ": " + std::strerror(errno);
    ::unlink(tmp_.c_str());
    tmp_.clear();
    return false;
  }
  tmp_.clear();
  return true;
}

void OutFile::discard() {
  if (f_ != nullptr) std::fclose(f_);
  f_ = nullptr;
  if (!tmp_.empty()) ::unlink(tmp_.c_str());
  tmp_.clear();
}

}  // namespace pv::tools
