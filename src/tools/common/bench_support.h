#pragma once
// Shared by the benchmarks: the process CPU clock and the wall clock, medians and quantiles,
// the repository root, option lists, the presets the registry offers, and the natural
// frequencies of a system at rest (bench_support.cpp).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <string>
#include <vector>

#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/system.h"

namespace tt {
namespace bench {

// Backward Euler with a Jacobi-PCG linear solve. The defaults are the report's backward-Euler
// rows: 1e-8, at most 500 iterations (the defaults until the measured ones, docs/solvers.md),
// so that the error the rows show is the time stepping's, not the linear solve's.
BackwardEulerParams jacobiBackwardEuler(double tolerance = 1e-8, int maxIterations = 500);

// CPU time of the whole process (all threads), s.
double cpuSeconds();
// A monotonic wall clock, s.
double wallSeconds();

// The largest distance between corresponding nodes of two position vectors (m).
double maxNodeDistance(const Eigen::VectorXd& a, const Eigen::VectorXd& b);

// NaN when empty.
double median(std::vector<double> values);
// The q quantile of v (nearest rank); NaN for no values.
double quantile(std::vector<double> v, double q);

// The repository root: $TT_SOURCE_DIR, else the one the tool was built from.
std::string sourceDir();

// --- command lines ---------------------------------------------------------------------------

// "a,b,c" -> {a, b, c} (empty items dropped).
std::vector<std::string> splitList(const std::string& s);

// True when `chosen` is empty (all) or holds name.
bool selected(const std::vector<std::string>& chosen, const std::string& name);

// The value of a command-line option that must be a positive number; exits 2 with one line
// naming the option otherwise.
double positiveNumber(const char* tool, const std::string& option, const char* text);

// A positive whole number, or one error line and exit 2.
int positiveInteger(const char* tool, const std::string& option, const char* text);

// Every name in `chosen` must be one of `known`; otherwise one error line and exit 2.
void requireKnown(const char* tool, const char* what, const std::vector<std::string>& chosen,
                  const std::vector<std::string>& known);

// Keeps the names of `list` that `chosen` names (all when it is empty); an unknown name is
// one error line and exit 2.
void keepOnly(const char* tool, const char* what, std::vector<std::string>& list,
              const std::vector<std::string>& chosen);

// The presets of the registry's force models, one model each ("edge_length, ...").
std::vector<std::string> elasticModelNames();

// Adds the force models of any preset (a model's or a tissue's) to the system.
void addPreset(System& s, const std::string& preset);

// -K at x with identity rows and columns for the constrained DOFs, column-major for the
// sparse solvers.
Eigen::SparseMatrix<double> negativeStiffness(const System& s, const Eigen::VectorXd& x);

// Natural frequencies and mode shapes at rest: -K phi = omega^2 M phi on the free DOFs
// (dense, for the small meshes of the work-precision problems).
struct RestModes {
  Eigen::VectorXd omega;   // rad/s, ascending
  Eigen::MatrixXd shapes;  // one column per mode, 3n, M-normalised, zero on constrained DOFs
};

RestModes restModes(const System& s);

}  // namespace bench
}  // namespace tt
