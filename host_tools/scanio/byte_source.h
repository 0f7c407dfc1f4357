// Internal to scanio: buffered file reading with one fixed buffer, plus the
// small parsing helpers the readers share. Not part of the public API.
#ifndef PITVOL_SCANIO_BYTE_SOURCE_H
#define PITVOL_SCANIO_BYTE_SOURCE_H

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>

#include "scanio/scan_reader.h"

namespace pv::scanio::detail {

// Reads a file through a fixed kBufferBytes buffer. Invariant:
// 0 <= pos_ <= end_ <= kBufferBytes; data()/avail() describe buf[pos_, end_).
class ByteSource {
 public:
  ByteSource() = default;
  ~ByteSource();
  ByteSource(const ByteSource &) = delete;
  ByteSource &operator=(const ByteSource &) = delete;

  // Opens a regular file; fills err on failure.
  bool open(const std::string &path, Error *err);

  // Makes at least n bytes (n <= kBufferBytes) available. False when the
  // file (or a read error) ends first; then avail() < n.
  bool ensure(size_t n);
  const unsigned char *data() const { return buf_.get() + pos_; }
  size_t avail() const { return end_ - pos_; }
  void advance(size_t n) { pos_ += n < avail() ? n : avail(); }
  // Discards n bytes; returns how many were there (< n at end of file).
  uint64_t skip(uint64_t n);
  // True when nothing is left (reads to find out).
  bool at_end() { return !ensure(1); }

  uint64_t offset() const { return base_ + pos_; }  // file offset of data()
  uint64_t size() const { return size_; }
  bool read_failed() const { return read_failed_; }
  // "read error in 'x' at byte N: <errno text>" for the last failed read.
  std::string read_error_text() const;

  // One line without its '\n' and one trailing '\r'.
  enum class Line { Ok, End, TooLong, ReadError };
  Line read_line(std::string_view *line);

  // What follows the declared data: only blank lines (ascii; *line counts
  // the lines read) or at most one line break (binary) is Clean.
  enum class Tail { Clean, Data, ReadError };
  Tail rest_of_file(bool ascii, uint64_t *line);

 private:
  std::FILE *f_ = nullptr;
  std::string path_;
  std::unique_ptr<unsigned char[]> buf_;
  size_t pos_ = 0, end_ = 0;
  uint64_t base_ = 0;  // file offset of buf_[0]
  uint64_t size_ = 0;
  bool eof_ = false;
  bool read_failed_ = false;
  int read_errno_ = 0;
};

// Splits a line into tokens. Separators: space, tab, \r, \v, \f and, with
// csv = true, also ',' and ';'. Runs of separators count as one.
struct Tokenizer {
  const char *p, *e;
  bool csv;
  Tokenizer(std::string_view s, bool csv_seps)
      : p(s.data()), e(s.data() + s.size()), csv(csv_seps) {}
  bool next(std::string_view *tok);
};

// Whole token must be a number (from_chars, locale-independent; leading '+'
// allowed; inf/nan accepted). Out-of-range values become +-inf / +-0.
bool parse_float(std::string_view tok, float *out);
bool is_number(std::string_view tok);
bool parse_u64(std::string_view tok, uint64_t *out);

// 'text' for messages: at most max chars, non-printables shown as '?'.
std::string quote(std::string_view text, size_t max = 40);

// Numeric scalar types of the binary formats.
enum class Scalar { I8, U8, I16, U16, I32, U32, I64, U64, F32, F64 };
size_t scalar_size(Scalar s);
bool scalar_is_integer(Scalar s);
// Decodes scalar_size(s) bytes at p.
double decode_scalar(const unsigned char *p, Scalar s, bool big_endian);
// double -> float without undefined behaviour (out of range -> +-inf).
float to_float(double d);
// a * b, false on overflow.
inline bool mul_u64(uint64_t a, uint64_t b, uint64_t *r) {
  return !__builtin_mul_overflow(a, b, r);
}

std::unique_ptr<ScanReader> open_ply(const std::string &path, Error *err);
std::unique_ptr<ScanReader> open_pcd(const std::string &path, Error *err);
std::unique_ptr<ScanReader> open_text(const std::string &path, Format f,
                                      Error *err);

// Header limits shared by the readers (see scan_reader.h).
constexpr uint64_t kMaxHeaderBytes = 1024 * 1024;
constexpr size_t kMaxProperties = 4096;
constexpr size_t kMaxElements = 256;
constexpr size_t kMaxRecordBytes = kBufferBytes / 2;

}  // namespace pv::scanio::detail

#endif
