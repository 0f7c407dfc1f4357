// The host tools' JSON (nlohmann/json, Debian's nlohmann-json3-dev): an
// object keeps its fields in the order they were added, and json_line()
// is how every tool prints one.
#ifndef PV_TOOLS_JSON_H
#define PV_TOOLS_JSON_H

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <nlohmann/json.hpp>

namespace pv::tools {

using Json = nlohmann::ordered_json;

// A double with no fraction as an integer (95, not nlohmann's 95.0), as
// the tools printed it before nlohmann.
inline void json_integral_as_integer(Json &j) {
  if (j.is_number_float()) {
    const double v = j.get<double>();
    if (std::isfinite(v) && v == std::trunc(v) && std::fabs(v) < 9007199254740992.0)  // 2^53
      j = static_cast<std::int64_t>(v);
  } else if (j.is_structured()) {
    for (Json &e : j) json_integral_as_integer(e);
  }
}

// One line of ASCII as the tools have always printed it: `{"key": value,
// "key": [a, b]}` (scripts and the tests match `"key": ` with sed and
// grep). Every other character is a \u escape, so no byte a terminal acts
// on (C0, DEL, C1 controls) reaches it; bytes that are not UTF-8 become
// U+FFFD. NaN and infinities print as null; a double as the shortest text
// that reads back as the same double (0.1, not %.17g's 0.10000000000000001),
// without a fraction as an integer.
inline std::string json_line(Json j) {
  json_integral_as_integer(j);
  const std::string c = j.dump(-1, ' ', true, Json::error_handler_t::replace);
  std::string o;
  o.reserve(c.size() + c.size() / 8);
  bool in_string = false;
  for (size_t i = 0; i < c.size(); ++i) {
    o += c[i];
    if (in_string) {
      if (c[i] == '\\') o += c[++i];  // an escape: the next byte is not a quote that ends it
      else if (c[i] == '"') in_string = false;
    } else if (c[i] == '"') {
      in_string = true;
    } else if (c[i] == ',' || c[i] == ':') {
      o += ' ';
    }
  }
  return o;
}

// An object with one top-level field a line (a file a person may read):
// "{\n  \"key\": value,\n ...\n}".
inline std::string json_lines(const Json &object) {
  std::string o = "{";
  for (auto it = object.begin(); it != object.end(); ++it) {
    o += std::string(it == object.begin() ? "\n  " : ",\n  ") + json_line(it.key()) + ": " +
         json_line(it.value());
  }
  return o + "\n}";
}

// v to `decimals` places exactly as printf("%.*f") rounds it, as a double
// that prints with those digits (trailing zeros dropped: 0.250 as 0.25).
inline double json_decimals(double v, int decimals) {
  if (!std::isfinite(v) || std::fabs(v) >= 1e15) return v;  // no fraction to round
  char b[64];
  std::snprintf(b, sizeof b, "%.*f", decimals, v);
  return std::strtod(b, nullptr);
}

}  // namespace pv::tools

#endif
