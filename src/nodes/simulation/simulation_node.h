#pragma once
// The simulation node: loads a scene, steps its integrator in real time (tt::RealTimeClock:
// a frame that overran makes the next one start at once and cover the wall time that passed),
// couples the instrument (collision shapes from /robot_description, poses from tf2, jaw from
// /instrument/jaw/measured_js) to the tissue through tt::TissueContact, and publishes the
// contact model, the surface, a marker, the status and diagnostics. No physics here: the
// core does it all; this class converts messages and parameters.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tissue_trainer/LoadScene.h"
#include "tissue_trainer/core/contact/tissue_contact.h"
#include "tissue_trainer/core/contact/tool_proxy.h"
#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/scene/display_surface.h"
#include "tissue_trainer/core/scene/frame_meter.h"
#include "tissue_trainer/core/scene/real_time_clock.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt_nodes {

struct SimulationParams {
  std::string scene;
  double rate = 100.0;          // Hz: the nominal step is 1/rate s
  int surfaceEvery = 1;         // publish /tissue/surface every n-th step
  double markerRate = 2.0;      // Hz, /tissue/surface_marker
  double damageStrain = 0.3;    // Green-strain norm counted as damage
  std::string worldFrame = "world";
  std::string tipFrame = "instrument_tip";
  // Crash survival: the state is written to snapshotPath every snapshotPeriod s (0: never);
  // a restarted process (~starts > 0) continues from it unless resume is "scene".
  std::string snapshotPath;     // default: ROS_HOME (or ~/.ros)/simulation.snapshot
  double snapshotPeriod = 0.5;  // s
  std::string resume = "snapshot";
  // Wall time the stability guard may spend on one frame, in step periods (0: no limit).
  double guardBudget = 3.0;
  // Threads of the physics' element loops; default: the cores, less one for the haptic loop
  // that may share the host.
  int threads = 0;
};

class SimulationNode {
 public:
  SimulationNode(ros::NodeHandle nh, ros::NodeHandle pnh);
  // Reads the parameters and the scene; false (after one error line) when either is bad.
  bool start();

 private:
  bool readParams();
  bool readSnapshotParams();
  bool readThreads();  // ~threads, then the core's thread count
  // Replaces the scene (and rebuilds the contact) or throws tt::InputError.
  void loadScene(const std::string& path);
  // Steps the scene's run.settle_time before real time starts (the tissue at rest).
  void settle();
  void buildContact();
  // Counts this start in ~starts and, on a restart, continues from the last snapshot.
  void resumeIfRestarted();
  void writeSnapshot();
  void readRobotDescription();
  void step(const ros::SteadyTimerEvent&);
  // The step timer fires once; each frame sets it for the next (at once when behind).
  void scheduleNextStep();
  // The longest frame of a scene: run.max_frame_time, else kDefaultMaxFrames nominal steps.
  double maxFrameTime(const tt::Scene& scene) const;
  bool readTool(Eigen::Isometry3d& tip, std::vector<Eigen::Isometry3d>& links);
  // Moves the tool's poses onto the contact's proxy, which follows the tip at a bounded speed.
  void followWithProxy(Eigen::Isometry3d& tip, std::vector<Eigen::Isometry3d>& links, double step);
  void publishContact(const tt::ContactResult& r, const ros::Time& stamp);
  void publishSurface(const ros::Time& stamp);
  void publishMarker(const ros::Time& stamp);
  void publishStatus(const tt::StepReport& report, double stepWall, const tt::ClockStep& planned,
                     double stepTaken, const ros::Time& stamp);
  void publishDiagnostics(const ros::SteadyTimerEvent&);
  void onJaw(const sensor_msgs::JointState& msg);
  void onActivation(const sensor_msgs::JointState& msg);
  bool onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  bool onLoadScene(tissue_trainer::LoadScene::Request& req, tissue_trainer::LoadScene::Response& res);

  ros::NodeHandle nh_, pnh_;
  SimulationParams params_;
  tt::Scene scene_;
  tt::State initialState_;
  tt::DisplaySurface display_;
  tt::FrameMeter meter_;  // the status's measurements, with the scene's rest data
  Eigen::Matrix3Xd displayPositions_;  // of the current state, filled when a message is due
  std::unique_ptr<tt::TissueContact> contact_;
  tt::ToolProxy proxy_{tt::ContactSettings().toolMaxSpeed};
  std::vector<tt::ToolShape> toolShapes_;
  bool haveRobot_ = false;

  tf2_ros::Buffer tfBuffer_;
  tf2_ros::TransformListener tfListener_{tfBuffer_};
  ros::Publisher contactPub_, surfacePub_, markerPub_, statusPub_, diagnosticsPub_;
  ros::Subscriber jawSub_;
  ros::Subscriber activationSub_;
  ros::ServiceServer resetSrv_, loadSrv_;
  ros::SteadyTimer stepTimer_, diagnosticsTimer_;

  double jawAngle_ = 1.0;  // open until a jaw reading arrives
  bool haveJaw_ = false;
  std::uint64_t step_ = 0, contactSeq_ = 0, surfaceSeq_ = 0;
  static constexpr double kTrianglesResendPeriod = 1.0;  // s
  static constexpr double kToolTimeout = 0.2;  // s: an older instrument pose means no tool
  // Default longest frame, in nominal steps: 0.1 s at 100 Hz, the haptic bridge's default
  // model_timeout, beyond which the bridge fades the force anyway (docs/scene_format.md).
  static constexpr double kDefaultMaxFrames = 10.0;
  std::unique_ptr<tt::RealTimeClock> frameClock_;
  bool trianglesChanged_ = true;
  ros::Time lastTrianglesStamp_;
  ros::WallTime lastMarker_;
  bool stable_ = true;
  std::string failure_;
  std::string toolProblem_;

  // Crash survival (see SimulationParams).
  std::uint64_t fingerprint_ = 0;
  int restarts_ = 0;            // processes started before this one in the session
  double resumedAt_ = -1.0;     // simulation time this process continued from (-1: the scene)
  std::string startedFrom_ = "scene";
  ros::WallTime lastSnapshot_;
  std::uint64_t snapshotsWritten_ = 0, snapshotFailures_ = 0;

  // Statistics for the status and the diagnostics.
  std::deque<std::pair<double, double>> clock_;  // (wall s, simulation s) over the last second
  double realTimeFactor_ = 0.0, lastStepWall_ = 0.0, maxStepWall_ = 0.0;
  double lastStepTaken_ = 0.0, maxStepTaken_ = 0.0;  // simulated s (maxima since the last diagnostics)
  std::uint64_t behindCount_ = 0, failures_ = 0;
  std::uint64_t failingSteps_ = 0;  // in a row, up to the current step
  tt::GuardStats guard_;  // summed over the steps since the node started
  tt::ContactResult lastContact_;
  double maxStrain_ = 0.0;
};

}  // namespace tt_nodes
