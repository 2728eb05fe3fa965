// Registers explicit_euler and symplectic_euler (one class, two schemes).
#include "tissue_trainer/core/integrate/explicit_euler.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {
namespace {

IntegratorEntry eulerEntry(const char* name, const char* description, bool symplectic) {
  IntegratorEntry e;
  e.name = name;
  e.description = description;
  e.keys = {{"time_step", "longest substep (s, default 1e-4)"}};
  e.make = [symplectic](const YamlEntry& spec, Notes&) -> std::unique_ptr<Integrator> {
    ExplicitEulerParams p;
    p.substep = spec.positive("time_step", p.substep);
    p.symplectic = symplectic;
    return std::make_unique<ExplicitEulerIntegrator>(p);
  };
  return e;
}

}  // namespace

void registerExplicitEuler(Registry& registry) {
  registry.add(eulerEntry("explicit_euler", "forward Euler (unstable without damping)", false));
  registry.add(eulerEntry("symplectic_euler", "semi-implicit Euler: x+ = x + h v+", true));
}

}  // namespace tt
