// Registers quasistatic in the scene registry.
#include "tissue_trainer/core/integrate/quasistatic.h"
#include "tissue_trainer/core/registry/linear_solve_keys.h"
#include "tissue_trainer/core/registry/newton_keys.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {

namespace {

// The Newton steps are solved by PCG with a factor made at once: its non-positive curvature is
// what starts the shifted solves, and a slow step is solved again with the new factor.
void refuseWhatNewtonCannotUse(const YamlEntry& spec, const LinearSolveSettings& s) {
  if (s.method != LinearMethod::kPcg)
    spec["linear_solver"].fail(
        "quasistatic takes pcg only: its Newton steps need CG to report non-positive "
        "curvature, which starts their shifted solves");
  if (s.backgroundRefactor)
    spec["background_refactor"].fail(
        "quasistatic takes false only: a Newton step that was slow with the kept factor is "
        "solved again at once with a new one, which cannot wait for a background factor");
}

}  // namespace

void registerQuasistatic(Registry& registry) {
  IntegratorEntry e;
  e.name = "quasistatic";
  e.description = "equilibrium at each frame's end (Newton-Raphson, PCG, line search)";
  e.keys = {{"newton_abs_tolerance", "converged when |f| over the free DOFs is at most this "
                                     "(N, default 1e-9) ..."},
            {"newton_tolerance", "... or at most this fraction of |f| at the frame's start "
                                 "(default 1e-9)"},
            {"max_newton_iterations", "Newton iterations per frame (integer >= 1, default 50)"},
            {"max_line_search", "halvings of a Newton step before it is given up (integer >= 0, "
                                "default 30)"},
            {"max_pseudo_time_steps", "pseudo-time steps per frame when a Newton step finds no "
                                      "decrease, e.g. from inverted elements (integer >= 0, "
                                      "default 200; 0 fails the frame there)"}};
  for (KeyDoc& key : linearSolveKeyDocs(EquilibriumParams().linearSolve())) {
    if (key.key == "linear_solver") key.description = "pcg only (the default)";
    if (key.key == "gmres_restart") key.description = "gmres only, which quasistatic does not take";
    if (key.key == "background_refactor") key.description = "false only (the default)";
    e.keys.push_back(std::move(key));
  }
  e.keys.push_back({"refactor_above", "deprecated: refactor_iterations, the same meaning"});
  e.keys.push_back({"abs_tolerance", "deprecated: newton_abs_tolerance, the same meaning"});
  e.keys.push_back({"rel_tolerance", "deprecated: newton_tolerance, the same meaning"});
  e.make = [](const YamlEntry& spec, Notes& notes) -> std::unique_ptr<Integrator> {
    EquilibriumParams p;
    p.absoluteTolerance =
        readNewtonAbsTolerance(spec, p.absoluteTolerance, notes, "abs_tolerance");
    p.relativeTolerance = readNewtonTolerance(spec, p.relativeTolerance, notes, "rel_tolerance");
    p.maxNewtonIterations = readMaxNewtonIterations(spec, p.maxNewtonIterations, notes);
    const LinearSolveSettings linear = readLinearSolveSettings(spec, p.linearSolve(), notes);
    refuseWhatNewtonCannotUse(spec, linear);
    p.setLinearSolve(linear);
    p.maxLineSearchSteps = spec.integerAtLeast("max_line_search", 0, p.maxLineSearchSteps);
    p.maxPseudoTimeSteps = spec.integerAtLeast("max_pseudo_time_steps", 0, p.maxPseudoTimeSteps);
    return std::make_unique<QuasistaticIntegrator>(p);
  };
  registry.add(std::move(e));
}

}  // namespace tt
