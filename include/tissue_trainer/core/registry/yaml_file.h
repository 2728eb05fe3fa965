#pragma once
// Reads a YAML file whole for the readers of scenes, tasks and settings: a file that cannot be
// opened or is not valid YAML is one InputError naming the file (and the line, where YAML
// gives one).
#include <yaml-cpp/yaml.h>

#include <string>

namespace tt {

// `kind` names the file in the error, e.g. "scene file": "PATH: cannot open the scene file".
YAML::Node loadYamlFile(const std::string& path, const std::string& kind);

}  // namespace tt
