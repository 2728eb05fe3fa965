#pragma once
// Name -> object for the scene's force models and integrators. Only the listed ones are
// constructed. Each throws InputError through the entry for unknown types or options.
#include <memory>

#include "tissue_trainer/core/integrate/integrator.h"
#include "tissue_trainer/core/scene/yaml_reader.h"
#include "tissue_trainer/core/system.h"

namespace tt {

std::unique_ptr<ForceModel> makeForceModel(const YamlEntry& spec, const System& system);
std::unique_ptr<Integrator> makeIntegrator(const YamlEntry& spec);

// The elastic models by name with default options, for tissue_cli forces; nullptr when the
// name is unknown. `names` lists the known ones.
std::unique_ptr<ForceModel> makeElasticModel(const std::string& name, const Mesh& mesh,
                                             const std::vector<Material>& materials);
extern const char* const kElasticModelNames;

}  // namespace tt
