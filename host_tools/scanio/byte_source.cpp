#include "scanio/byte_source.h"

#include <sys/stat.h>

#include <cerrno>
#include <charconv>
#include <cfloat>
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace pv::scanio::detail {

ByteSource::~ByteSource() {
  if (f_) std::fclose(f_);
}

bool ByteSource::open(const std::string &path, Error *err) {
  path_ = path;
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    err->message = "cannot open '" + path + "': " + std::strerror(errno);
    return false;
  }
  if (S_ISDIR(st.st_mode)) {
    err->message = "'" + path + "' is a directory, not a scan file";
    return false;
  }
  if (S_ISREG(st.st_mode) && st.st_size == 0) {
    err->message = "'" + path + "' is empty (0 bytes); there are no points to read";
    return false;
  }
  f_ = std::fopen(path.c_str(), "rb");
  if (!f_) {
    err->message = "cannot open '" + path + "': " + std::strerror(errno);
    return false;
  }
  size_ = S_ISREG(st.st_mode) ? static_cast<uint64_t>(st.st_size) : 0;
  buf_.reset(new unsigned char[kBufferBytes]);
  return true;
}

bool ByteSource::ensure(size_t n) {
  if (avail() >= n) return true;
  if (n > kBufferBytes || eof_ || !f_) return false;
  size_t have = avail();
  if (pos_ > 0) {
    std::memmove(buf_.get(), buf_.get() + pos_, have);
    base_ += pos_;
    pos_ = 0;
    end_ = have;
  }
  while (end_ < n) {
    size_t got = std::fread(buf_.get() + end_, 1, kBufferBytes - end_, f_);
    if (got == 0) {
      if (std::ferror(f_)) {
        read_failed_ = true;
        read_errno_ = errno;
      }
      eof_ = true;
      break;
    }
    end_ += got;
  }
  return end_ >= n;
}

uint64_t ByteSource::skip(uint64_t n) {
  uint64_t done = 0;
  while (done < n) {
    if (avail() == 0 && !ensure(1)) break;
    uint64_t step = n - done;
    if (step > avail()) step = avail();
    pos_ += static_cast<size_t>(step);
    done += step;
  }
  return done;
}

std::string ByteSource::read_error_text() const {
  return "read error in '" + path_ + "' at byte " + std::to_string(offset()) +
         ": " + std::strerror(read_errno_ ? read_errno_ : EIO);
}

ByteSource::Line ByteSource::read_line(std::string_view *line) {
  size_t scanned = 0;
  for (;;) {
    const unsigned char *p = data();
    size_t n = avail();
    const void *nl = scanned < n ? std::memchr(p + scanned, '\n', n - scanned)
                                 : nullptr;
    if (nl) {
      size_t len = static_cast<size_t>(static_cast<const unsigned char *>(nl) - p);
      pos_ += len + 1;
      if (len > 0 && p[len - 1] == '\r') --len;
      *line = std::string_view(reinterpret_cast<const char *>(p), len);
      return Line::Ok;
    }
    scanned = n;
    if (n >= kBufferBytes) return Line::TooLong;
    if (!ensure(n + 1)) {
      if (read_failed_) return Line::ReadError;
      if (avail() == 0) return Line::End;
      // Last line without '\n'.
      p = data();
      size_t len = avail();
      pos_ += len;
      if (len > 0 && p[len - 1] == '\r') --len;
      *line = std::string_view(reinterpret_cast<const char *>(p), len);
      return Line::Ok;
    }
  }
}

static bool is_sep(char c, bool csv) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f' ||
         (csv && (c == ',' || c == ';'));
}

bool Tokenizer::next(std::string_view *tok) {
  while (p < e && is_sep(*p, csv)) ++p;
  if (p == e) return false;
  const char *b = p;
  while (p < e && !is_sep(*p, csv)) ++p;
  *tok = std::string_view(b, static_cast<size_t>(p - b));
  return true;
}

