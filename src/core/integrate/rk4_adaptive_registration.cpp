// Registers rk4_adaptive in the scene registry.
#include "tissue_trainer/core/integrate/rk4_adaptive.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {

namespace {

Rk4AdaptiveParams readParams(const YamlEntry& spec) {
  Rk4AdaptiveParams p;
  p.adaptive = spec.boolean("adaptive", p.adaptive);
  p.timeStep = spec.positive("time_step", p.timeStep);
  p.absTol = spec.positive("abs_tol", p.absTol);
  p.absTolVelocity = spec.positive("abs_tol_velocity", p.absTol);
  if (spec.has("rel_tol")) {
    const YamlEntry entry = spec["rel_tol"];
    p.relTol = entry.number();
    if (!(p.relTol >= 0.0)) entry.fail("expected a non-negative relative tolerance");
  }
  p.extrapolate = spec.boolean("extrapolate", p.extrapolate);
  p.minStep = spec.positive("min_step", p.minStep);
  p.maxStep = spec.positive("max_step", p.maxStep);
  if (p.maxStep < p.minStep) spec["max_step"].fail("expected max_step >= min_step");
  p.maxSubsteps = spec.integerAtLeast("max_substeps", 1, static_cast<int>(p.maxSubsteps));
  return p;
}

}  // namespace

void registerRk4Adaptive(Registry& registry) {
  IntegratorEntry e;
  e.name = "rk4_adaptive";
  e.description = "classical fourth-order Runge-Kutta, step size by step doubling (Numerical "
                  "Recipes Sec. 16.2)";
  e.keys = {{"adaptive", "false: fixed steps no longer than time_step (default true)"},
            {"time_step", "first step, or the longest fixed step (s, default 1e-4)"},
            {"abs_tol", "absolute tolerance of the doubling error estimate, positions (m, "
                        "default 1e-6)"},
            {"abs_tol_velocity", "the same for velocities (m/s, default: abs_tol)"},
            {"rel_tol", "relative part of both tolerances, times |value| (default 1e-6)"},
            {"extrapolate", "keep the locally extrapolated fifth-order state (default true)"},
            {"min_step", "shortest step; a shorter proposal fails the frame (s, default 1e-12)"},
            {"max_step", "longest step (s, default unlimited)"},
            {"max_substeps", "steps per frame, kept and rejected, before the frame fails "
                             "(integer >= 1, default 100000)"}};
  e.make = [](const YamlEntry& spec, Notes&) -> std::unique_ptr<Integrator> {
    return std::make_unique<Rk4AdaptiveIntegrator>(readParams(spec));
  };
  registry.add(std::move(e));
}

}  // namespace tt
