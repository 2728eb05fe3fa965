#include "tissue_trainer/core/registry/linear_solve_keys.h"

#include <cstdio>

namespace tt {

namespace {

std::string keyDefaultText(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

void readMethod(const YamlEntry& spec, LinearSolveSettings& s) {
  if (spec.has("linear_solver")) {
    const std::string name = spec["linear_solver"].choice({"pcg", "gmres", "bicgstab"});
    s.method = name == "gmres"      ? LinearMethod::kGmres
               : name == "bicgstab" ? LinearMethod::kBiCgStab
                                    : LinearMethod::kPcg;
  }
  if (!spec.has("gmres_restart")) return;
  if (s.method != LinearMethod::kGmres)
    spec["gmres_restart"].fail("applies only with linear_solver: gmres");
  s.gmresRestart = spec["gmres_restart"].integerAtLeast(1);
}

void readPreconditioner(const YamlEntry& spec, LinearSolveSettings& s) {
  if (spec.has("preconditioner")) {
    const std::string name = spec["preconditioner"].choice({"jacobi", "cholesky", "amg"});
    s.preconditioner = name == "cholesky" ? PreconditionerKind::kCholesky
                       : name == "amg"    ? PreconditionerKind::kAmg
                                          : PreconditionerKind::kJacobi;
  }
  s.backgroundRefactor = spec.boolean("background_refactor", s.backgroundRefactor);
}

void readRefactorIterations(const YamlEntry& spec, LinearSolveSettings& s, Notes& notes) {
  if (const auto entry = renamedKey(spec, "refactor_iterations", "refactor_above", notes))
    s.refactorIterations = entry->integerAtLeast(0);
}

}  // namespace

LinearSolveSettings readLinearSolveSettings(const YamlEntry& spec, LinearSolveSettings s,
                                            Notes& notes) {
  readMethod(spec, s);
  s.tolerance = spec.positive("linear_tolerance", s.tolerance);
  s.maxIterations = spec.integerAtLeast("linear_max_iterations", 1, s.maxIterations);
  readPreconditioner(spec, s);
  readRefactorIterations(spec, s, notes);
  return s;
}

std::vector<KeyDoc> linearSolveKeyDocs(const LinearSolveSettings& d) {
  const auto onOff = [](bool b) { return b ? "true" : "false"; };
  return {
      {"linear_solver", std::string("pcg (BiCGSTAB where CG meets non-positive curvature), "
                                    "gmres or bicgstab (default ") + methodName(d.method) + ")"},
      {"gmres_restart", "gmres: Krylov vectors per cycle (integer >= 1, default " +
                            std::to_string(d.gmresRestart) + ")"},
      {"linear_tolerance",
       "relative residual of each linear solve (default " + keyDefaultText(d.tolerance) + ")"},
      {"linear_max_iterations", "iteration limit of each linear solve (integer >= 1, default " +
                                    std::to_string(d.maxIterations) + ")"},
      {"preconditioner", std::string("jacobi, cholesky (a sparse Cholesky factor of a recent "
                                     "matrix, kept between solves) or amg (a hypre BoomerAMG "
                                     "hierarchy of one, a V-cycle per iteration); default ") +
                             preconditionerName(d.preconditioner)},
      {"refactor_iterations",
       "cholesky, amg: a solve needing more iterations with the kept factor gets a new one "
       "(integer >= 0, default " + std::to_string(d.refactorIterations) +
           "; 0: a new factor for every solve)"},
      {"background_refactor", std::string("cholesky: factorise on a thread of its own, the new "
                                          "factor taking over at a later step (default ") +
                                  onOff(d.backgroundRefactor) + ")"},
  };
}

}  // namespace tt
