// PLY 1.0: ascii, binary_little_endian, binary_big_endian.
#include <algorithm>
#include <cstring>
#include <vector>

#include "scanio/byte_source.h"

namespace pv::scanio::detail {
namespace {

struct Property {
  std::string name;
  bool is_list = false;
  Scalar type = Scalar::F32;        // scalar type, or list item type
  Scalar count_type = Scalar::U8;   // list count type
};

struct Element {
  std::string name;
  uint64_t count = 0;
  std::vector<Property> props;
  bool has_list = false;
  size_t fixed_size = 0;  // bytes per instance when !has_list
};

bool scalar_from_name(std::string_view n, Scalar *s) {
  static const struct { const char *name; Scalar s; } kTypes[] = {
      {"char", Scalar::I8},    {"int8", Scalar::I8},     {"uchar", Scalar::U8},
      {"uint8", Scalar::U8},   {"short", Scalar::I16},   {"int16", Scalar::I16},
      {"ushort", Scalar::U16}, {"uint16", Scalar::U16},  {"int", Scalar::I32},
      {"int32", Scalar::I32},  {"uint", Scalar::U32},    {"uint32", Scalar::U32},
      {"int64", Scalar::I64},  {"uint64", Scalar::U64},  {"float", Scalar::F32},
      {"float32", Scalar::F32}, {"double", Scalar::F64}, {"float64", Scalar::F64}};
  for (const auto &t : kTypes)
    if (n == t.name) {
      *s = t.s;
      return true;
    }
  return false;
}

class PlyReader final : public ScanReader {
 public:
  PlyReader() : ScanReader(Format::Ply) {}

  bool open(const std::string &path, Error *err) {
    if (!src_.open(path, err)) return false;
    bytes_total_ = src_.size();
    if (!parse_header(err)) return false;
    bytes_consumed_ = src_.offset();
    return true;
  }

  uint64_t declared_points() const override { return vcount_; }

  long read_points(pv_point_t *out, size_t cap, Error *err) override {
    if (!skipped_before_) {
      for (size_t e = 0; e < vindex_; ++e)
        if (!skip_element(elements_[e], err)) return -1;
      skipped_before_ = true;
    }
    const Element &v = elements_[vindex_];
    size_t n = 0;
    if (fast_f32_xyz(v)) n = read_f32_run(v, out, cap);
    while (n < cap && done_ < vcount_) {
      bool ok = ascii_ ? ascii_vertex(v, &out[n], err)
                : v.has_list ? binary_vertex(v, &out[n], err)
                             : fixed_vertex(v, &out[n], err);
      if (!ok) return -1;
      ++n;
      ++done_;
    }
    if (n == 0 && done_ == vcount_ && !checked_tail_) {
      checked_tail_ = true;
      if (vindex_ + 1 == elements_.size() && !check_tail(err)) return -1;
    }
    return static_cast<long>(n);
  }
  uint64_t position() const override { return src_.offset(); }

 private:
  // ---- header --------------------------------------------------------
  bool header_error(Error *err, const std::string &msg) {
    err->message = "PLY header line " + std::to_string(line_) + ": " + msg;
    err->line = line_;
    return false;
  }

