#include "common/bench_support.h"

#include <time.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "tissue_trainer/core/registry/registry.h"

namespace tt {
namespace bench {

BackwardEulerParams jacobiBackwardEuler(double tolerance, int maxIterations) {
  BackwardEulerParams p;
  p.preconditioner = BackwardEulerParams::Preconditioning::kJacobi;
  p.linearTolerance = tolerance;
  p.linearMaxIterations = maxIterations;
  return p;
}

double cpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double wallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

double maxNodeDistance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double d = 0.0;
  for (Eigen::Index n = 0; n < a.size() / 3; ++n)
    d = std::max(d, (a.segment<3>(3 * n) - b.segment<3>(3 * n)).norm());
  return d;
}

double median(std::vector<double> values) {
  if (values.empty()) return std::nan("");
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + mid, values.end());
  return values[mid];
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5))];
}

std::string sourceDir() {
  if (const char* env = std::getenv("TT_SOURCE_DIR")) return env;
  return TT_SOURCE_ROOT;
}

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> items;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) items.push_back(item);
  return items;
}

bool selected(const std::vector<std::string>& chosen, const std::string& name) {
  return chosen.empty() || std::find(chosen.begin(), chosen.end(), name) != chosen.end();
}

double positiveNumber(const char* tool, const std::string& option, const char* text) {
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(v) || !(v > 0.0)) {
    std::fprintf(stderr, "%s: %s expects a positive number, got '%s'\n", tool, option.c_str(), text);
    std::exit(2);
  }
  return v;
}

int positiveInteger(const char* tool, const std::string& option, const char* text) {
  char* end = nullptr;
  const long v = std::strtol(text, &end, 10);
  if (end == text || *end != '\0' || v < 1 || v > 1000000) {
    std::fprintf(stderr, "%s: %s expects a positive whole number, got '%s'\n", tool, option.c_str(),
                 text);
    std::exit(2);
  }
  return static_cast<int>(v);
}

void requireKnown(const char* tool, const char* what, const std::vector<std::string>& chosen,
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

void keepOnly(const char* tool, const char* what, std::vector<std::string>& list,
                     const std::vector<std::string>& chosen) {
  requireKnown(tool, what, chosen, list);
  list.erase(std::remove_if(list.begin(), list.end(),
                            [&](const std::string& n) { return !selected(chosen, n); }),
             list.end());
}

std::vector<std::string> elasticModelNames() { return registry().modelPresetNames(); }

void addPreset(System& s, const std::string& preset) {
  for (auto& m : makePresetModels(preset, s.mesh, s.materials)) s.models.push_back(std::move(m));
}

Eigen::SparseMatrix<double> negativeStiffness(const System& s, const Eigen::VectorXd& x) {
  SparseMatrix K;
  s.assembleStiffness(x, K);
  K *= -1.0;
  s.constrainMatrix(K);
  return Eigen::SparseMatrix<double>(K);
}

RestModes restModes(const System& s) {
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
