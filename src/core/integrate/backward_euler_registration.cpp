// Registers backward_euler in the scene registry.
#include <algorithm>

#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/registry/linear_solve_keys.h"
#include "tissue_trainer/core/registry/newton_keys.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {

namespace {

using Params = BackwardEulerParams;

// The iteration-count step control (adaptive: true) and its keys, which apply only with it.
void readStepControl(const YamlEntry& spec, Params& p) {
  p.adaptive = spec.boolean("adaptive", p.adaptive);
  const char* adaptiveKeys[] = {"lower_iterations", "upper_iterations", "initial_step",
                                "min_step", "max_step"};
  for (const char* key : adaptiveKeys)
    if (spec.has(key) && !p.adaptive) spec[key].fail("applies only with adaptive: true");
  if (!p.adaptive) return;
  if (spec.has("substeps")) spec["substeps"].fail("does not apply with adaptive: true");
  p.lowerIterations = spec.integerAtLeast("lower_iterations", 0, p.lowerIterations);
  p.upperIterations = spec.integerAtLeast("upper_iterations", 1, p.upperIterations);
  // Of two keys in conflict, the one given (the first when both are).
  const auto given = [&spec](const char* first, const char* second) {
    return spec.has(first) ? spec[first] : spec[second];
  };
  if (p.upperIterations <= p.lowerIterations)
    given("upper_iterations", "lower_iterations")
        .fail("expected upper_iterations (" + std::to_string(p.upperIterations) +
              ") > lower_iterations (" + std::to_string(p.lowerIterations) + ")");
  if (p.upperIterations > p.linearMaxIterations)
    given("upper_iterations", "linear_max_iterations")
        .fail("expected upper_iterations (" + std::to_string(p.upperIterations) +
              ") <= linear_max_iterations (" + std::to_string(p.linearMaxIterations) + ")");
  p.minStep = spec.positive("min_step", p.minStep);
  p.maxStep = spec.positive("max_step", p.maxStep);
  if (p.maxStep < p.minStep)
    given("max_step", "min_step").fail("expected max_step >= min_step");
  if (spec.has("initial_step")) {
    p.initialStep = spec.positive("initial_step", p.initialStep);
    if (p.initialStep < p.minStep || p.initialStep > p.maxStep)
      spec["initial_step"].fail("expected min_step <= initial_step <= max_step");
  } else {
    p.initialStep = std::clamp(p.initialStep, p.minStep, p.maxStep);
  }
}

void readJacobian(const YamlEntry& spec, Params& p) {
  if (spec.has("jacobian"))
    p.jacobian = spec["jacobian"].choice({"analytic", "finite_difference"}) == "finite_difference"
                     ? Params::Jacobian::kFiniteDifference
                     : Params::Jacobian::kAnalytic;
  const bool differences = p.jacobian == Params::Jacobian::kFiniteDifference;
  for (const char* key : {"coloring", "fd_epsilon", "fd_position_scale", "fd_velocity_scale"})
    if (spec.has(key) && !differences)
      spec[key].fail("applies only with jacobian: finite_difference");
  FiniteDifferenceSettings& fd = p.finiteDifference;
  fd.coloring = spec.boolean("coloring", fd.coloring);
  fd.epsilon = spec.positive("fd_epsilon", fd.epsilon);
  if (fd.epsilon >= 1e-2) spec["fd_epsilon"].fail("expected a relative perturbation below 0.01");
  fd.positionScale = spec.positive("fd_position_scale", fd.positionScale);
  fd.velocityScale = spec.positive("fd_velocity_scale", fd.velocityScale);
}

}  // namespace

void registerBackwardEuler(Registry& registry) {
  IntegratorEntry e;
  e.name = "backward_euler";
  e.description = "linearised implicit Euler (one Newton step), optionally full Newton";
  e.keys = {{"substeps", "equal substeps per frame (integer >= 1, default 1)"},
            {"max_newton_iterations", "Newton iterations per step (integer >= 1; 1: the "
                                      "linearised step, the default; > 1: full Newton)"},
            {"newton_tolerance", "relative residual of the implicit equations (default 1e-6)"},
            {"require_convergence", "true: an unconverged Newton loop fails the frame"},
            {"warm_start", "start the linear solve from the previous solution (default true)"},
            {"adaptive", "true: the step follows the Krylov iteration count (halved and redone "
                         "at upper_iterations, doubled at lower_iterations); default false"},
            {"lower_iterations", "adaptive: at or below, the next step doubles (default 10)"},
            {"upper_iterations", "adaptive: at or above, the step is halved and redone "
                                 "(> lower_iterations, <= linear_max_iterations; default 40)"},
            {"initial_step", "adaptive: the first step (s, default 1e-3 within the bounds)"},
            {"min_step", "adaptive: shortest step, kept whatever it needs (s, default 1e-6)"},
            {"max_step", "adaptive: longest step (s, default unlimited)"},
            {"jacobian", "analytic (default: the models' stiffness and velocity Jacobians) or "
                         "finite_difference (of the total force; any force model)"},
            {"coloring", "finite_difference: perturb DOFs of a distance-2 node colouring "
                         "together (default true)"},
            {"fd_epsilon", "finite_difference: relative perturbation (default 1.49e-8)"},
            {"fd_position_scale", "finite_difference: the perturbation is fd_epsilon * "
                                  "max(|x_i|, this) (m, default the mesh's largest extent)"},
            {"fd_velocity_scale", "finite_difference: the same for velocities (m/s, default 1)"}};
  for (KeyDoc& key : linearSolveKeyDocs(BackwardEulerParams().linearSolve()))
    e.keys.push_back(std::move(key));
  e.keys.push_back({"newton_iterations", "deprecated: max_newton_iterations, the same meaning"});
  e.make = [](const YamlEntry& spec, Notes& notes) -> std::unique_ptr<Integrator> {
    BackwardEulerParams p;
    p.substeps = spec.integerAtLeast("substeps", 1, p.substeps);
    p.setLinearSolve(readLinearSolveSettings(spec, p.linearSolve(), notes));
    readStepControl(spec, p);
    readJacobian(spec, p);
    p.newtonIterations =
        readMaxNewtonIterations(spec, p.newtonIterations, notes, "newton_iterations");
    p.newtonTolerance = readNewtonTolerance(spec, p.newtonTolerance, notes);
    p.requireConvergence = spec.boolean("require_convergence", p.requireConvergence);
    p.warmStart = spec.boolean("warm_start", p.warmStart);
    return std::make_unique<BackwardEulerIntegrator>(p);
  };
  registry.add(std::move(e));
}

}  // namespace tt
