// PCD 0.6 / 0.7: DATA ascii or binary (little endian, packed records).
#include <vector>

#include "scanio/byte_source.h"

namespace pv::scanio::detail {
namespace {

struct Field {
  std::string name;
  size_t size = 4;
  char type = 'F';
  uint64_t count = 1;
};

bool ieq(std::string_view a, const char *b) {
  size_t i = 0;
  for (; i < a.size() && b[i]; ++i) {
    char c = a[i];
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
    if (c != b[i]) return false;
  }
  return i == a.size() && !b[i];
}

class PcdReader final : public ScanReader {
 public:
  PcdReader() : ScanReader(Format::Pcd) {}

  bool open(const std::string &path, Error *err) {
    if (!src_.open(path, err)) return false;
    bytes_total_ = src_.size();
    if (!parse_header(err)) return false;
    bytes_consumed_ = src_.offset();
    return true;
  }

  uint64_t declared_points() const override { return points_; }

  long read_points(pv_point_t *out, size_t cap, Error *err) override {
    size_t n = 0;
    while (n < cap && done_ < points_) {
      if (!(ascii_ ? ascii_point(&out[n], err) : binary_point(&out[n], err))) return -1;
      ++n;
      ++done_;
    }
    if (n == 0 && done_ == points_ && !checked_tail_) {
      checked_tail_ = true;
      if (!check_tail(err)) return -1;
    }
    return static_cast<long>(n);
  }
  uint64_t position() const override { return src_.offset(); }

 private:
  bool header_error(Error *err, const std::string &msg) {
    err->message = "PCD header line " + std::to_string(line_) + ": " + msg;
    err->line = line_;
    return false;
  }

