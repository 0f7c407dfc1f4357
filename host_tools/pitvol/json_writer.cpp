#include "json_writer.h"

#include <cmath>
#include <cstdio>

namespace pv::tools {

std::string json_escape(const std::string &s) {
  std::string o = "\"";
  for (const unsigned char c : s) {
    switch (c) {
      case '"': o += "\\\""; break;
      case '\\': o += "\\\\"; break;
      case '\n': o += "\\n"; break;
      case '\r': o += "\\r"; break;
      case '\t': o += "\\t"; break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          o += buf;
        } else {
          o += char(c);
        }
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
