// Rostest of the tongue in the graph (test/integration/tongue_fitting.test, which runs
// launch/tongue_fitting.launch): the landmarks of the muscle tongue at known activations, solved
// here by the core, are published on /tissue/landmarks; the landmark_fitting node must publish
// those activations on /tissue/activation with a small residual on its status, and the
// simulation node, running the tongue with them, must reach the solved state: its
// /tissue/surface at the solved surface, the landmarks among its vertices at their targets.
// The muscles are read from the scene, so any number and names of them are checked.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "tissue_trainer/FitStatus.h"
#include "tissue_trainer/TissueStatus.h"
#include "tissue_trainer/TissueSurface.h"
#include "tissue_trainer/TrackedLandmarks.h"
#include "tissue_trainer/core/fit/landmark_fit.h"
#include "tissue_trainer/core/integrate/quasistatic.h"
#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/model/activated_force_model.h"
#include "tissue_trainer/core/scene/display_surface.h"
#include "tissue_trainer/core/scene/scene.h"
#include "tissue_trainer/core/solve/equilibrium.h"

namespace {

constexpr double kActivationTolerance = 1e-4;  // of the fitted activations
constexpr double kResidualTolerance = 1e-7;    // m, the fit's RMS landmark distance
constexpr double kSurfaceTolerance = 1e-6;     // m, simulated surface and landmarks vs. solved

// The scene at known activations, solved to equilibrium from rest as its quasistatic frames
// are (same equilibrium parameters).
struct Target {
  std::map<std::string, double> activations;
  tissue_trainer::TrackedLandmarks landmarks;
  Eigen::Matrix3Xd surface;          // the displayed surface (/tissue/surface's vertices)
  std::vector<int> landmarkVertex;   // the surface vertex of each node landmark, or -1
  double solveSeconds = 0.0;
};

// 0.2, 0.25, 0.3, 0.2, ... by muscle order: every muscle active, none near its bounds.
double knownActivation(int k) { return 0.2 + 0.05 * (k % 3); }

Target solveTarget() {
  Target target;
  std::string scenePath, landmarkPath;
  EXPECT_TRUE(ros::param::get("~scene", scenePath));
  EXPECT_TRUE(ros::param::get("~landmarks", landmarkPath));
  tt::Scene scene = tt::loadScene(scenePath);
  int k = 0;
  for (const auto& model : scene.system.models)
    if (auto* muscles = dynamic_cast<tt::ActivatedForceModel*>(model.get()))
      for (int i = 0; i < muscles->activationCount(); ++i, ++k) {
        muscles->setActivation(i, knownActivation(k));
        target.activations[muscles->activationName(i)] = knownActivation(k);
      }
  tt::EquilibriumParams params;
  if (const auto* q = dynamic_cast<const tt::QuasistaticIntegrator*>(&tt::unguarded(*scene.integrator)))
    params = q->params();
  const ros::WallTime start = ros::WallTime::now();
  const tt::EquilibriumReport report = tt::solveEquilibrium(scene.system, params);
  target.solveSeconds = (ros::WallTime::now() - start).toSec();
  EXPECT_TRUE(report.converged()) << report.reason;

  const Eigen::VectorXd& x = scene.system.state.x;
  const std::vector<tt::Landmark> landmarks = tt::readLandmarks(landmarkPath, scene.system.mesh);
  const tt::DisplaySurface display(scene);
  display.positions(x, target.surface);
  Eigen::Matrix3Xd restSurface;
  display.positions(Eigen::Map<const Eigen::VectorXd>(scene.system.mesh.rest.data(),
                                                      scene.system.mesh.rest.size()),
                    restSurface);
  for (size_t l = 0; l < landmarks.size(); ++l) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int c = 0; c < 4; ++c) p += landmarks[l].weights[c] * x.segment<3>(3 * landmarks[l].nodes[c]);
    geometry_msgs::Point q;
    q.x = p.x();
    q.y = p.y();
    q.z = p.z();
    target.landmarks.ids.push_back(static_cast<uint32_t>(l));
    target.landmarks.positions.push_back(q);
    // A node landmark on the displayed surface is the vertex at its node's rest position.
    int vertex = -1;
    for (int c = 0; c < 4; ++c)
      if (landmarks[l].weights[c] == 1.0) {
        const Eigen::Vector3d rest = scene.system.mesh.rest.col(landmarks[l].nodes[c]);
        for (int v = 0; v < restSurface.cols(); ++v)
          if (restSurface.col(v) == rest) vertex = v;
      }
    target.landmarkVertex.push_back(vertex);
  }
  return target;
}