  bool parse_header(Error *err) {
    bool have_format = false;
    for (;;) {
      std::string_view line;
      ByteSource::Line r = src_.read_line(&line);
      if (r == ByteSource::Line::ReadError) {
        err->message = src_.read_error_text();
        return false;
      }
      if (r == ByteSource::Line::End) {
        err->message = line_ == 0 ? "not a PLY file: it is empty"
                                  : "PLY header has no 'end_header' line "
                                    "(file truncated or not a PLY file)";
        err->line = line_;
        return false;
      }
      ++line_;
      if (r == ByteSource::Line::TooLong || src_.offset() > kMaxHeaderBytes) {
        if (line_ == 1) {
          err->message = "not a PLY file: the first line must be 'ply'";
          err->line = 1;
          return false;
        }
        return header_error(err, "header longer than " +
                                     std::to_string(kMaxHeaderBytes) +
                                     " bytes; is 'end_header' missing?");
      }
      Tokenizer tk(line, false);
      std::string_view t[6];
      size_t nt = 0;
      std::string_view extra;
      while (nt < 6 && tk.next(&t[nt])) ++nt;
      bool more = tk.next(&extra);
      if (line_ == 1) {
        if (nt != 1 || t[0] != "ply") {
          err->message = "not a PLY file: the first line must be 'ply', found " +
                         quote(line);
          err->line = 1;
          return false;
        }
        continue;
      }
      if (nt == 0) continue;
      const std::string_view kw = t[0];
      if (kw == "comment" || kw == "obj_info") continue;
      if (kw == "format") {
        if (nt != 3 || more)
          return header_error(err, "expected 'format <ascii|binary_little_endian|"
                                   "binary_big_endian> 1.0', found " + quote(line));
        if (t[1] == "ascii") ascii_ = true;
        else if (t[1] == "binary_little_endian") big_endian_ = false;
        else if (t[1] == "binary_big_endian") big_endian_ = true;
        else return header_error(err, "unknown PLY format " + quote(t[1]));
        if (t[2] != "1.0" && t[2] != "1")
          return header_error(err, "unsupported PLY version " + quote(t[2]) +
                                       " (only 1.0 is supported)");
        have_format = true;
      } else if (kw == "element") {
        uint64_t count = 0;
        if (nt != 3 || more || !parse_u64(t[2], &count))
          return header_error(err, "expected 'element <name> <count>', found " +
                                       quote(line));
        if (elements_.size() >= kMaxElements)
          return header_error(err, "more than " + std::to_string(kMaxElements) +
                                       " elements");
        elements_.emplace_back();
        elements_.back().name = std::string(t[1]);
        elements_.back().count = count;
      } else if (kw == "property") {
        if (elements_.empty())
          return header_error(err, "'property' before any 'element'");
        if (++nprops_ > kMaxProperties)
          return header_error(err, "more than " + std::to_string(kMaxProperties) +
                                       " properties");
        Property p;
        bool ok;
        if (nt >= 2 && t[1] == "list") {
          ok = nt == 5 && !more && scalar_from_name(t[2], &p.count_type) &&
               scalar_from_name(t[3], &p.type);
          if (ok && !scalar_is_integer(p.count_type))
            return header_error(err, "list count type must be an integer type, found " +
                                         quote(t[2]));
          p.is_list = true;
          if (ok) p.name = std::string(t[4]);
        } else {
          ok = nt == 3 && !more && scalar_from_name(t[1], &p.type);
          if (ok) p.name = std::string(t[2]);
        }
        if (!ok)
          return header_error(err, "expected 'property <type> <name>' or 'property "
                                   "list <count type> <item type> <name>' with a "
                                   "known type (char uchar short ushort int uint "
                                   "float double, int8 ... float64), found " +
                                       quote(line, 60));
        Element &e = elements_.back();
        if (p.is_list) e.has_list = true;
        else e.fixed_size += scalar_size(p.type);
        e.props.push_back(std::move(p));
      } else if (kw == "end_header") {
        break;
      } else {
        return header_error(err, "unexpected header line " + quote(line));
      }
    }
    if (!have_format) return header_error(err, "no 'format' line before 'end_header'");
    vindex_ = elements_.size();
    for (size_t i = 0; i < elements_.size(); ++i)
      if (elements_[i].name == "vertex") {
        vindex_ = i;
        break;
      }
    if (vindex_ == elements_.size())
      return header_error(err, "the file has no 'vertex' element, so no points");
    const Element &v = elements_[vindex_];
    static const char *kAxes[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
      axis_[a] = SIZE_MAX;
      for (size_t i = 0; i < v.props.size(); ++i)
        if (v.props[i].name == kAxes[a]) {
          axis_[a] = i;
          break;
        }
      if (axis_[a] == SIZE_MAX)
        return header_error(err, std::string("the 'vertex' element has no '") +
                                     kAxes[a] +
                                     "' property; pitvol needs x, y and z per vertex");
      if (v.props[axis_[a]].is_list)
        return header_error(err, std::string("vertex property '") + kAxes[a] +
                                     "' is a list; it must be a single number");
    }
    if (!v.has_list && v.fixed_size > kMaxRecordBytes)
      return header_error(err, "vertex record of " + std::to_string(v.fixed_size) +
                                   " bytes is too large");
    vcount_ = v.count;
    return true;
  }

  // ---- errors --------------------------------------------------------
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
  bool ended(Error *err, const Element &e, uint64_t done) {
    if (src_.read_failed()) return fail_b(err, src_.read_error_text());
    std::string what = &e == &elements_[vindex_] ? "vertices"
                                                 : "'" + e.name + "' elements";
    return fail_b(err, "file ends after " + std::to_string(done) + " of " +
                           std::to_string(e.count) + " " + what + " declared" +
                           where() + "; the file is truncated, copy or export it again");
  }

