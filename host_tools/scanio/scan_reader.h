/*
 * pitvol scanio — streaming readers for recorded scan files (host side).
 *
 *   pv::scanio::Error err;
 *   auto r = pv::scanio::open_scan("pit.ply", pv::scanio::Format::Auto, &err);
 *   if (!r) { report(err); }
 *   pv_point_t buf[65536];
 *   long n;
 *   while ((n = r->read(buf, 65536, &err)) > 0) push(buf, n);
 *   if (n < 0) { report(err); }
 *
 * Supported files
 *   PLY 1.0   ascii, binary_little_endian, binary_big_endian. The "vertex"
 *             element's x, y, z (any numeric type: char/int8 ... double/
 *             float64, also int64/uint64) at any position among other
 *             properties; other properties, list properties and other
 *             elements (before or after "vertex") are skipped. ASCII data:
 *             one element instance per line (blank lines tolerated).
 *   PCD 0.6/0.7  DATA ascii or binary (little endian, packed records);
 *             x, y, z of TYPE F (size 4/8) or I/U (size 1/2/4/8), any other
 *             fields with any COUNT skipped. binary_compressed is refused.
 *   XYZ/ASC/TXT/CSV  one point per line, first three numbers are x y z,
 *             separated by whitespace, ',' or ';'; extra columns ignored;
 *             blank lines and comments (#, //) skipped; non-numeric header
 *             lines allowed only before the first data line (at most 100).
 * Values are passed through in the file's own units; NaN/Inf are passed
 * through too (the core counts and skips them). Numbers are parsed with
 * std::from_chars: locale-independent, the whole token must be a number.
 *
 * Guarantees for untrusted input (the fuzz target relies on these):
 *   - Memory is bounded and does not grow with the file: one fixed read
 *     buffer (kBufferBytes) per reader plus a header description whose size
 *     is capped (header <= 1 MiB, <= 4096 PLY properties / PCD fields,
 *     <= 256 PLY elements). Points go straight into the caller's array.
 *   - Never reads out of bounds: every access to the buffer is preceded by
 *     a check of the bytes available; a line or token longer than the
 *     buffer, or a record larger than half of it, is an error.
 *   - Never loops forever: every loop iteration consumes at least one byte
 *     or ends at end of file; counts from headers are only upper bounds of
 *     work that stops at end of file; size arithmetic is overflow-checked.
 *   - Errors instead of crashes: malformed input gives read()/open_scan()
 *     an Error (message + 1-based line for text, byte offset for binary).
 *     No exception leaves this API except std::bad_alloc from open_scan().
 *   - An error is sticky: later read() calls return -1 with the same error.
 *     After the end of the data read() keeps returning 0.
 */
#ifndef PITVOL_SCANIO_SCAN_READER_H
#define PITVOL_SCANIO_SCAN_READER_H

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "pitvol/pitvol.h"

namespace pv::scanio {

enum class Format { Auto, Ply, Xyz, Csv, Pcd };

// Size of the one read buffer each reader owns.
constexpr size_t kBufferBytes = 64 * 1024;

struct Error {
  std::string message;      // what is wrong and, where it helps, what to do
  uint64_t line = 0;        // 1-based line for text data/headers, else 0
  uint64_t byte_offset = 0; // byte offset in the file (binary data), else 0
};

class ScanReader {
 public:
  virtual ~ScanReader();
  ScanReader(const ScanReader &) = delete;
  ScanReader &operator=(const ScanReader &) = delete;

  // Reads up to cap points into out. Returns the number read (0 = end of
  // data), or -1 with *err filled (err may be NULL). cap == 0 or out == NULL
  // is an error (-1), so that 0 always means the end. After an error every
  // later call returns -1 with the same error.
  long read(pv_point_t *out, size_t cap, Error *err);
  // Point count from the header if the format declares it, else 0.
  virtual uint64_t declared_points() const;

  // For a progress bar: file size and bytes consumed so far (equal to
  // bytes_total() once read() has returned 0).
  uint64_t bytes_total() const { return bytes_total_; }
  uint64_t bytes_consumed() const { return bytes_consumed_; }
  Format format() const { return format_; }

 protected:
  explicit ScanReader(Format f) : format_(f) {}
  // The format's own reading, behind read(): out != NULL, 1 <= cap <=
  // LONG_MAX, err != NULL. Returns the count (0 = end) or -1 with *err filled.
  virtual long read_points(pv_point_t *out, size_t cap, Error *err) = 0;
  // Byte offset reached in the file, for bytes_consumed().
  virtual uint64_t position() const = 0;
  uint64_t bytes_total_ = 0;
  uint64_t bytes_consumed_ = 0;
  Format format_;

 private:
  bool failed_ = false;
  Error sticky_;
};

// Opens path and parses its header. nullptr with *err filled on failure
// (missing/unreadable/empty file, unknown extension with Format::Auto,
// bad header). Format::Xyz and Format::Csv both read any of the text forms.
std::unique_ptr<ScanReader> open_scan(const std::string &path, Format fmt,
                                      Error *err);

// "ply", "xyz", "asc", "csv", "txt", "pcd" (case-insensitive; a file name or
// path is judged by its extension) -> Format; anything else -> Auto.
Format format_from_name(const std::string &name);

// "auto", "ply", "xyz", "csv", "pcd".
const char *format_name(Format f);

}  // namespace pv::scanio

#endif
