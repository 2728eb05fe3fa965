// The contact's tool proxy (contact/tool_proxy.h): it never moves faster than its limit per
// simulated second, reaches a target that stops, and follows a slow one exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "tissue_trainer/core/contact/tool_proxy.h"

namespace tt {
namespace {

TEST(ToolProxy, TheFirstTargetPlacesIt) {
  ToolProxy proxy(0.1);
  EXPECT_FALSE(proxy.placed());
  const Eigen::Vector3d target(0.01, -0.02, 0.3);
  EXPECT_EQ(proxy.follow(target, 0.01), target);
  EXPECT_TRUE(proxy.placed());
  EXPECT_EQ(proxy.lag(), 0.0);
}

TEST(ToolProxy, NeverFasterThanItsLimitPerSimulatedSecond) {
  const double speed = 0.1;
  ToolProxy proxy(speed);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> jump(-0.05, 0.05), step(0.0, 0.1);
  Eigen::Vector3d device(0, 0, 0);
  proxy.follow(device, 0.01);
  double simulated = 0.0, travelled = 0.0;
  for (int k = 0; k < 5000; ++k) {
    device += Eigen::Vector3d(jump(random), jump(random), jump(random));  // up to 8.7 cm a frame
    const double h = step(random);
    const Eigen::Vector3d before = proxy.position();
    const Eigen::Vector3d after = proxy.follow(device, h);
    const double moved = (after - before).norm();
    // Up to the round-off of positions of a metre or two (the device wanders): 1e-12 m.
    EXPECT_LE(moved, speed * h + 1e-12) << "frame " << k;
    // Toward the target: the distance falls by exactly what it moved.
    EXPECT_NEAR((device - before).norm() - proxy.lag(), moved, 1e-12);
    simulated += h;
    travelled += moved;
  }
  EXPECT_LE(travelled, speed * simulated + 5000 * 1e-12);
  EXPECT_GT(travelled, 0.5 * speed * simulated);  // it did move, mostly at its limit
}

TEST(ToolProxy, ReachesATargetThatStops) {
  ToolProxy proxy(0.1);
  proxy.follow(Eigen::Vector3d::Zero(), 0.01);
  const Eigen::Vector3d target(0.03, 0.0, -0.04);  // 5 cm away: 0.5 s at 0.1 m/s
  int frames = 0;
  while (proxy.follow(target, 0.01) != target) {
    ASSERT_LT(++frames, 1000);
  }
  // 50 frames of 10 ms cover the 5 cm (one more when round-off leaves a sliver).
  EXPECT_GE(frames + 1, 50);
  EXPECT_LE(frames + 1, 51);
  EXPECT_EQ(proxy.lag(), 0.0);
}

TEST(ToolProxy, FollowsASlowTargetExactly) {
  ToolProxy proxy(0.1);
  for (int k = 0; k <= 100; ++k) {
    const Eigen::Vector3d target(0.0005 * k, 0.0, 0.0);  // 0.05 m/s in frames of 10 ms
    EXPECT_EQ(proxy.follow(target, 0.01), target);
  }
}

TEST(ToolProxy, AZeroStepHoldsItAndResetPlacesItAgain) {
  ToolProxy proxy(0.1);
  proxy.follow(Eigen::Vector3d::Zero(), 0.01);
  EXPECT_EQ(proxy.follow(Eigen::Vector3d(0.1, 0, 0), 0.0), Eigen::Vector3d::Zero());
  EXPECT_DOUBLE_EQ(proxy.lag(), 0.1);
  proxy.reset();
  EXPECT_EQ(proxy.follow(Eigen::Vector3d(0.1, 0, 0), 0.0), Eigen::Vector3d(0.1, 0, 0));
}

TEST(ToolProxy, RefusesBadInput) {
  EXPECT_THROW(ToolProxy(0.0), std::invalid_argument);
  EXPECT_THROW(ToolProxy(-1.0), std::invalid_argument);
  EXPECT_THROW(ToolProxy{std::numeric_limits<double>::infinity()}, std::invalid_argument);
  ToolProxy proxy(0.1);
  proxy.follow(Eigen::Vector3d::Zero(), 0.01);
  EXPECT_THROW(proxy.follow(Eigen::Vector3d(std::nan(""), 0, 0), 0.01), std::invalid_argument);
  EXPECT_THROW(proxy.follow(Eigen::Vector3d(0.1, 0, 0), -0.01), std::invalid_argument);
  EXPECT_THROW(proxy.follow(Eigen::Vector3d(0.1, 0, 0), std::nan("")), std::invalid_argument);
  EXPECT_EQ(proxy.position(), Eigen::Vector3d::Zero());
}

}  // namespace
}  // namespace tt
