#pragma once
// Fits the muscle activations of a scene to tracked landmarks (M. Bao, "Derivation of
// Quasistatics and Landmark Optimization for Muscles", Secs. 1-3; core/fit/landmark_fit.h) at
// its own rate, off the simulation's loop, and publishes them on /tissue/activation for the
// simulation node. Its own copy of the scene is solved to equilibrium; each fit starts from the
// last one's activations and state.
#include <ros/ros.h>

#include <string>
#include <vector>

#include "tissue_trainer/TrackedLandmarks.h"
#include "tissue_trainer/core/fit/landmark_fit.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt_nodes {

struct LandmarkFittingParams {
  std::string scene;      // required: the scene the simulation runs
  std::string landmarks;  // required: landmark definitions, the `tissue_cli fit` targets format
  double rate = 10.0;     // fits per second at most (Hz)
  int maxIterations = 10;
  double levenbergMarquardt = 0.0;
  double residualTolerance = 1e-6;  // m
  double staleAfter = 1.0;          // s: tracked positions older than this are not fitted
};

class LandmarkFittingNode {
 public:
  LandmarkFittingNode(ros::NodeHandle nh, ros::NodeHandle pnh);
  bool start();  // false (after a fatal log line) on bad parameters or files

 private:
  void onLandmarks(const tissue_trainer::TrackedLandmarks& msg);
  void fit(const ros::SteadyTimerEvent&);
  void publishActivations();

  ros::NodeHandle nh_, pnh_;
  LandmarkFittingParams params_;
  tt::Scene scene_;
  std::vector<tt::Landmark> definitions_;     // from ~landmarks (targets replaced by tracking)
  std::vector<ros::WallTime> trackedAt_;      // per definition; zero: never tracked
  bool newTracking_ = false;
  ros::Subscriber landmarkSub_;
  ros::Publisher activationPub_, statusPub_;
  ros::SteadyTimer fitTimer_;
};

}  // namespace tt_nodes