struct Samples {
  std::vector<double> values;
  void add(double v) { values.push_back(v); }
  double median() const {
    if (values.empty()) return NAN;
    std::vector<double> s = values;
    std::nth_element(s.begin(), s.begin() + s.size() / 2, s.end());
    return s[s.size() / 2];
  }
  double max() const { return values.empty() ? NAN : *std::max_element(values.begin(), values.end()); }
};

TEST(TongueFitting, TrackedLandmarksDriveTheSimulatedTongue) {
  ros::NodeHandle nh;
  const Target target = solveTarget();
  ASSERT_FALSE(target.activations.empty());
  ROS_INFO("target: %zu muscles, %zu landmarks, equilibrium solved in %.2f s",
           target.activations.size(), target.landmarks.ids.size(), target.solveSeconds);
  testing::Test::RecordProperty("target_solve_s", std::to_string(target.solveSeconds));

  ros::Publisher landmarkPub = nh.advertise<tissue_trainer::TrackedLandmarks>("tissue/landmarks", 10);
  std::map<std::string, double> fitted;
  ros::Subscriber activationSub = nh.subscribe<sensor_msgs::JointState>(
      "tissue/activation", 10, [&](const auto& m) {
        for (size_t k = 0; k < m->name.size() && k < m->position.size(); ++k)
          fitted[m->name[k]] = m->position[k];
      });
  tissue_trainer::FitStatus fit;
  Samples fitSeconds;
  ros::Subscriber fitSub = nh.subscribe<tissue_trainer::FitStatus>(
      "landmark_fitting/status", 10, [&](const auto& m) {
        fit = *m;
        fitSeconds.add(m->fit_wall_time);
        ROS_INFO("fit %zu: %u iterations, residual %.3g m (from %.3g), %.2f s%s%s",
                 fitSeconds.values.size(), m->iterations, m->residual, m->initial_residual,
                 m->fit_wall_time, m->converged ? "" : ", stopped: ", m->stop_reason.c_str());
      });
  Samples stepSeconds;
  bool stable = true;
  ros::Subscriber statusSub = nh.subscribe<tissue_trainer::TissueStatus>(
      "tissue/status", 10, [&](const auto& m) {
        stepSeconds.add(m->step_wall_time);
        stable = stable && m->stable;
      });
  Eigen::Matrix3Xf surface;
  ros::Subscriber surfaceSub = nh.subscribe<tissue_trainer::TissueSurface>(
      "tissue/surface", 2, [&](const auto& m) {
        if (m->positions.size() == static_cast<size_t>(3 * target.surface.cols()))
          surface = Eigen::Map<const Eigen::Matrix3Xf>(m->positions.data(), 3, target.surface.cols());
      });

  // Spins for up to `seconds`, publishing the landmarks at 5 Hz, until `done`.
  tissue_trainer::TrackedLandmarks tracked = target.landmarks;
  const auto spinFor = [&](double seconds, const std::function<bool()>& done) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
    ros::WallRate rate(5.0);
    while (ros::ok() && ros::WallTime::now() < end) {
      tracked.header.stamp = ros::Time::now();
      landmarkPub.publish(tracked);
      ros::spinOnce();
      if (done()) return true;
      rate.sleep();
    }
    return false;
  };
  constexpr double kNone = std::numeric_limits<double>::infinity();
  const auto activationError = [&] {
    double e = 0.0;
    for (const auto& [name, a] : target.activations)
      e = std::max(e, fitted.count(name) ? std::abs(fitted[name] - a) : kNone);
    return e;
  };
  const auto surfaceError = [&] {
    if (surface.cols() == 0) return kNone;
    return (surface.cast<double>() - target.surface).colwise().norm().maxCoeff();
  };

  ASSERT_TRUE(spinFor(30.0, [&] {
    return landmarkPub.getNumSubscribers() > 0 && activationSub.getNumPublishers() > 0 &&
           fitSub.getNumPublishers() > 0 && surfaceSub.getNumPublishers() > 0;
  })) << "no landmark_fitting or simulation";

  const ros::WallTime tracking = ros::WallTime::now();
  const bool activationsFitted = spinFor(150.0, [&] {
    return fit.converged && fit.residual < kResidualTolerance &&
           activationError() < kActivationTolerance;
  });
  const double fitDelay = (ros::WallTime::now() - tracking).toSec();
  for (const auto& [name, a] : target.activations)
    ROS_INFO("activation %s: %.6f fitted, %.6f known", name.c_str(),
             fitted.count(name) ? fitted[name] : NAN, a);
  ASSERT_TRUE(activationsFitted) << fitSeconds.values.size() << " fits, residual " << fit.residual
                                 << " m, activation error " << activationError() << ", stop '"
                                 << fit.stop_reason << "'";
  EXPECT_EQ(fit.landmarks, target.landmarks.ids.size());

  const bool surfaceReached = spinFor(60.0, [&] { return surfaceError() < kSurfaceTolerance; });
  const double simulationDelay = (ros::WallTime::now() - tracking).toSec();
  ASSERT_TRUE(surfaceReached) << "simulated surface " << surfaceError() << " m from the solved one";
  EXPECT_TRUE(stable);
  double landmarkError = 0.0;
  int onSurface = 0;
  for (size_t l = 0; l < target.landmarkVertex.size(); ++l) {
    const int v = target.landmarkVertex[l];
    if (v < 0) continue;
    const auto& q = target.landmarks.positions[l];
    landmarkError = std::max(landmarkError,
                             (surface.col(v).cast<double>() - Eigen::Vector3d(q.x, q.y, q.z)).norm());
    ++onSurface;
  }
  EXPECT_GT(onSurface, 0) << "no landmark is a vertex of /tissue/surface";
  EXPECT_LT(landmarkError, kSurfaceTolerance);

  ROS_INFO("activations fitted %.1f s after the first landmarks (%zu fits, median %.2f s, max "
           "%.2f s, last: %u iterations, residual %.3g m); the simulated surface within %.2g m "
           "of the solved one after %.1f s (%d landmarks on it within %.2g m); simulation "
           "frames: %zu, median %.2f s, max %.2f s",
           fitDelay, fitSeconds.values.size(), fitSeconds.median(), fitSeconds.max(),
           fit.iterations, fit.residual, surfaceError(), simulationDelay, onSurface,
           landmarkError, stepSeconds.values.size(), stepSeconds.median(), stepSeconds.max());
  testing::Test::RecordProperty("fit_delay_s", std::to_string(fitDelay));
  testing::Test::RecordProperty("fits", std::to_string(fitSeconds.values.size()));
  testing::Test::RecordProperty("fit_median_s", std::to_string(fitSeconds.median()));
  testing::Test::RecordProperty("fit_max_s", std::to_string(fitSeconds.max()));
  testing::Test::RecordProperty("simulation_delay_s", std::to_string(simulationDelay));
  testing::Test::RecordProperty("frames", std::to_string(stepSeconds.values.size()));
  testing::Test::RecordProperty("frame_median_s", std::to_string(stepSeconds.median()));
  testing::Test::RecordProperty("frame_max_s", std::to_string(stepSeconds.max()));
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "tongue_fitting_check");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
