// A minimal JSON object writer for the CLI's single-object output.
#ifndef PV_TOOLS_JSON_WRITER_H
#define PV_TOOLS_JSON_WRITER_H

#include <cstdint>
#include <string>
#include <vector>

namespace pv::tools {

class JsonObject {
 public:
  JsonObject &num(const std::string &key, double v);  // NaN/Inf -> null
  JsonObject &integer(const std::string &key, uint64_t v);
  JsonObject &str(const std::string &key, const std::string &v);
  JsonObject &null(const std::string &key);
  JsonObject &raw(const std::string &key, const std::string &json);
  JsonObject &strings(const std::string &key, const std::vector<std::string> &v);
  std::string text() const { return "{" + body_ + "}"; }

 private:
  void key(const std::string &k);
  std::string body_;
};

std::string json_escape(const std::string &s);

}  // namespace pv::tools

#endif