  bool parse_header(Error *err) {
    std::vector<std::string_view> tok;
    bool have_size = false, have_type = false, have_count = false;
    bool have_points = false, have_width = false, have_height = false;
    uint64_t width = 0, height = 0;
    for (;;) {
      std::string_view line;
      ByteSource::Line r = src_.read_line(&line);
      if (r == ByteSource::Line::ReadError) {
        err->message = src_.read_error_text();
        return false;
      }
      if (r == ByteSource::Line::End) {
        err->message = "PCD header has no 'DATA' line (file truncated or not a PCD file)";
        err->line = line_;
        return false;
      }
      ++line_;
      if (r == ByteSource::Line::TooLong || src_.offset() > kMaxHeaderBytes)
        return header_error(err, "header longer than " + std::to_string(kMaxHeaderBytes) +
                                     " bytes; is this really a PCD file?");
      tok.clear();
      Tokenizer tk(line, false);
      std::string_view t;
      while (tk.next(&t)) {
        if (tok.size() > kMaxProperties)
          return header_error(err, "more than " + std::to_string(kMaxProperties) +
                                       " values on one line");
        tok.push_back(t);
      }
      if (tok.empty() || tok[0][0] == '#') continue;
      const std::string_view kw = tok[0];
      const size_t nv = tok.size() - 1;
      if (ieq(kw, "VERSION") || ieq(kw, "VIEWPOINT")) continue;
      if (ieq(kw, "FIELDS") || ieq(kw, "COLUMNS")) {
        if (nv == 0) return header_error(err, "FIELDS lists no fields");
        fields_.assign(nv, Field{});
        for (size_t i = 0; i < nv; ++i) fields_[i].name = std::string(tok[i + 1]);
      } else if (ieq(kw, "SIZE") || ieq(kw, "TYPE") || ieq(kw, "COUNT")) {
        if (fields_.empty()) return header_error(err, quote(kw) + " before FIELDS");
        if (nv != fields_.size())
          return header_error(err, quote(kw) + " has " + std::to_string(nv) +
                                       " values but FIELDS has " +
                                       std::to_string(fields_.size()));
        for (size_t i = 0; i < nv; ++i) {
          uint64_t u = 0;
          if (ieq(kw, "TYPE")) {
            std::string_view v = tok[i + 1];
            if (v.size() != 1 || (v[0] != 'F' && v[0] != 'I' && v[0] != 'U'))
              return header_error(err, "TYPE must be F, I or U, found " + quote(v));
            fields_[i].type = v[0];
            have_type = true;
          } else if (!parse_u64(tok[i + 1], &u)) {
            return header_error(err, quote(tok[i + 1]) + " is not a whole number");
          } else if (ieq(kw, "SIZE")) {
            if (u != 1 && u != 2 && u != 4 && u != 8)
              return header_error(err, "SIZE must be 1, 2, 4 or 8, found " + quote(tok[i + 1]));
            fields_[i].size = static_cast<size_t>(u);
            have_size = true;
          } else {
            if (u == 0 || u > kMaxRecordBytes)
              return header_error(err, "COUNT out of range: " + quote(tok[i + 1]));
            fields_[i].count = u;
            have_count = true;
          }
        }
      } else if (ieq(kw, "WIDTH") || ieq(kw, "HEIGHT") || ieq(kw, "POINTS")) {
        uint64_t u = 0;
        if (nv != 1 || !parse_u64(tok[1], &u))
          return header_error(err, "expected '" + std::string(kw) + " <number>', found " +
                                       quote(line));
        if (ieq(kw, "WIDTH")) { width = u; have_width = true; }
        else if (ieq(kw, "HEIGHT")) { height = u; have_height = true; }
        else { points_ = u; have_points = true; }
      } else if (ieq(kw, "DATA")) {
        if (nv != 1) return header_error(err, "expected 'DATA ascii|binary', found " + quote(line));
        if (ieq(tok[1], "ASCII")) ascii_ = true;
        else if (ieq(tok[1], "BINARY")) ascii_ = false;
        else if (ieq(tok[1], "BINARY_COMPRESSED"))
          return header_error(err,
                              "PCD DATA binary_compressed is not supported; convert "
                              "the file first, e.g. 'pcl_convert_pcd_ascii_binary in.pcd "
                              "out.pcd 1' (binary) or '... 0' (ascii)");
        else return header_error(err, "unknown DATA kind " + quote(tok[1]) +
                                          " (expected ascii or binary)");
        break;
      } else {
        return header_error(err, "unknown PCD header keyword " + quote(kw));
      }
    }
    if (fields_.empty()) return header_error(err, "no FIELDS line before DATA");
    if (!have_size) return header_error(err, "no SIZE line before DATA");
    if (!have_type) return header_error(err, "no TYPE line before DATA");
    (void)have_count;  // COUNT is optional (default 1)
    if (!have_points) {
      if (!have_width || !have_height || !mul_u64(width, height, &points_))
        return header_error(err, "no POINTS line and no usable WIDTH and HEIGHT");
    }
    size_t off = 0;
    size_t tok_index = 0;
    for (auto &f : fields_) {
      if (f.type == 'F' && f.size != 4 && f.size != 8)
        return header_error(err, "field '" + f.name + "' has TYPE F with SIZE " +
                                     std::to_string(f.size) + " (only 4 or 8)");
      for (int a = 0; a < 3; ++a)
        if (f.name == kAxes[a] && axis_off_[a] == SIZE_MAX) {
          axis_off_[a] = off;
          axis_tok_[a] = tok_index;
          axis_type_[a] = scalar_of(f);
        }
      uint64_t bytes = f.size * f.count;  // count <= kMaxRecordBytes: no overflow
      if (bytes > kMaxRecordBytes - off)
        return header_error(err, "records larger than " + std::to_string(kMaxRecordBytes) +
                                     " bytes are not supported");
      off += static_cast<size_t>(bytes);
      tok_index += static_cast<size_t>(f.count);
    }
    record_ = off;
    ntok_ = tok_index;
    for (int a = 0; a < 3; ++a)
      if (axis_off_[a] == SIZE_MAX)
        return header_error(err, std::string("no field '") + kAxes[a] +
                                     "' in FIELDS; pitvol needs x, y and z");
    return true;
  }

  static Scalar scalar_of(const Field &f) {
    if (f.type == 'F') return f.size == 8 ? Scalar::F64 : Scalar::F32;
    bool s = f.type == 'I';
    switch (f.size) {
      case 1: return s ? Scalar::I8 : Scalar::U8;
      case 2: return s ? Scalar::I16 : Scalar::U16;
      case 4: return s ? Scalar::I32 : Scalar::U32;
      default: return s ? Scalar::I64 : Scalar::U64;
    }
  }

