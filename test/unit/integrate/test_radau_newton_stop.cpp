// RadauOptions::newtonTolerance, the threshold of the Newton iteration's stopping test
// (Hairer and Wanner, Solving ODEs II, Sec. IV.8): by default their
// max(10 eps / rtol', min(0.03, sqrt(rtol'))) with rtol' = 0.1 rtol^(2/3); a tighter value
// costs more Newton iterations and changes the solution by less than the error tolerance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "oscillators.h"
#include "tissue_trainer/core/integrate/radau_iia.h"

namespace tt {
namespace {

using namespace oscillators;

struct Outcome {
  long newton = 0;
  Eigen::VectorXd x;
};

// Damped Duffing oscillators (the cubic term makes the Newton iteration work) over 2 s.
Outcome run(double newtonTolerance) {
  Oscillators o = harmonic(0.5);
  o.q = Eigen::VectorXd::Constant(12, 2e3);
  System s = o.build();
  RadauOptions options;
  options.absTol = options.relTol = 1e-3;
  options.newtonTolerance = newtonTolerance;
  RadauIIA radau(options);
  Outcome out;
  for (int frame = 0; frame < 40; ++frame) {
    const StepReport r = radau.advance(s, 0.05);
    EXPECT_TRUE(r.ok) << r.failure;
    out.newton += r.newtonIterations;
  }
  out.x = s.state.x;
  return out;
}

TEST(RadauNewtonStop, DefaultIsHairerAndWannersThreshold) {
  const double eps = std::numeric_limits<double>::epsilon();
  const double rtol = 0.1 * std::pow(1e-3, 2.0 / 3.0);
  const double hairer = std::max(10.0 * eps / rtol, std::min(0.03, std::sqrt(rtol)));
  const Outcome byDefault = run(0.0), explicitValue = run(hairer), other = run(0.5 * hairer);
  EXPECT_EQ(byDefault.newton, explicitValue.newton);
  EXPECT_EQ(byDefault.x, explicitValue.x);
  EXPECT_NE(byDefault.x, other.x);  // the option reaches the iteration
}

TEST(RadauNewtonStop, TighterThresholdCostsIterationsNotAccuracy) {
  const Outcome loose = run(0.0), tight = run(1e-6);
  std::printf("[ newton   ] Newton iterations over 2 s: %ld (default stop), %ld (1e-6)\n",
              loose.newton, tight.newton);
  EXPECT_GT(tight.newton, loose.newton + loose.newton / 4);
  EXPECT_LT((tight.x - loose.x).lpNorm<Eigen::Infinity>(), 1e-3);
}

}  // namespace
}  // namespace tt
