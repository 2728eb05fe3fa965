#pragma once
// The scene keys of a linear solve (solve/linear_solve.h), one vocabulary for every integrator
// that solves linear systems with these preconditioners (backward_euler, quasistatic): the
// same key means the same thing in each.
//
//   linear_solver          pcg | gmres | bicgstab
//   gmres_restart          gmres: Krylov vectors per cycle (integer >= 1)
//   linear_tolerance       relative residual of each solve (> 0)
//   linear_max_iterations  iterations per solve (integer >= 1)
//   preconditioner         jacobi | cholesky | amg
//   refactor_iterations    cholesky, amg: a solve needing more iterations with the kept factor
//                          gets a new one (integer >= 0; 0: a new factor for every solve)
//   background_refactor    cholesky: factorise on a thread of its own (boolean)
//
// Deprecated, still read: refactor_above (quasistatic's old name of refactor_iterations, with
// the same meaning), with one note "FILE:LINE: ..." saying so.
#include <string>
#include <vector>

#include "tissue_trainer/core/registry/registry.h"
#include "tissue_trainer/core/solve/linear_solve.h"

namespace tt {

// The settings of `spec`'s linear-solve keys over `defaults` (absent keys keep theirs).
// A malformed value is an InputError naming file, line and key.
LinearSolveSettings readLinearSolveSettings(const YamlEntry& spec, LinearSolveSettings defaults,
                                            Notes& notes);

// The keys' documentation, with the integrator's defaults.
std::vector<KeyDoc> linearSolveKeyDocs(const LinearSolveSettings& defaults);

}  // namespace tt