bool parse_float(std::string_view tok, float *out) {
  const char *b = tok.data(), *e = b + tok.size();
  if (b < e && *b == '+') {
    ++b;
    if (b < e && (*b == '-' || *b == '+')) return false;
  }
  if (b == e) return false;
  float f = 0.0f;
  auto r = std::from_chars(b, e, f);
  if (r.ptr != e) return false;
  if (r.ec == std::errc()) {
    *out = f;
    return true;
  }
  if (r.ec != std::errc::result_out_of_range) return false;
  // Syntactically a number but out of float range: let strtod (C locale
  // assumed) decide the direction, then saturate.
  char tmp[128];
  size_t len = static_cast<size_t>(e - b);
  if (len >= sizeof tmp) return false;
  std::memcpy(tmp, b, len);
  tmp[len] = '\0';
  *out = to_float(std::strtod(tmp, nullptr));
  return true;
}

bool is_number(std::string_view tok) {
  float f;
  return parse_float(tok, &f);
}

bool parse_u64(std::string_view tok, uint64_t *out) {
  const char *b = tok.data(), *e = b + tok.size();
  if (b < e && *b == '+') ++b;
  if (b == e) return false;
  auto r = std::from_chars(b, e, *out);
  return r.ec == std::errc() && r.ptr == e;
}

std::string quote(std::string_view text, size_t max) {
  std::string s = "'";
  size_t n = text.size() < max ? text.size() : max;
  for (size_t i = 0; i < n; ++i) {
    unsigned char c = static_cast<unsigned char>(text[i]);
    s += (c >= 0x20 && c < 0x7f) ? static_cast<char>(c) : '?';
  }
  if (text.size() > max) s += "...";
  s += "'";
  return s;
}

size_t scalar_size(Scalar s) {
  switch (s) {
    case Scalar::I8: case Scalar::U8: return 1;
    case Scalar::I16: case Scalar::U16: return 2;
    case Scalar::I32: case Scalar::U32: case Scalar::F32: return 4;
    case Scalar::I64: case Scalar::U64: case Scalar::F64: return 8;
  }
  return 1;
}

bool scalar_is_integer(Scalar s) { return s != Scalar::F32 && s != Scalar::F64; }

double decode_scalar(const unsigned char *p, Scalar s, bool big_endian) {
  size_t n = scalar_size(s);
  uint64_t u = 0;
  if (big_endian) {
    for (size_t i = 0; i < n; ++i) u = (u << 8) | p[i];
  } else {
    for (size_t i = n; i-- > 0;) u = (u << 8) | p[i];
  }
  switch (s) {
    case Scalar::I8: return static_cast<int8_t>(static_cast<uint8_t>(u));
    case Scalar::U8: return static_cast<uint8_t>(u);
    case Scalar::I16: return static_cast<int16_t>(static_cast<uint16_t>(u));
    case Scalar::U16: return static_cast<uint16_t>(u);
    case Scalar::I32: return static_cast<int32_t>(static_cast<uint32_t>(u));
    case Scalar::U32: return static_cast<uint32_t>(u);
    case Scalar::I64: return static_cast<double>(static_cast<int64_t>(u));
    case Scalar::U64: return static_cast<double>(u);
    case Scalar::F32: {
      uint32_t b = static_cast<uint32_t>(u);
      float f;
      std::memcpy(&f, &b, 4);
      return f;
    }
    case Scalar::F64: {
      double d;
      std::memcpy(&d, &u, 8);
      return d;
    }
  }
  return 0.0;
}

float to_float(double d) {
  if (d > static_cast<double>(FLT_MAX)) return HUGE_VALF;
  if (d < -static_cast<double>(FLT_MAX)) return -HUGE_VALF;
  return static_cast<float>(d);  // NaN stays NaN
}

ByteSource::Tail ByteSource::rest_of_file(bool ascii, uint64_t *line) {
  if (ascii) {
    std::string_view text;
    for (;;) {
      const Line r = read_line(&text);
      if (r == Line::End) return Tail::Clean;
      if (r == Line::ReadError) return Tail::ReadError;
      ++*line;
      if (r == Line::TooLong) return Tail::Data;
      for (char c : text) {
        if (c != ' ' && c != '\t' && c != '\r') return Tail::Data;
      }
    }
  }
  ensure(3);
  const size_t n = avail();
  const unsigned char *d = data();
  if (n == 0 || (n == 1 && d[0] == '\n') || (n == 2 && d[0] == '\r' && d[1] == '\n')) {
    advance(n);
    return Tail::Clean;
  }
  return read_failed() ? Tail::ReadError : Tail::Data;
}

}  // namespace pv::scanio::detail