  // ---- ascii ---------------------------------------------------------
  // Next non-blank line; false at end of file (err set) or on a bad line.
  bool next_line(std::string_view *line, const Element &e, uint64_t done, Error *err) {
    for (;;) {
      ByteSource::Line r = src_.read_line(line);
      if (r == ByteSource::Line::End || r == ByteSource::Line::ReadError)
        return ended(err, e, done);
      ++line_;
      if (r == ByteSource::Line::TooLong)
        return fail_b(err, "line " + std::to_string(line_) + " is longer than " +
                               std::to_string(kBufferBytes) + " bytes");
      for (char c : *line)
        if (c != ' ' && c != '\t' && c != '\r') return true;
    }
  }

  bool ascii_instance(const Element &e, uint64_t done, pv_point_t *p, Error *err) {
    std::string_view line;
    if (!next_line(&line, e, done, err)) return false;
    Tokenizer tk(line, false);
    std::string_view tok;
    float v[3] = {0, 0, 0};
    for (size_t i = 0; i < e.props.size(); ++i) {
      const Property &pr = e.props[i];
      if (!tk.next(&tok))
        return fail_b(err, at() + "too few values for the '" + e.name +
                               "' element; the header lists " +
                               std::to_string(e.props.size()) + " properties");
      if (pr.is_list) {
        uint64_t cnt = 0;
        if (!parse_u64(tok, &cnt))
          return fail_b(err, at() + quote(tok) + " is not a valid list count (property '" +
                                 pr.name + "')");
        for (uint64_t k = 0; k < cnt; ++k) {
          if (!tk.next(&tok))
            return fail_b(err, at() + "list '" + pr.name + "' declares " +
                                   std::to_string(cnt) + " items but has fewer");
          if (!is_number(tok))
            return fail_b(err, at() + quote(tok) + " is not a number (list '" +
                                   pr.name + "')");
        }
        continue;
      }
      int axis = p ? (i == axis_[0] ? 0 : i == axis_[1] ? 1 : i == axis_[2] ? 2 : -1) : -1;
      float f;
      if (!parse_float(tok, &f))
        return fail_b(err, at() + quote(tok) + " is not a number (property '" +
                               pr.name + "')");
      if (axis >= 0) v[axis] = f;
    }
    if (tk.next(&tok))
      return fail_b(err, at() + "more values than the header lists for the '" +
                             e.name + "' element (" + std::to_string(e.props.size()) +
                             " properties); header and data disagree");
    if (p) {
      p->x_mm = v[0];
      p->y_mm = v[1];
      p->z_mm = v[2];
    }
    return true;
  }

  std::string at() const { return "line " + std::to_string(line_) + ": "; }

  bool ascii_vertex(const Element &v, pv_point_t *p, Error *err) {
    return ascii_instance(v, done_, p, err);
  }

  // ---- binary --------------------------------------------------------
  // The common case, x y z as little-endian float32 in fixed-size records
  // on a little-endian host: copied straight from the buffer, whole records
  // at a time (the general path decodes each property through a double:
  // 3-4 M points/s end to end, slower than the core takes them). Same values: a float32 read as
  // double and back is itself.
  bool fast_f32_xyz(const Element &v) {
    if (fast_checked_) return fast_;
    fast_checked_ = true;
    const uint16_t probe = 1;
    unsigned char first = 0;
    std::memcpy(&first, &probe, 1);
    fast_ = !ascii_ && !v.has_list && !big_endian_ && first == 1;
    for (int a = 0; a < 3 && fast_; ++a) {
      fast_ = v.props[axis_[a]].type == Scalar::F32;
      size_t off = 0;
      for (size_t i = 0; i < axis_[a]; ++i) off += scalar_size(v.props[i].type);
      fast_off_[a] = off;
    }
    return fast_;
  }

  // As many whole records as the buffer holds, up to cap; the general path
  // takes over for a record split across refills and for errors.
  size_t read_f32_run(const Element &v, pv_point_t *out, size_t cap) {
    const size_t rec = v.fixed_size;
    size_t n = 0;
    while (n < cap && done_ < vcount_) {
      if (src_.avail() < rec && !src_.ensure(rec)) break;
      size_t k = src_.avail() / rec;
      k = std::min<size_t>(k, cap - n);
      k = size_t(std::min<uint64_t>(k, vcount_ - done_));
      const unsigned char *d = src_.data();
      for (size_t i = 0; i < k; ++i, d += rec) {
        std::memcpy(&out[n + i].x_mm, d + fast_off_[0], 4);
        std::memcpy(&out[n + i].y_mm, d + fast_off_[1], 4);
        std::memcpy(&out[n + i].z_mm, d + fast_off_[2], 4);
      }
      src_.advance(k * rec);
      n += k;
      done_ += k;
    }
    return n;
  }

