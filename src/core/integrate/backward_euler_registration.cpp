// Registers backward_euler in the scene registry.
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/scene/registry.h"

namespace tt {

void registerBackwardEuler(Registry& registry) {
  IntegratorEntry e;
  e.name = "backward_euler";
  e.description = "linearised implicit Euler (one Newton step), optionally full Newton";
  e.keys = {{"substeps", "equal substeps per frame (integer >= 1, default 1)"},
            {"linear_tolerance", "relative residual of the linear solve (default 1e-8)"},
            {"linear_max_iterations", "iteration limit of the linear solve (default 500)"},
            {"newton_iterations", "1: the linearised step (default); > 1: full Newton"},
            {"newton_tolerance", "relative residual of the implicit equations (default 1e-6)"},
            {"require_convergence", "true: an unconverged Newton loop fails the frame"},
            {"warm_start", "start the linear solve from the previous solution (default true)"},
            {"preconditioner", "of the linear solve: jacobi (default), cholesky (a sparse "
                               "Cholesky factor of a recent system matrix) or amg (hypre "
                               "BoomerAMG hierarchy of one, a V-cycle per iteration)"},
            {"refactor_iterations", "cholesky, amg: a solve needing more iterations starts a "
                                    "new factor or hierarchy (integer >= 1, default 15)"},
            {"background_refactor", "cholesky: factorise on a thread of its own, the new factor "
                                    "taking over at a later step (default true)"}};
  e.make = [](const YamlEntry& spec) -> std::unique_ptr<Integrator> {
    BackwardEulerParams p;
    p.substeps = spec.integerAtLeast("substeps", 1, p.substeps);
    p.linearTolerance = spec.positive("linear_tolerance", p.linearTolerance);
    p.linearMaxIterations = spec.integerAtLeast("linear_max_iterations", 1, p.linearMaxIterations);
    p.newtonIterations = spec.integerAtLeast("newton_iterations", 1, p.newtonIterations);
    p.newtonTolerance = spec.positive("newton_tolerance", p.newtonTolerance);
    p.requireConvergence = spec.boolean("require_convergence", p.requireConvergence);
    p.warmStart = spec.boolean("warm_start", p.warmStart);
    using Preconditioning = BackwardEulerParams::Preconditioning;
    if (spec.has("preconditioner")) {
      const std::string name = spec["preconditioner"].choice({"jacobi", "cholesky", "amg"});
      p.preconditioner = name == "cholesky" ? Preconditioning::kCholesky
                         : name == "amg"    ? Preconditioning::kAmg
                                            : Preconditioning::kJacobi;
    }
    p.refactorIterations = spec.integerAtLeast("refactor_iterations", 1, p.refactorIterations);
    p.backgroundRefactor = spec.boolean("background_refactor", p.backgroundRefactor);
    return std::make_unique<BackwardEulerIntegrator>(p);
  };
  registry.add(std::move(e));
}

}  // namespace tt
