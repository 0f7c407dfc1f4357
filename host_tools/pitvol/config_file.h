// --config FILE: "key = value" lines setting pv_config_t fields by name.
#ifndef PV_TOOLS_CONFIG_FILE_H
#define PV_TOOLS_CONFIG_FILE_H

#include <string>

#include "pitvol/pitvol.h"

namespace pv::tools {

// Applies the file's settings on top of *cfg. On failure returns false and
// sets *error to "FILE:LINE: what is wrong".
bool load_config_file(const std::string &path, pv_config_t *cfg, std::string *error);

}  // namespace pv::tools

#endif
