// Registers newtonian in the scene registry.
#include "tissue_trainer/core/integrate/newtonian.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {

void registerNewtonian(Registry& registry) {
  IntegratorEntry e;
  e.name = "newtonian";
  e.description = "variable-step explicit central-difference scheme on positions";
  e.keys = {{"time_step", "longest substep (s, default 1e-3)"},
            {"equal_steps", "true: the equal-step form, even when steps change"},
            {"force_threshold", "N; free nodes with a smaller net force stay put (default 0: off)"}};
  e.make = [](const YamlEntry& spec, Notes&) -> std::unique_ptr<Integrator> {
    NewtonianParams p;
    p.substep = spec.positive("time_step", p.substep);
    p.assumeEqualSteps = spec.boolean("equal_steps", p.assumeEqualSteps);
    if (spec.has("force_threshold")) {
      const YamlEntry t = spec["force_threshold"];
      p.forceThreshold = t.number();
      if (p.forceThreshold < 0.0) t.fail("expected a non-negative force threshold (N)");
    }
    return std::make_unique<NewtonianIntegrator>(p);
  };
  registry.add(std::move(e));
}

}  // namespace tt
