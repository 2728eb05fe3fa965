#pragma once
// Shared by the solver tests: reproducible right-hand sides.
#include <Eigen/Core>
#include <random>

namespace tt {

// Standard-normal entries from a fixed seed.
inline Eigen::VectorXd randomVector(Eigen::Index size, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::VectorXd v(size);
  for (Eigen::Index i = 0; i < size; ++i) v[i] = n(rng);
  return v;
}

}  // namespace tt
