// Registers abm3 in the scene registry.
#include "tissue_trainer/core/integrate/abm3.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {

namespace {

double positiveFraction(const YamlEntry& spec, const char* key, double fallback) {
  if (!spec.has(key)) return fallback;
  const YamlEntry entry = spec[key];
  const double value = entry.number();
  if (!(value > 0.0 && value < 1.0)) entry.fail("expected a number between 0 and 1 (exclusive)");
  return value;
}

Abm3Params readParams(const YamlEntry& spec) {
  Abm3Params p;
  p.adaptive = spec.boolean("adaptive", p.adaptive);
  p.timeStep = spec.positive("time_step", p.timeStep);
  if (spec.has("start"))
    p.start = spec["start"].choice({"rk3", "euler"}) == "euler" ? Abm3Params::Start::kEuler
                                                                 : Abm3Params::Start::kRungeKutta3;
  if (spec.has("history_interpolation"))
    p.interpolation = spec["history_interpolation"].choice({"linear", "hermite"}) == "hermite"
                          ? Abm3Params::Interpolation::kHermite
                          : Abm3Params::Interpolation::kLinear;
  p.absTol = spec.positive("abs_tol", p.absTol);
  p.absTolVelocity = spec.positive("abs_tol_velocity", p.absTol);
  if (spec.has("rel_tol")) {
    const YamlEntry entry = spec["rel_tol"];
    p.relTol = entry.number();
    if (!(p.relTol >= 0.0)) entry.fail("expected a non-negative relative tolerance");
  }
  p.lowerRatio = positiveFraction(spec, "lower_ratio", p.lowerRatio);
  p.minStep = spec.positive("min_step", p.minStep);
  p.maxStep = spec.positive("max_step", p.maxStep);
  if (p.maxStep < p.minStep) spec["max_step"].fail("expected max_step >= min_step");
  return p;
}

}  // namespace

void registerAbm3(Registry& registry) {
  IntegratorEntry e;
  e.name = "abm3";
  e.description = "third-order Adams-Bashforth-Moulton predictor-corrector, halving/doubling step";
  e.keys = {{"adaptive", "false: fixed steps no longer than time_step (default true)"},
            {"time_step", "first step, or the longest fixed step (s, default 1e-4)"},
            {"start", "starting steps: rk3 (third-order Runge-Kutta, default) | euler"},
            {"history_interpolation", "points between kept ones on a halving: linear (default) "
                                      "| hermite"},
            {"abs_tol", "upper threshold of the predictor-corrector difference, positions (m, "
                        "default 1e-6)"},
            {"abs_tol_velocity", "the same for velocities (m/s, default: abs_tol)"},
            {"rel_tol", "relative part of both thresholds, times |value| (default 1e-6)"},
            {"lower_ratio", "every difference below this fraction of the threshold doubles the "
                            "step (0 < r < 1, default 0.03)"},
            {"min_step", "shortest step; shorter fails the frame (s, default 1e-12)"},
            {"max_step", "longest step (s, default unlimited)"}};
  e.make = [](const YamlEntry& spec, Notes&) -> std::unique_ptr<Integrator> {
    return std::make_unique<Abm3Integrator>(readParams(spec));
  };
  registry.add(std::move(e));
}

}  // namespace tt
