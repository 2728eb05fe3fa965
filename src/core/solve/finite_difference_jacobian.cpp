#include "tissue_trainer/core/solve/finite_difference_jacobian.h"

#include <algorithm>
#include <cmath>

namespace tt {

namespace {

// Node b is a neighbour of node a when block (a, b) is in the pattern.
std::vector<std::vector<int>> nodeNeighbours(const SparseMatrix& pattern) {
  std::vector<std::vector<int>> neighbours(pattern.rows() / 3);
  for (int a = 0; a < static_cast<int>(neighbours.size()); ++a) {
    for (SparseMatrix::InnerIterator it(pattern, 3 * a); it; ++it)
      if (neighbours[a].empty() || neighbours[a].back() != it.col() / 3)
        neighbours[a].push_back(static_cast<int>(it.col() / 3));
  }
  return neighbours;
}

double largestExtent(const Mesh& mesh) {
  if (mesh.numNodes() == 0) return 1.0;
  const Eigen::Vector3d extent = mesh.rest.rowwise().maxCoeff() - mesh.rest.rowwise().minCoeff();
  return extent.maxCoeff() > 0.0 ? extent.maxCoeff() : 1.0;
}

}  // namespace

std::vector<int> distanceTwoColouring(const SparsePattern& pattern) {
  const std::vector<std::vector<int>> neighbours = nodeNeighbours(pattern.zeroMatrix());
  const int nodes = static_cast<int>(neighbours.size());
  std::vector<int> colour(nodes, -1);
  std::vector<char> taken;
  int colours = 0;
  for (int a = 0; a < nodes; ++a) {
    taken.assign(colours + 1, 0);
    for (int b : neighbours[a])
      for (int d : neighbours[b])
        if (colour[d] >= 0) taken[colour[d]] = 1;
    colour[a] = static_cast<int>(std::find(taken.begin(), taken.end(), 0) - taken.begin());
    colours = std::max(colours, colour[a] + 1);
  }
  return colour;
}

FiniteDifferenceJacobian::FiniteDifferenceJacobian(const System& system,
                                                   FiniteDifferenceSettings settings)
    : settings_(settings) {
  if (!(settings_.positionScale > 0.0)) settings_.positionScale = largestExtent(system.mesh);
  const SparseMatrix pattern = system.pattern.zeroMatrix();
  dofs_ = pattern.rows();
  patternNonZeros_ = pattern.nonZeros();
  std::vector<int> groupOf(dofs_);
  if (settings_.coloring) {
    const std::vector<int> colour = distanceTwoColouring(system.pattern);
    colours_ = colour.empty() ? 0 : *std::max_element(colour.begin(), colour.end()) + 1;
    for (Eigen::Index dof = 0; dof < dofs_; ++dof) groupOf[dof] = 3 * colour[dof / 3] + dof % 3;
    groupDofs_.resize(3 * colours_);
  } else {
    for (Eigen::Index dof = 0; dof < dofs_; ++dof) groupOf[dof] = static_cast<int>(dof);
    groupDofs_.resize(dofs_);
  }
  for (Eigen::Index dof = 0; dof < dofs_; ++dof) groupDofs_[groupOf[dof]].push_back(dof);
  groupEntries_.resize(groupDofs_.size());
  for (int row = 0; row < pattern.outerSize(); ++row)
    for (SparseMatrix::InnerIterator it(pattern, row); it; ++it) {
      const int offset = static_cast<int>(&it.value() - pattern.valuePtr());
      groupEntries_[groupOf[it.col()]].push_back({offset, row, static_cast<int>(it.col())});
    }
}

bool FiniteDifferenceJacobian::matches(const System& system) const {
  return system.numDofs() == dofs_ && system.pattern.nonZeros() == patternNonZeros_;
}

void FiniteDifferenceJacobian::positions(const System& system, const Eigen::VectorXd& x,
                                         const Eigen::VectorXd& v, const Eigen::VectorXd& f,
                                         double scale, SparseMatrix& J) {
  differentiate(system, false, x, v, f, scale, J);
}

void FiniteDifferenceJacobian::velocities(const System& system, const Eigen::VectorXd& x,
                                          const Eigen::VectorXd& v, const Eigen::VectorXd& f,
                                          double scale, SparseMatrix& J) {
  differentiate(system, true, x, v, f, scale, J);
}

void FiniteDifferenceJacobian::differentiate(const System& system, bool inVelocity,
                                             const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                                             const Eigen::VectorXd& f, double scale,
                                             SparseMatrix& J) {
  if (J.nonZeros() == 0) J = system.pattern.zeroMatrix();
  xs_ = x;
  vs_ = v;
  Eigen::VectorXd& u = inVelocity ? vs_ : xs_;
  const Eigen::VectorXd& u0 = inVelocity ? v : x;
  const double floor = inVelocity ? settings_.velocityScale : settings_.positionScale;
  step_.resize(dofs_);
  double* values = J.valuePtr();
  for (size_t g = 0; g < groupDofs_.size(); ++g) {
    for (int j : groupDofs_[g]) {
      u[j] = u0[j] + settings_.epsilon * std::max(std::abs(u0[j]), floor);
      step_[j] = u[j] - u0[j];
    }
    system.computeForce(xs_, vs_, fs_);
    ++evaluations_;
    for (const Entry& e : groupEntries_[g])
      values[e.offset] = scale * (fs_[e.row] - f[e.row]) / step_[e.column];
    for (int j : groupDofs_[g]) u[j] = u0[j];
  }
}

}  // namespace tt
