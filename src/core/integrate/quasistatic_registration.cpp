// Registers quasistatic in the scene registry.
#include "tissue_trainer/core/integrate/quasistatic.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {

void registerQuasistatic(Registry& registry) {
  IntegratorEntry e;
  e.name = "quasistatic";
  e.description = "equilibrium at each frame's end (Newton-Raphson, PCG, line search)";
  e.keys = {{"abs_tolerance", "converged when |f| over the free DOFs is at most this (N, default "
                              "1e-9) ..."},
            {"rel_tolerance", "... or at most this fraction of |f| at the frame's start "
                              "(default 1e-9)"},
            {"max_newton_iterations", "Newton iterations per frame (integer >= 1, default 50)"},
            {"linear_tolerance", "relative residual of each CG solve (default 1e-10)"},
            {"linear_max_iterations", "iteration limit of each CG solve (integer >= 1, default "
                                      "2000)"},
            {"max_line_search", "halvings of a Newton step before it is given up (integer >= 0, "
                                "default 30)"},
            {"max_pseudo_time_steps", "pseudo-time steps per frame when a Newton step finds no "
                                      "decrease, e.g. from inverted elements (integer >= 0, "
                                      "default 200; 0 fails the frame there)"},
            {"preconditioner", "of the CG solves: jacobi (default) or cholesky (a sparse "
                               "Cholesky factor of a Newton matrix)"},
            {"refactor_above", "cholesky: the factor is kept across Newton iterations and "
                               "frames while CG needs at most this many iterations with it "
                               "(integer >= 0, default 20; 0: a new factor every iteration)"}};
  e.make = [](const YamlEntry& spec) -> std::unique_ptr<Integrator> {
    EquilibriumParams p;
    p.absoluteTolerance = spec.positive("abs_tolerance", p.absoluteTolerance);
    p.relativeTolerance = spec.positive("rel_tolerance", p.relativeTolerance);
    p.maxNewtonIterations = spec.integerAtLeast("max_newton_iterations", 1, p.maxNewtonIterations);
    p.linearTolerance = spec.positive("linear_tolerance", p.linearTolerance);
    p.linearMaxIterations = spec.integerAtLeast("linear_max_iterations", 1, p.linearMaxIterations);
    p.maxLineSearchSteps = spec.integerAtLeast("max_line_search", 0, p.maxLineSearchSteps);
    p.refactorAbove = spec.integerAtLeast("refactor_above", 0, p.refactorAbove);
    p.maxPseudoTimeSteps = spec.integerAtLeast("max_pseudo_time_steps", 0, p.maxPseudoTimeSteps);
    if (spec.has("preconditioner"))
      p.preconditioner = spec["preconditioner"].choice({"jacobi", "cholesky"}) == "cholesky"
                             ? EquilibriumParams::Preconditioning::kCholesky
                             : EquilibriumParams::Preconditioning::kJacobi;
    return std::make_unique<QuasistaticIntegrator>(p);
  };
  registry.add(std::move(e));
}

}  // namespace tt
