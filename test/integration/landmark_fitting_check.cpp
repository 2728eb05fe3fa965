// Rostest of the landmark fitting node (test/integration/landmark_fitting.test): the landmarks
// of the two-muscle block at known activations, solved here by the core, are published on
// /tissue/landmarks; the node must publish those activations on /tissue/activation and a
// converged fit on ~status. Malformed tracking (unknown ids, NaN, mismatched lists) is dropped
// without ending the node.
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>

#include <cmath>
#include <functional>
#include <map>

#include "tissue_trainer/FitStatus.h"
#include "tissue_trainer/TrackedLandmarks.h"
#include "tissue_trainer/core/fit/landmark_fit.h"
#include "tissue_trainer/core/model/activated_force_model.h"
#include "tissue_trainer/core/scene/scene.h"
#include "tissue_trainer/core/solve/equilibrium.h"

namespace {

// The landmark positions of the scene at these activations (equilibrium from rest).
tissue_trainer::TrackedLandmarks landmarksAt(const std::map<std::string, double>& activations) {
  std::string scenePath, landmarkPath;
  EXPECT_TRUE(ros::param::get("~scene", scenePath));
  EXPECT_TRUE(ros::param::get("~landmarks", landmarkPath));
  tt::Scene scene = tt::loadScene(scenePath);
  for (const auto& [name, a] : activations) {
    const tt::ActivationRef muscle = scene.system.findActivation(name);
    EXPECT_NE(muscle.model, nullptr) << name;
    if (muscle.model) muscle.model->setActivation(muscle.index, a);
  }
  EXPECT_TRUE(tt::solveEquilibrium(scene.system).converged());
  const std::vector<tt::Landmark> landmarks = tt::readLandmarks(landmarkPath, scene.system.mesh);
  tissue_trainer::TrackedLandmarks msg;
  for (size_t k = 0; k < landmarks.size(); ++k) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int c = 0; c < 4; ++c)
      p += landmarks[k].weights[c] * scene.system.state.x.segment<3>(3 * landmarks[k].nodes[c]);
    geometry_msgs::Point q;
    q.x = p.x();
    q.y = p.y();
    q.z = p.z();
    msg.ids.push_back(static_cast<uint32_t>(k));
    msg.positions.push_back(q);
  }
  return msg;
}

TEST(LandmarkFitting, RecoversTheActivationsOfTrackedLandmarks) {
  ros::NodeHandle nh;
  const std::map<std::string, double> truth = {{"lower", 0.6}, {"upper", 0.3}};
  tissue_trainer::TrackedLandmarks tracked = landmarksAt(truth);
  ros::Publisher pub = nh.advertise<tissue_trainer::TrackedLandmarks>("tissue/landmarks", 10);
  std::map<std::string, double> fitted;
  tissue_trainer::FitStatus status;
  int fits = 0;
  ros::Subscriber activationSub = nh.subscribe<sensor_msgs::JointState>(
      "tissue/activation", 10, [&](const auto& m) {
        for (size_t k = 0; k < m->name.size() && k < m->position.size(); ++k)
          fitted[m->name[k]] = m->position[k];
      });
  ros::Subscriber statusSub = nh.subscribe<tissue_trainer::FitStatus>(
      "landmark_fitting/status", 10, [&](const auto& m) {
        status = *m;
        ++fits;
      });

  // Malformed tracking first: an unknown id, a NaN, and lists of different lengths.
  tissue_trainer::TrackedLandmarks bad = tracked;
  bad.ids[0] = 1000;
  bad.positions[1].x = NAN;
  tissue_trainer::TrackedLandmarks uneven = tracked;
  uneven.positions.pop_back();

  // Spins for up to `seconds`, publishing the tracked landmarks at 20 Hz when `track`.
  const auto spinFor = [&](double seconds, bool track, const std::function<bool()>& done) {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
    ros::WallRate rate(20.0);
    while (ros::ok() && ros::WallTime::now() < end) {
      tracked.header.stamp = ros::Time::now();
      if (track) pub.publish(tracked);
      ros::spinOnce();
      if (done()) return true;
      rate.sleep();
    }
    return false;
  };
  ASSERT_TRUE(spinFor(10.0, false, [&] {
    return pub.getNumSubscribers() > 0 && activationSub.getNumPublishers() > 0 &&
           statusSub.getNumPublishers() > 0;
  })) << "no landmark_fitting";
  // The uneven message is dropped whole; of the other, the unknown id and the NaN.
  pub.publish(uneven);
  pub.publish(bad);
  ASSERT_TRUE(spinFor(10.0, false, [&] { return fits > 0; })) << "no fit of the partial tracking";
  EXPECT_EQ(status.landmarks, tracked.ids.size() - 2);
  ASSERT_TRUE(spinFor(60.0, true, [&] {
    return status.converged && status.landmarks == tracked.ids.size() && fitted.size() == 2 &&
           std::abs(fitted["lower"] - 0.6) < 1e-4 && std::abs(fitted["upper"] - 0.3) < 1e-4;
  })) << "fits " << fits << ", residual " << status.residual << " m, lower "
      << fitted["lower"] << ", upper " << fitted["upper"] << ", stop '" << status.stop_reason << "'";
  ROS_INFO("fitted lower %.6f upper %.6f after %d fits: residual %.3g m (from %.3g), %u "
           "iterations, %.1f ms", fitted["lower"], fitted["upper"], fits, status.residual,
           status.initial_residual, status.iterations, 1e3 * status.fit_wall_time);
  EXPECT_LT(status.residual, 1e-6);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "landmark_fitting_check");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
