#include "tissue_trainer/core/registry/yaml_file.h"

#include <fstream>

#include "tissue_trainer/core/error.h"

namespace tt {

YAML::Node loadYamlFile(const std::string& path, const std::string& kind) {
  if (!std::ifstream(path)) throw InputError(path, 0, "cannot open the " + kind);
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw InputError(path, 0, "cannot open the " + kind);
  } catch (const YAML::Exception& e) {
    throw InputError(path, e.mark.line >= 0 ? e.mark.line + 1 : 0, "not valid YAML: " + e.msg);
  }
}

}  // namespace tt
