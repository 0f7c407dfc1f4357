#include "scanio/scan_reader.h"

#include <climits>
#include <new>

#include "scanio/byte_source.h"

namespace pv::scanio {

ScanReader::~ScanReader() = default;

uint64_t ScanReader::declared_points() const { return 0; }

long ScanReader::read(pv_point_t *out, size_t cap, Error *err) {
  Error local;
  if (err == nullptr) err = &local;
  if (failed_) {
    *err = sticky_;
    return -1;
  }
  long n = -1;
  if (out == nullptr || cap == 0) {
    *err = Error{};
    err->message = "read() needs an output array and cap > 0";
  } else {
    n = read_points(out, cap > size_t(LONG_MAX) ? size_t(LONG_MAX) : cap, err);
  }
  if (n < 0) {
    failed_ = true;
    sticky_ = *err;
    bytes_consumed_ = position();
    return -1;
  }
  // At the end the progress is complete even if elements after the data
  // (PLY faces, ...) were not read.
  bytes_consumed_ = n == 0 ? bytes_total_ : position();
  return n;
}

static std::string lower(std::string s) {
  for (char &c : s)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return s;
}

Format format_from_name(const std::string &name) {
  std::string n = name;
  size_t slash = n.find_last_of('/');
  if (slash != std::string::npos) n = n.substr(slash + 1);
  size_t dot = n.find_last_of('.');
  if (dot != std::string::npos) n = n.substr(dot + 1);
  n = lower(n);
  if (n == "ply") return Format::Ply;
  if (n == "xyz" || n == "asc" || n == "txt") return Format::Xyz;
  if (n == "csv") return Format::Csv;
  if (n == "pcd") return Format::Pcd;
  return Format::Auto;
}

const char *format_name(Format f) {
  switch (f) {
    case Format::Auto: return "auto";
    case Format::Ply: return "ply";
    case Format::Xyz: return "xyz";
    case Format::Csv: return "csv";
    case Format::Pcd: return "pcd";
  }
  return "unknown";
}

std::unique_ptr<ScanReader> open_scan(const std::string &path, Format fmt,
                                      Error *err) {
  Error local;
  if (!err) err = &local;
  *err = Error{};
  if (fmt == Format::Auto) {
    size_t slash = path.find_last_of('/');
    size_t dot = path.find_last_of('.');
    bool has_ext = dot != std::string::npos &&
                   (slash == std::string::npos || dot > slash);
    fmt = has_ext ? format_from_name(path.substr(dot + 1)) : Format::Auto;
    if (fmt == Format::Auto) {
      err->message = "cannot tell the format of '" + path +
                     "' from its extension; use .ply, .pcd, .xyz, .asc, "
                     ".csv or .txt, or name the format explicitly";
      return nullptr;
    }
  }
  switch (fmt) {
    case Format::Ply: return detail::open_ply(path, err);
    case Format::Pcd: return detail::open_pcd(path, err);
    case Format::Xyz:
    case Format::Csv: return detail::open_text(path, fmt, err);
    case Format::Auto: break;
  }
  err->message = "internal error: no reader for the format";
  return nullptr;
}

}  // namespace pv::scanio
