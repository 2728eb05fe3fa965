#include "landmark_fitting_node.h"

#include <sensor_msgs/JointState.h>

#include <cmath>
#include <exception>

#include "../common/param_reader.h"
#include "tissue_trainer/FitStatus.h"
#include "tissue_trainer/core/model/activated_force_model.h"

namespace tt_nodes {

LandmarkFittingNode::LandmarkFittingNode(ros::NodeHandle nh, ros::NodeHandle pnh)
    : nh_(std::move(nh)), pnh_(std::move(pnh)) {}

bool LandmarkFittingNode::start() {
  try {
    const ParamReader p(pnh_);
    params_.scene = p.text("scene", "");
    params_.landmarks = p.text("landmarks", "");
    if (params_.scene.empty() || params_.landmarks.empty())
      throw ParamError(p.qualified(params_.scene.empty() ? "scene" : "landmarks") +
                       ": required (a file path)");
    params_.rate = p.number("rate", params_.rate, 0.01, 1000.0);
    params_.maxIterations =
        static_cast<int>(p.number("max_iterations", params_.maxIterations, 1, 1000));
    params_.levenbergMarquardt = p.number("levenberg_marquardt", params_.levenbergMarquardt, 0.0, 1e12);
    params_.residualTolerance = p.number("residual_tolerance", params_.residualTolerance, 0.0, 1.0);
    params_.staleAfter = p.number("stale_after", params_.staleAfter, 1e-3, 1e6);
    scene_ = tt::loadScene(params_.scene);
    definitions_ = tt::readLandmarks(params_.landmarks, scene_.system.mesh);
    // Checks the scene has activations to fit, once, with every landmark.
    tt::LandmarkFit check(scene_.system, definitions_);
  } catch (const std::exception& e) {
    ROS_FATAL("landmark_fitting: %s", e.what());
    return false;
  }
  trackedAt_.assign(definitions_.size(), ros::WallTime());
  landmarkSub_ = nh_.subscribe("tissue/landmarks", 10, &LandmarkFittingNode::onLandmarks, this);
  activationPub_ = nh_.advertise<sensor_msgs::JointState>("tissue/activation", 10);
  statusPub_ = pnh_.advertise<tissue_trainer::FitStatus>("status", 10);
  fitTimer_ = nh_.createSteadyTimer(ros::WallDuration(1.0 / params_.rate), &LandmarkFittingNode::fit, this);
  ROS_INFO("landmark_fitting: scene '%s', %zu landmarks, fits at up to %.1f Hz",
           scene_.name.c_str(), definitions_.size(), params_.rate);
  return true;
}

// Positions by landmark id; an id outside the file's landmarks, a non-finite position or a
// message whose lists differ in length is dropped with a warning.
void LandmarkFittingNode::onLandmarks(const tissue_trainer::TrackedLandmarks& msg) {
  if (msg.ids.size() != msg.positions.size()) {
    ROS_WARN_THROTTLE(1.0, "tissue/landmarks: %zu ids but %zu positions; message ignored",
                      msg.ids.size(), msg.positions.size());
    return;
  }
  const ros::WallTime now = ros::WallTime::now();
  for (size_t k = 0; k < msg.ids.size(); ++k) {
    const auto& q = msg.positions[k];
    if (msg.ids[k] >= definitions_.size() ||
        !(std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z))) {
      ROS_WARN_THROTTLE(1.0, "tissue/landmarks: landmark %u dropped (ids 0..%zu, finite positions)",
                        msg.ids[k], definitions_.size() - 1);
      continue;
    }
    definitions_[msg.ids[k]].target = Eigen::Vector3d(q.x, q.y, q.z);
    trackedAt_[msg.ids[k]] = now;
    newTracking_ = true;
  }
}

void LandmarkFittingNode::fit(const ros::SteadyTimerEvent&) {
  if (!newTracking_) return;
  newTracking_ = false;
  const ros::WallTime now = ros::WallTime::now();
  std::vector<tt::Landmark> tracked;
  for (size_t k = 0; k < definitions_.size(); ++k)
    if (!trackedAt_[k].isZero() && (now - trackedAt_[k]).toSec() <= params_.staleAfter)
      tracked.push_back(definitions_[k]);
  if (tracked.empty()) return;
  tt::FitParams fitParams;
  fitParams.maxIterations = params_.maxIterations;
  fitParams.levenbergMarquardt = params_.levenbergMarquardt;
  fitParams.residualTolerance = params_.residualTolerance;
  tissue_trainer::FitStatus status;
  try {
    tt::LandmarkFit landmarkFit(scene_.system, tracked, fitParams);
    const tt::FitResult result = landmarkFit.run();
    status.initial_residual = result.initialResidual;
    status.residual = result.residual;
    status.iterations = static_cast<uint32_t>(result.iterations.size());
    status.converged = result.converged();
    status.stop_reason = result.converged() ? "" : result.reason;
  } catch (const std::exception& e) {
    ROS_WARN_THROTTLE(1.0, "landmark_fitting: %s", e.what());
    return;
  }
  status.header.stamp = ros::Time::now();
  status.landmarks = static_cast<uint32_t>(tracked.size());
  status.fit_wall_time = (ros::WallTime::now() - now).toSec();
  publishActivations();
  statusPub_.publish(status);
}

void LandmarkFittingNode::publishActivations() {
  sensor_msgs::JointState msg;
  msg.header.stamp = ros::Time::now();
  for (const auto& model : scene_.system.models)
    if (const auto* muscles = dynamic_cast<const tt::ActivatedForceModel*>(model.get()))
      for (int i = 0; i < muscles->activationCount(); ++i) {
        msg.name.push_back(muscles->activationName(i));
        msg.position.push_back(muscles->activation(i));
      }
  activationPub_.publish(msg);
}

}  // namespace tt_nodes
