// Registers radau_iia in the scene registry.
#include "tissue_trainer/core/integrate/radau_iia.h"
#include "tissue_trainer/core/registry/newton_keys.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {

void registerRadauIIA(Registry& registry) {
  IntegratorEntry e;
  e.name = "radau_iia";
  e.description = "implicit 3-stage Radau IIA (order 5) with step-size control";
  e.keys = {{"jacobian", "analytical (default) | numerical | simplified"},
            {"abs_tol", "absolute tolerance on positions (m, default 1e-6)"},
            {"rel_tol", "relative tolerance (default 1e-6)"},
            {"adaptive", "false: fixed steps of initial_step (default true)"},
            {"initial_step", "first (or fixed) step (s, default 1e-3)"},
            {"max_step", "longest step (s)"},
            {"max_newton_iterations", "Newton iterations per step (integer >= 1, default 7)"}};
  e.make = [](const YamlEntry& spec, Notes& notes) -> std::unique_ptr<Integrator> {
    RadauOptions o;
    if (spec.has("jacobian")) {
      const std::string j = spec["jacobian"].choice({"analytical", "numerical", "simplified"});
      o.jacobian = j == "analytical" ? RadauJacobian::kAnalytical
                   : j == "numerical" ? RadauJacobian::kNumerical : RadauJacobian::kSimplified;
    }
    o.absTol = spec.positive("abs_tol", o.absTol);
    o.relTol = spec.positive("rel_tol", o.relTol);
    o.adaptive = spec.boolean("adaptive", o.adaptive);
    o.initialStep = spec.positive("initial_step", o.initialStep);
    o.maxStep = spec.positive("max_step", o.maxStep);
    o.maxNewtonIterations = readMaxNewtonIterations(spec, o.maxNewtonIterations, notes);
    return std::make_unique<RadauIIA>(o);
  };
  registry.add(std::move(e));
}

}  // namespace tt
