#pragma once
// The scene keys of a Newton solve, one vocabulary for every integrator that iterates Newton
// (backward_euler, quasistatic, radau_iia): the same key means the same thing in each.
//
//   max_newton_iterations  at most this many Newton iterations per step (integer >= 1;
//                          backward_euler: 1 is the linearised step)
//   newton_tolerance       relative residual at which Newton stops (> 0; backward_euler,
//                          quasistatic)
//   newton_abs_tolerance   absolute residual at which Newton stops (N, > 0; quasistatic)
//
// Deprecated, still read with the same meaning and one note "FILE:LINE: ..." each:
// backward_euler's newton_iterations (max_newton_iterations), quasistatic's rel_tolerance
// (newton_tolerance) and abs_tolerance (newton_abs_tolerance).
#include "tissue_trainer/core/registry/registry.h"
#include "tissue_trainer/core/registry/yaml_reader.h"

namespace tt {

// Each reads its key of `spec` over `fallback` (absent: the fallback); `oldName` is the
// integrator's deprecated name of the key, or nullptr where it had none. A malformed value is
// an InputError naming file, line and key.
inline int readMaxNewtonIterations(const YamlEntry& spec, int fallback, Notes& notes,
                                   const char* oldName = nullptr) {
  const auto entry = renamedKey(spec, "max_newton_iterations", oldName, notes);
  return entry ? entry->integerAtLeast(1) : fallback;
}

inline double readNewtonTolerance(const YamlEntry& spec, double fallback, Notes& notes,
                                  const char* oldName = nullptr) {
  const auto entry = renamedKey(spec, "newton_tolerance", oldName, notes);
  return entry ? entry->positive() : fallback;
}

inline double readNewtonAbsTolerance(const YamlEntry& spec, double fallback, Notes& notes,
                                     const char* oldName = nullptr) {
  const auto entry = renamedKey(spec, "newton_abs_tolerance", oldName, notes);
  return entry ? entry->positive() : fallback;
}

}  // namespace tt