  long fail(Error *err, std::string msg) {
    *err = Error{};
    err->message = std::move(msg);
    if (ascii_) err->line = line_;
    else err->byte_offset = src_.offset();
    return -1;
  }
  bool fail_b(Error *err, std::string msg) {
    fail(err, std::move(msg));
    return false;
  }
  std::string where() const {
    return ascii_ ? " (line " + std::to_string(line_) + ")"
                  : " (at byte " + std::to_string(src_.offset()) + ")";
  }
  bool ended(Error *err) {
    if (src_.read_failed()) return fail_b(err, src_.read_error_text());
    return fail_b(err, "file ends after " + std::to_string(done_) + " of " +
                           std::to_string(points_) + " points declared" + where() +
                           "; the file is truncated, copy or export it again");
  }

  bool binary_point(pv_point_t *p, Error *err) {
    if (!src_.ensure(record_)) return ended(err);
    const unsigned char *d = src_.data();
    p->x_mm = to_float(decode_scalar(d + axis_off_[0], axis_type_[0], false));
    p->y_mm = to_float(decode_scalar(d + axis_off_[1], axis_type_[1], false));
    p->z_mm = to_float(decode_scalar(d + axis_off_[2], axis_type_[2], false));
    src_.advance(record_);
    return true;
  }

  bool ascii_point(pv_point_t *p, Error *err) {
    std::string_view line;
    for (;;) {
      ByteSource::Line r = src_.read_line(&line);
      if (r == ByteSource::Line::End || r == ByteSource::Line::ReadError) return ended(err);
      ++line_;
      if (r == ByteSource::Line::TooLong)
        return fail_b(err, "line " + std::to_string(line_) + " is longer than " +
                               std::to_string(kBufferBytes) + " bytes");
      bool blank = true;
      for (char c : line)
        if (c != ' ' && c != '\t' && c != '\r') blank = false;
      if (!blank) break;
    }
    Tokenizer tk(line, false);
    std::string_view tok;
    float v[3] = {0, 0, 0};
    size_t i = 0;
    for (; tk.next(&tok); ++i) {
      if (i >= ntok_)
        return fail_b(err, "line " + std::to_string(line_) + ": more values than the " +
                               std::to_string(ntok_) + " the header's fields need");
      float f;
      if (!parse_float(tok, &f))
        return fail_b(err, "line " + std::to_string(line_) + ": " + quote(tok) +
                               " is not a number (value " + std::to_string(i + 1) + ")");
      for (int a = 0; a < 3; ++a)
        if (axis_tok_[a] == i) v[a] = f;
    }
    if (i < ntok_)
      return fail_b(err, "line " + std::to_string(line_) + ": " + std::to_string(i) +
                             " values, the header's fields need " + std::to_string(ntok_));
    p->x_mm = v[0];
    p->y_mm = v[1];
    p->z_mm = v[2];
    return true;
  }

  // After POINTS points only whitespace (ascii) or nothing / one line break
  // (binary) may follow.
  bool check_tail(Error *err) {
    switch (src_.rest_of_file(ascii_, &line_)) {
      case ByteSource::Tail::Clean: return true;
      case ByteSource::Tail::ReadError: return fail_b(err, src_.read_error_text());
      case ByteSource::Tail::Data: break;
    }
    return fail_b(err, "data continues after the " + std::to_string(points_) +
                           " points declared" + where() +
                           "; the header's POINTS is wrong or the file is corrupt");
  }

  static constexpr const char *kAxes[3] = {"x", "y", "z"};
  ByteSource src_;
  std::vector<Field> fields_;
  size_t axis_off_[3] = {SIZE_MAX, SIZE_MAX, SIZE_MAX};
  size_t axis_tok_[3] = {0, 0, 0};
  Scalar axis_type_[3] = {Scalar::F32, Scalar::F32, Scalar::F32};
  size_t record_ = 0, ntok_ = 0;
  uint64_t points_ = 0, done_ = 0, line_ = 0;
  bool ascii_ = false, checked_tail_ = false;
};

}  // namespace

std::unique_ptr<ScanReader> open_pcd(const std::string &path, Error *err) {
  auto r = std::make_unique<PcdReader>();
  if (!r->open(path, err)) return nullptr;
  return r;
}

}  // namespace pv::scanio::detail