  bool fixed_vertex(const Element &v, pv_point_t *p, Error *err) {
    if (!src_.ensure(v.fixed_size)) return ended(err, v, done_);
    const unsigned char *d = src_.data();
    float xyz[3] = {0, 0, 0};
    size_t off = 0;
    for (size_t i = 0; i < v.props.size(); ++i) {
      const Property &pr = v.props[i];
      for (int a = 0; a < 3; ++a)
        if (axis_[a] == i) xyz[a] = to_float(decode_scalar(d + off, pr.type, big_endian_));
      off += scalar_size(pr.type);
    }
    src_.advance(v.fixed_size);
    p->x_mm = xyz[0];
    p->y_mm = xyz[1];
    p->z_mm = xyz[2];
    return true;
  }

  // One instance of an element with list properties; p may be NULL.
  bool binary_instance(const Element &e, uint64_t done, pv_point_t *p, Error *err) {
    float xyz[3] = {0, 0, 0};
    for (size_t i = 0; i < e.props.size(); ++i) {
      const Property &pr = e.props[i];
      if (pr.is_list) {
        size_t cs = scalar_size(pr.count_type);
        if (!src_.ensure(cs)) return ended(err, e, done);
        double c = decode_scalar(src_.data(), pr.count_type, big_endian_);
        if (!(c < 18446744073709551616.0)) return ended(err, e, done);
        if (c < 0)
          return fail_b(err, "negative list count in property '" + pr.name + "'" +
                                 where() + "; the file is corrupt");
        src_.advance(cs);
        uint64_t bytes = 0;
        if (!mul_u64(static_cast<uint64_t>(c), scalar_size(pr.type), &bytes) ||
            src_.skip(bytes) != bytes)
          return ended(err, e, done);
        continue;
      }
      size_t s = scalar_size(pr.type);
      if (!src_.ensure(s)) return ended(err, e, done);
      if (p)
        for (int a = 0; a < 3; ++a)
          if (axis_[a] == i) xyz[a] = to_float(decode_scalar(src_.data(), pr.type, big_endian_));
      src_.advance(s);
    }
    if (p) {
      p->x_mm = xyz[0];
      p->y_mm = xyz[1];
      p->z_mm = xyz[2];
    }
    return true;
  }

  bool binary_vertex(const Element &v, pv_point_t *p, Error *err) {
    return binary_instance(v, done_, p, err);
  }

  bool skip_element(const Element &e, Error *err) {
    if (!ascii_ && !e.has_list) {
      uint64_t bytes = 0;
      if (!mul_u64(e.count, e.fixed_size, &bytes)) bytes = UINT64_MAX;
      uint64_t got = src_.skip(bytes);
      if (got == bytes) return true;
      return ended(err, e, e.fixed_size ? got / e.fixed_size : 0);
    }
    if (e.props.empty()) return true;  // nothing stored per instance
    for (uint64_t k = 0; k < e.count; ++k) {
      bool ok = ascii_ ? ascii_instance(e, k, nullptr, err)
                       : binary_instance(e, k, nullptr, err);
      if (!ok) return false;
    }
    return true;
  }

  // The vertex element is the last one: only whitespace may follow (ascii)
  // or at most a line break (binary).
  bool check_tail(Error *err) {
    switch (src_.rest_of_file(ascii_, &line_)) {
      case ByteSource::Tail::Clean: return true;
      case ByteSource::Tail::ReadError: return fail_b(err, src_.read_error_text());
      case ByteSource::Tail::Data: break;
    }
    return fail_b(err, "data continues after the " + std::to_string(vcount_) +
                           " vertices declared" + where() +
                           "; the header's vertex count is wrong or the file is corrupt");
  }

  ByteSource src_;
  std::vector<Element> elements_;
  size_t nprops_ = 0;
  size_t vindex_ = 0;
  size_t axis_[3] = {0, 0, 0};
  bool fast_checked_ = false, fast_ = false;  // fast_f32_xyz
  size_t fast_off_[3] = {0, 0, 0};
  uint64_t vcount_ = 0, done_ = 0, line_ = 0;
  bool ascii_ = false, big_endian_ = false;
  bool skipped_before_ = false, checked_tail_ = false;
};

}  // namespace

std::unique_ptr<ScanReader> open_ply(const std::string &path, Error *err) {
  auto r = std::make_unique<PlyReader>();
  if (!r->open(path, err)) return nullptr;
  return r;
}

}  // namespace pv::scanio::detail
