#include "json_writer.h"

#include <cmath>
#include <cstdio>

namespace pv::tools {

// Valid UTF-8 out, and nothing a terminal acts on: C0, DEL and C1
// controls are \u escapes; a byte that is not part of a UTF-8 sequence is
// taken as Latin-1 (\u00XX), so the text survives and stays readable.
std::string json_escape(const std::string &s) {
  std::string o = "\"";
  char buf[8];
  for (size_t i = 0; i < s.size();) {
    const auto c = static_cast<unsigned char>(s[i]);
    switch (c) {
      case '"': o += "\\\""; ++i; continue;
      case '\\': o += "\\\\"; ++i; continue;
      case '\n': o += "\\n"; ++i; continue;
      case '\r': o += "\\r"; ++i; continue;
      case '\t': o += "\\t"; ++i; continue;
      default: break;
    }
    if (c >= 0x20 && c < 0x7f) {
      o += char(c);
      ++i;
      continue;
    }
    size_t n = c >= 0xc2 && c <= 0xdf ? 2 : c >= 0xe0 && c <= 0xef ? 3 : c >= 0xf0 && c <= 0xf4 ? 4 : 0;
    if (n > 0 && i + n <= s.size()) {
      for (size_t k = 1; k < n; ++k)
        if ((static_cast<unsigned char>(s[i + k]) & 0xc0) != 0x80) n = 0;
    } else {
      n = 0;
    }
    if (n == 2 && c == 0xc2 && static_cast<unsigned char>(s[i + 1]) < 0xa0) {
      std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned char>(s[i + 1]));
      o += buf;
      i += 2;
    } else if (n > 0) {
      o.append(s, i, n);
      i += n;
    } else {
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      o += buf;
      ++i;
    }
  }
  return o + "\"";
}

void JsonObject::key(const std::string &k) {
  if (!body_.empty()) body_ += ", ";
  body_ += json_escape(k) + ": ";
}

JsonObject &JsonObject::num(const std::string &k, double v) {
  if (!std::isfinite(v)) return null(k);
  key(k);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  body_ += buf;
  return *this;
}

JsonObject &JsonObject::integer(const std::string &k, uint64_t v) {
  key(k);
  body_ += std::to_string(v);
  return *this;
}

JsonObject &JsonObject::str(const std::string &k, const std::string &v) {
  key(k);
  body_ += json_escape(v);
  return *this;
}

JsonObject &JsonObject::null(const std::string &k) {
  key(k);
  body_ += "null";
  return *this;
}

JsonObject &JsonObject::raw(const std::string &k, const std::string &json) {
  key(k);
  body_ += json;
  return *this;
}

JsonObject &JsonObject::strings(const std::string &k, const std::vector<std::string> &v) {
  std::string a = "[";
  for (size_t i = 0; i < v.size(); ++i) a += (i ? ", " : "") + json_escape(v[i]);
  return raw(k, a + "]");
}

}  // namespace pv::tools
