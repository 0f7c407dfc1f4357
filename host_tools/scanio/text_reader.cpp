// XYZ / ASC / TXT / CSV: one point per line, x y z = first three numbers.

#include "scanio/byte_source.h"

namespace pv::scanio::detail {
namespace {

constexpr uint64_t kMaxHeaderLines = 100;

class TextReader final : public ScanReader {
 public:
  explicit TextReader(Format f) : ScanReader(f) {}

  bool open(const std::string &path, Error *err) {
    if (!src_.open(path, err)) return false;
    bytes_total_ = src_.size();
    return true;
  }

  long read_points(pv_point_t *out, size_t cap, Error *err) override {
    size_t n = 0;
    while (n < cap && !done_) {
      std::string_view line;
      switch (src_.read_line(&line)) {
        case ByteSource::Line::End:
          done_ = true;
          if (points_ == 0)
            return fail(err,
                        "no points found: the file has " +
                            std::to_string(line_) +
                            " line(s) but none with x y z numbers",
                        line_);
          continue;
        case ByteSource::Line::TooLong:
          return fail(err,
                      "line " + std::to_string(line_ + 1) +
                          " is longer than " + std::to_string(kBufferBytes) +
                          " bytes; is this really a text point file?",
                      line_ + 1);
        case ByteSource::Line::ReadError:
          return fail(err, src_.read_error_text(), line_ + 1);
        case ByteSource::Line::Ok: break;
      }
      ++line_;
      if (parse_line(line, &out[n], err) < 0) return -1;
      if (got_point_) ++n;
    }
    return static_cast<long>(n);
  }
  uint64_t position() const override { return src_.offset(); }

 private:
  // Sets got_point_; -1 on error.
  int parse_line(std::string_view line, pv_point_t *p, Error *err) {
    got_point_ = false;
    size_t i = 0;
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    std::string_view s = line.substr(i);
    if (s.empty() || s[0] == '#' || (s.size() >= 2 && s[0] == '/' && s[1] == '/'))
      return 0;  // blank or comment
    Tokenizer tk(s, true);
    float v[3];
    int k = 0;
    std::string_view tok;
    while (k < 3 && tk.next(&tok)) {
      if (!parse_float(tok, &v[k])) {
        if (k == 0 && points_ == 0) {  // header line before the data
          if (++header_lines_ > kMaxHeaderLines)
            return fail(err,
                        "line " + std::to_string(line_) +
                            ": no numeric x y z line in the first " +
                            std::to_string(kMaxHeaderLines) +
                            " lines; is this really a text point file?",
                        line_);
          return 0;
        }
        return fail(err,
                    "line " + std::to_string(line_) + ": " + quote(tok) +
                        " is not a number (column " + std::to_string(k + 1) +
                        "); expected x y z in the first three columns: " +
                        quote(s, 60),
                    line_);
      }
      ++k;
    }
    if (k == 0) return 0;  // only separators
    if (k < 3)
      return fail(err,
                  "line " + std::to_string(line_) + ": only " +
                      std::to_string(k) +
                      " number(s), expected at least x y z: " + quote(s, 60),
                  line_);
    p->x_mm = v[0];
    p->y_mm = v[1];
    p->z_mm = v[2];
    ++points_;
    got_point_ = true;
    return 0;
  }

  int fail(Error *err, std::string msg, uint64_t line) {
    *err = Error{};
    err->message = std::move(msg);
    err->line = line;
    err->byte_offset = src_.offset();
    return -1;
  }

  ByteSource src_;
  uint64_t line_ = 0, points_ = 0, header_lines_ = 0;
  bool got_point_ = false, done_ = false;
};

}  // namespace

std::unique_ptr<ScanReader> open_text(const std::string &path, Format f,
                                      Error *err) {
  auto r = std::make_unique<TextReader>(f);
  if (!r->open(path, err)) return nullptr;
  return r;
}

}  // namespace pv::scanio::detail
