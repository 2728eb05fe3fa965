#pragma once
// Shared by the benchmarks that write CSV (bench_work_precision, bench_scaling): the process
// CPU clock and the wall clock, medians, the elastic model names the registry offers, and the
// natural frequencies of a system at rest.
#include <time.h>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/registry/registry.h"
#include "tissue_trainer/core/system.h"

namespace tt {
namespace bench {

// Backward Euler with a Jacobi-PCG linear solve. The defaults are the report's backward-Euler
// rows: 1e-8, at most 500 iterations (the defaults until the measured ones, docs/solvers.md),
// so that the error the rows show is the time stepping's, not the linear solve's.
inline BackwardEulerParams jacobiBackwardEuler(double tolerance = 1e-8, int maxIterations = 500) {
  BackwardEulerParams p;
  p.preconditioner = BackwardEulerParams::Preconditioning::kJacobi;
  p.linearTolerance = tolerance;
  p.linearMaxIterations = maxIterations;
  return p;
}

// CPU time of the whole process (all threads), s.
inline double cpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

inline double wallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// The largest distance between corresponding nodes of two position vectors (m).
inline double maxNodeDistance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double d = 0.0;
  for (Eigen::Index n = 0; n < a.size() / 3; ++n)
    d = std::max(d, (a.segment<3>(3 * n) - b.segment<3>(3 * n)).norm());
  return d;
}

inline double median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + mid, values.end());
  return values[mid];
}

// --- command lines ---------------------------------------------------------------------------

// "a,b,c" -> {a, b, c} (empty items dropped).
inline std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> items;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) items.push_back(item);
  return items;
}

// True when `chosen` is empty (all) or holds name.
inline bool selected(const std::vector<std::string>& chosen, const std::string& name) {
  return chosen.empty() || std::find(chosen.begin(), chosen.end(), name) != chosen.end();
}

// The value of a command-line option that must be a positive number; exits 2 with one line
// naming the option otherwise.
inline double positiveNumber(const char* tool, const std::string& option, const char* text) {
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(v) || !(v > 0.0)) {
    std::fprintf(stderr, "%s: %s expects a positive number, got '%s'\n", tool, option.c_str(), text);
    std::exit(2);
  }
  return v;
}

// A positive whole number, or one error line and exit 2.
inline int positiveInteger(const char* tool, const std::string& option, const char* text) {
  char* end = nullptr;
  const long v = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || v < 1 || v > 1000000) {
    std::fprintf(stderr, "%s: %s expects a positive whole number, got '%s'\n", tool, option.c_str(),
                 text);
    std::exit(2);
  }
  return static_cast<int>(v);
}

// Every name in `chosen` must be one of `known`; otherwise one error line and exit 2.
inline void requireKnown(const char* tool, const char* what, const std::vector<std::string>& chosen,
                         const std::vector<std::string>& known) {
  for (const std::string& name : chosen) {
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    std::string list;
    for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
    std::fprintf(stderr, "%s: unknown %s '%s' (expected one of %s)\n", tool, what, name.c_str(),
                 list.c_str());
    std::exit(2);
  }
}

// Keeps the names of `list` that `chosen` names (all when it is empty); an unknown name is
// one error line and exit 2.
inline void keepOnly(const char* tool, const char* what, std::vector<std::string>& list,
                     const std::vector<std::string>& chosen) {
  requireKnown(tool, what, chosen, list);
  list.erase(std::remove_if(list.begin(), list.end(),
                            [&](const std::string& n) { return !selected(chosen, n); }),
             list.end());
}

// The presets of the registry's force models, one model each ("edge_length, ...").
inline std::vector<std::string> elasticModelNames() { return registry().modelPresetNames(); }

// Adds the force models of any preset (a model's or a tissue's) to the system.
inline void addPreset(System& s, const std::string& preset) {
  for (auto& m : makePresetModels(preset, s.mesh, s.materials)) s.models.push_back(std::move(m));
}

// -K at x with identity rows and columns for the constrained DOFs, column-major for the
// sparse solvers.
inline Eigen::SparseMatrix<double> negativeStiffness(const System& s, const Eigen::VectorXd& x) {
  SparseMatrix K;
  s.assembleStiffness(x, K);
  K *= -1.0;
  s.constrainMatrix(K);
  return Eigen::SparseMatrix<double>(K);
}

// Natural frequencies and mode shapes at rest: -K phi = omega^2 M phi on the free DOFs
// (dense, for the small meshes of the work-precision problems).
struct RestModes {
  Eigen::VectorXd omega;   // rad/s, ascending
  Eigen::MatrixXd shapes;  // one column per mode, 3n, M-normalised, zero on constrained DOFs
};

inline RestModes restModes(const System& s) {
  std::vector<int> free;
  for (int dof = 0; dof < s.numDofs(); ++dof)
    if (!s.isConstrained[dof]) free.push_back(dof);
  const Eigen::MatrixXd K = Eigen::MatrixXd(negativeStiffness(s, s.mesh.rest.reshaped()));
  const int n = static_cast<int>(free.size());
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      A(i, j) = K(free[i], free[j]) / std::sqrt(s.mass[free[i]] * s.mass[free[j]]);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(A);
  RestModes modes;
  modes.omega = eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  modes.shapes = Eigen::MatrixXd::Zero(s.numDofs(), n);
  for (int i = 0; i < n; ++i)
    modes.shapes.row(free[i]) = eigen.eigenvectors().row(i) / std::sqrt(s.mass[free[i]]);
  return modes;
}

}  // namespace bench
}  // namespace tt
