#pragma once
// Random draws in a fixed order. C++ leaves open the order in which a call's arguments (and an
// overloaded operator's operands) are evaluated: g++ evaluates the last one first, clang the
// first one first, so Vector3d(d(rng), d(rng), d(rng)) was a different vector under each. The
// tests' random states were written against g++'s order, which these helpers and the tests'
// explicit draws keep (the z draw first), so that every compiler sees the same states.
#include <Eigen/Core>
#include <random>

namespace tt {
namespace testutil {

// (x, y, z) from three draws of `d`, z drawn first.
template <class Distribution>
Eigen::Vector3d drawVector(Distribution& d, std::mt19937& rng) {
  const double z = d(rng);
  const double y = d(rng);
  const double x = d(rng);
  return Eigen::Vector3d(x, y, z);
}

}  // namespace testutil
}  // namespace tt
