#include "simulation_node.h"

#include <geometry_msgs/TransformStamped.h>
#include <visualization_msgs/Marker.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

#include "../common/tissue_colour.h"
#include "node_params.h"
#include "tissue_trainer/ContactModel.h"
#include "tissue_trainer/TissueStatus.h"
#include "tissue_trainer/TissueSurface.h"
#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/model/activated_force_model.h"
#include "tissue_trainer/core/model/strain.h"
#include "tissue_trainer/core/parallel.h"
#include "tissue_trainer/core/scene/scene_runner.h"
#include "tissue_trainer/core/scene/state_snapshot.h"
#include "urdf_tool.h"

namespace tt_nodes {
namespace {

std::string defaultSnapshotPath() {
  const char* rosHome = std::getenv("ROS_HOME");
  const char* home = std::getenv("HOME");
  const std::string dir = rosHome && *rosHome ? rosHome : std::string(home ? home : ".") + "/.ros";
  return dir + "/simulation.snapshot";
}

Eigen::Isometry3d toEigen(const geometry_msgs::Transform& t) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z)
                      .normalized()
                      .toRotationMatrix();
  pose.translation() = Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z);
  return pose;
}

}  // namespace

SimulationNode::SimulationNode(ros::NodeHandle nh, ros::NodeHandle pnh)
    : nh_(nh), pnh_(pnh) {}

bool SimulationNode::readParams() {
  return readString(pnh_, "scene", params_.scene, true) &&
         readNumber(pnh_, "rate", params_.rate, 0.0, true) &&
         readInteger(pnh_, "surface_every", params_.surfaceEvery, 1) &&
         readNumber(pnh_, "marker_rate", params_.markerRate, 0.0, true) &&
         readNumber(pnh_, "damage_strain", params_.damageStrain, 0.0, true) &&
         readString(pnh_, "world_frame", params_.worldFrame, false) &&
         readString(pnh_, "tip_frame", params_.tipFrame, false) &&
         readNumber(pnh_, "guard_budget", params_.guardBudget, 0.0, false) &&
         readSnapshotParams() && readThreads();
}

bool SimulationNode::readThreads() {
  params_.threads = std::max(1, tt::hardwareThreads() - 1);
  if (!readInteger(pnh_, "threads", params_.threads, 1)) return false;
  if (params_.threads > tt::kMaxThreads) {
    ROS_FATAL("parameter %s: expected at most %d threads, got %d",
              pnh_.resolveName("threads").c_str(), tt::kMaxThreads, params_.threads);
    return false;
  }
  tt::setThreadCount(params_.threads);
  return true;
}

bool SimulationNode::readSnapshotParams() {
  params_.snapshotPath = defaultSnapshotPath();
  if (!readString(pnh_, "snapshot_path", params_.snapshotPath, false) ||
      !readNumber(pnh_, "snapshot_period", params_.snapshotPeriod, 0.0, false) ||
      !readString(pnh_, "resume", params_.resume, false))
    return false;
  if (params_.resume != "snapshot" && params_.resume != "scene") {
    ROS_FATAL("parameter %s: expected 'snapshot' or 'scene', got '%s'",
              pnh_.resolveName("resume").c_str(), params_.resume.c_str());
    return false;
  }
  return true;
}

void SimulationNode::resumeIfRestarted() {
  int starts = 0;
  if (pnh_.getParam("starts", starts) && starts > 0) restarts_ = starts;
  pnh_.setParam("starts", restarts_ + 1);
  if (restarts_ == 0) return;  // the first start of the session takes the scene
  if (params_.resume == "scene") {
    startedFrom_ = "scene (~resume is 'scene')";
    ROS_WARN("simulation: restart %d: starting from the scene (~resume is 'scene')", restarts_);
    return;
  }
  try {
    const tt::State s = tt::readStateSnapshot(params_.snapshotPath, fingerprint_, scene_.system.numNodes());
    scene_.system.state = s;
    resumedAt_ = s.t;
    startedFrom_ = "snapshot at t = " + std::to_string(s.t) + " s";
    ROS_WARN("simulation: restart %d: resumed from %s at t = %.3f s", restarts_,
             params_.snapshotPath.c_str(), s.t);
  } catch (const std::exception& e) {
    startedFrom_ = std::string("scene (snapshot refused: ") + e.what() + ")";
    ROS_WARN("simulation: restart %d: %s; starting from the scene instead", restarts_, e.what());
  }
}

void SimulationNode::writeSnapshot() {
  if (params_.snapshotPeriod <= 0.0 || !stable_) return;
  const ros::WallTime now = ros::WallTime::now();
  if ((now - lastSnapshot_).toSec() < params_.snapshotPeriod) return;
  lastSnapshot_ = now;
  try {
    tt::writeStateSnapshot(params_.snapshotPath, scene_.system.state, fingerprint_);
    ++snapshotsWritten_;
  } catch (const std::exception& e) {
    ++snapshotFailures_;
    ROS_ERROR_THROTTLE(10.0, "simulation: state snapshot not written (%lu failures): %s",
                       static_cast<unsigned long>(snapshotFailures_), e.what());
  }
}

bool SimulationNode::start() {
  if (!readParams()) return false;
  try {
    loadScene(params_.scene);
  } catch (const std::exception& e) {
    ROS_FATAL("parameter %s: %s", pnh_.resolveName("scene").c_str(), e.what());
    return false;
  }
  resumeIfRestarted();
  if (resumedAt_ < 0.0) settle();
  if (nh_.hasParam("robot_description")) {
    std::string xml;
    if (!nh_.getParam("robot_description", xml)) {
      ROS_FATAL("parameter %s: expected the URDF as a string", nh_.resolveName("robot_description").c_str());
      return false;
    }
    try {
      readRobotDescription();
    } catch (const std::exception& e) {
      ROS_FATAL("%s", e.what());
      return false;
    }
  } else {
    ROS_WARN("no /robot_description yet: no instrument contact until it is set");
  }

  contactPub_ = nh_.advertise<tissue_trainer::ContactModel>("tissue/contact", 10);
  // A new subscriber gets the triangles with the next message.
  surfacePub_ = nh_.advertise<tissue_trainer::TissueSurface>(
      "tissue/surface", 2, [this](const ros::SingleSubscriberPublisher&) { trianglesChanged_ = true; });
  markerPub_ = nh_.advertise<visualization_msgs::Marker>("tissue/surface_marker", 1, true);
  statusPub_ = nh_.advertise<tissue_trainer::TissueStatus>("tissue/status", 10);
  diagnosticsPub_ = nh_.advertise<diagnostic_msgs::DiagnosticArray>("diagnostics", 10);
  jawSub_ = nh_.subscribe("instrument/jaw/measured_js", 10, &SimulationNode::onJaw, this,
                          ros::TransportHints().tcpNoDelay());
  activationSub_ = nh_.subscribe("tissue/activation", 10, &SimulationNode::onActivation, this);
  resetSrv_ = pnh_.advertiseService("reset", &SimulationNode::onReset, this);
  loadSrv_ = pnh_.advertiseService("load_scene", &SimulationNode::onLoadScene, this);
  stepTimer_ = nh_.createSteadyTimer(ros::WallDuration(1.0 / params_.rate), &SimulationNode::step, this,
                                     /*oneshot=*/true);
  diagnosticsTimer_ = nh_.createSteadyTimer(ros::WallDuration(1.0), &SimulationNode::publishDiagnostics, this);
  ROS_INFO("simulation: scene '%s' (%d nodes, %d tets, %s), %.0f Hz (frames of %.1f ms, up to "
           "%.1f ms to keep real time), %d thread(s), %zu tool shapes; snapshot every %.2f s to %s",
           scene_.name.c_str(), scene_.system.numNodes(), scene_.system.mesh.numTets(),
           scene_.contact ? "contact" : "no contact", params_.rate, 1e3 / params_.rate,
           1e3 * frameClock_->maxStep(), tt::threadCount(), toolShapes_.size(),
           params_.snapshotPeriod, params_.snapshotPath.c_str());
  return true;
}

void SimulationNode::settle() {
  if (scene_.settleTime <= 0.0) return;
  const tt::SettleSummary s = tt::settleScene(scene_, scene_.settleTime, frameClock_->maxStep());
  if (s.ok)
    ROS_INFO("simulation: settled the tissue for %.3g s of simulated time in %d frames (%.2f s)",
             s.simulatedTime, s.frames, s.wallSeconds);
  else
    ROS_WARN("simulation: settling stopped after %.3g s of simulated time: %s", s.simulatedTime,
             s.failure.c_str());
  initialState_ = scene_.system.state;  // ~reset returns here
  frameClock_->restart();
}

void SimulationNode::readRobotDescription() {
  std::string xml;
  if (!nh_.getParam("robot_description", xml)) return;
  std::vector<std::string> skipped;
  toolShapes_ = toolShapesFromUrdf(xml, &skipped);
  for (const std::string& s : skipped) ROS_WARN("robot_description: %s", s.c_str());
  if (toolShapes_.empty()) ROS_WARN("robot_description: no link has collision geometry");
  haveRobot_ = true;
  buildContact();
}

void SimulationNode::buildContact() {
  contact_.reset();
  if (scene_.contact && haveRobot_)
    contact_ = std::make_unique<tt::TissueContact>(scene_.system, *scene_.contact, toolShapes_);
}

double SimulationNode::maxFrameTime(const tt::Scene& scene) const {
  return scene.maxFrameTime.value_or(kDefaultMaxFrames / params_.rate);
}

void SimulationNode::loadScene(const std::string& path) {
  tt::Scene loaded = tt::loadScene(path);  // throws before anything changes
  const double nominal = 1.0 / params_.rate, longest = maxFrameTime(loaded);
  if (longest < nominal) {
    char text[160];
    std::snprintf(text, sizeof text, "run.max_frame_time: expected a time >= the node's step 1/~rate (%g s), got %g",
                  nominal, longest);
    throw std::invalid_argument(path + ": " + text);
  }
  frameClock_ = std::make_unique<tt::RealTimeClock>(nominal, longest);
  proxy_ = tt::ToolProxy(loaded.contact ? loaded.contact->toolMaxSpeed : tt::ContactSettings().toolMaxSpeed);
  contact_.reset();
  scene_ = std::move(loaded);
  for (const std::string& note : scene_.notes) ROS_INFO("scene: %s", note.c_str());
  initialState_ = scene_.system.state;
  // Real time: a frame the guard cannot make stable may take guard_budget periods, or as many
  // typical steps where one step takes longer than a period (so that it can still be halved).
  if (auto* guard = dynamic_cast<tt::StabilityGuard*>(scene_.integrator.get()))
    guard->setWallBudget(params_.guardBudget / params_.rate, params_.guardBudget);
  fingerprint_ = tt::sceneFingerprint(scene_.name, scene_.system.mesh);
  display_ = tt::DisplaySurface(scene_);
  meter_ = tt::FrameMeter(scene_.system);
  trianglesChanged_ = true;
  lastMarker_ = ros::WallTime();
  buildContact();
}

bool SimulationNode::readTool(Eigen::Isometry3d& tip, std::vector<Eigen::Isometry3d>& links) {
  try {
    const geometry_msgs::TransformStamped tipTf =
        tfBuffer_.lookupTransform(params_.worldFrame, params_.tipFrame, ros::Time(0));
    // A frozen pose (the kinematics stopped) must not keep feeding contact at an old place.
    const double age = (ros::Time::now() - tipTf.header.stamp).toSec();
    if (age > kToolTimeout) {
      toolProblem_ = "instrument pose is " + std::to_string(age) + " s old";
      return false;
    }
    tip = toEigen(tipTf.transform);
    links.clear();
    for (const tt::ToolShape& s : toolShapes_)
      links.push_back(toEigen(tfBuffer_.lookupTransform(params_.worldFrame, s.link, ros::Time(0)).transform));
  } catch (const tf2::TransformException& e) {
    toolProblem_ = e.what();
    return false;
  }
  toolProblem_.clear();
  return true;
}

void SimulationNode::onJaw(const sensor_msgs::JointState& msg) {
  for (size_t k = 0; k < msg.name.size() && k < msg.position.size(); ++k)
    if (msg.name[k] == "jaw") {
      if (!std::isfinite(msg.position[k])) {
        ROS_WARN_THROTTLE(1.0, "instrument/jaw/measured_js: non-finite jaw angle ignored");
        return;
      }
      jawAngle_ = msg.position[k];
      haveJaw_ = true;
    }
}

// Muscle activations by name (a scene's `muscle_groups`); each one holds until the next
// message that names it. A name no muscle has, or a value that is not in [0, 1], is dropped
// with a warning; the message's other entries still apply.
void SimulationNode::onActivation(const sensor_msgs::JointState& msg) {
  if (msg.name.size() != msg.position.size()) {
    ROS_WARN_THROTTLE(1.0, "tissue/activation: %zu names but %zu positions; message ignored",
                      msg.name.size(), msg.position.size());
    return;
  }
  for (size_t k = 0; k < msg.name.size(); ++k) {
    const tt::ActivationRef muscle = scene_.system.findActivation(msg.name[k]);
    const double a = msg.position[k];
    if (!muscle.model)
      ROS_WARN_THROTTLE(1.0, "tissue/activation: scene '%s' has no muscle '%s'",
                        scene_.name.c_str(), msg.name[k].c_str());
    else if (!(a >= 0.0 && a <= 1.0))
      ROS_WARN_THROTTLE(1.0, "tissue/activation: '%s' = %g is not in [0, 1]; ignored",
                        msg.name[k].c_str(), a);
    else
      muscle.model->setActivation(muscle.index, a);
  }
}

void SimulationNode::scheduleNextStep() {
  const double wait = frameClock_->nextStart() - ros::SteadyTime::now().toSec();
  stepTimer_.stop();
  stepTimer_.setPeriod(ros::WallDuration(std::max(wait, 1e-6)));  // behind: at once
  stepTimer_.start();
}

void SimulationNode::followWithProxy(Eigen::Isometry3d& tip, std::vector<Eigen::Isometry3d>& links,
                                     double step) {
  const Eigen::Vector3d shift = proxy_.follow(tip.translation(), step) - tip.translation();
  tip.translation() += shift;
  for (Eigen::Isometry3d& link : links) link.translation() += shift;
}

void SimulationNode::step(const ros::SteadyTimerEvent&) {
  const ros::WallTime wallStart = ros::WallTime::now();
  const ros::Time stamp = ros::Time::now();
  tt::System& system = scene_.system;
  const tt::ClockStep planned = frameClock_->next(ros::SteadyTime::now().toSec());

  tt::ContactResult contact;
  if (contact_) {
    Eigen::Isometry3d tip;
    std::vector<Eigen::Isometry3d> links;
    if (readTool(tip, links)) {
      try {
        followWithProxy(tip, links, planned.step);
        contact_->setTool(tip, links, jawAngle_, system.state.t);
      } catch (const std::invalid_argument& e) {
        toolProblem_ = e.what();
        ROS_WARN_THROTTLE(1.0, "rejected tool pose: %s", e.what());
        contact_->clearTool();
      }
    } else {
      contact_->clearTool();
    }
    contact = contact_->update();
  }
  lastContact_ = contact;
  publishContact(contact, stamp);

  const double startTime = system.state.t;
  const tt::StepReport report = scene_.integrator->advance(system, planned.step);
  // The step taken: less than planned when the guard cut the frame short, 0 when it failed.
  const double stepTaken = system.state.t - startTime;
  frameClock_->advanced(stepTaken);
  ++step_;
  const tt::StabilityGuard* guard = tt::guardOf(*scene_.integrator);
  const tt::GuardFrame guardFrame = guard ? guard->lastFrame() : tt::GuardFrame{};
  if (guard) guard_.add(guardFrame);
  if (!report.ok) {
    ++failures_;
    ++failingSteps_;
    failure_ = report.failure;
    // One error when the failures start, a reminder every 10 s while they last.
    if (stable_)
      ROS_ERROR("simulation step failed (state restored; retrying every step): %s",
                report.failure.c_str());
    else
      ROS_ERROR_THROTTLE(10.0, "simulation still failing (%lu steps): %s",
                         static_cast<unsigned long>(failingSteps_), report.failure.c_str());
  } else if (!stable_) {
    ROS_INFO("simulation stable again after %lu failed steps",
             static_cast<unsigned long>(failingSteps_));
    failingSteps_ = 0;
  } else if (guardFrame.halvings > 0) {
    ROS_WARN_THROTTLE(5.0, "stability guard: %ld steps recovered by halving so far; last: %s",
                      guard_.recoveries, guardFrame.reason.c_str());
  }
  stable_ = report.ok;

  const bool surfaceDue = step_ % params_.surfaceEvery == 0;
  const bool markerDue = (ros::WallTime::now() - lastMarker_).toSec() >= 1.0 / params_.markerRate;
  if (surfaceDue || markerDue) display_.positions(system.state.x, displayPositions_);
  if (surfaceDue) publishSurface(stamp);
  if (markerDue) {
    publishMarker(stamp);
    lastMarker_ = ros::WallTime::now();
  }
  writeSnapshot();
  const double stepWall = (ros::WallTime::now() - wallStart).toSec();
  publishStatus(report, stepWall, planned, stepTaken, stamp);
  scheduleNextStep();
}

void SimulationNode::publishContact(const tt::ContactResult& r, const ros::Time& stamp) {
  tissue_trainer::ContactModel msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = params_.worldFrame;
  msg.sequence = ++contactSeq_;
  msg.in_contact = r.inContact;
  msg.tool_position.x = r.x0.x();
  msg.tool_position.y = r.x0.y();
  msg.tool_position.z = r.x0.z();
  msg.force.x = r.f0.x();
  msg.force.y = r.f0.y();
  msg.force.z = r.f0.z();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) msg.stiffness[3 * i + j] = r.K(i, j);
  msg.simulation_time = scene_.system.state.t;
  contactPub_.publish(msg);
}

void SimulationNode::publishSurface(const ros::Time& stamp) {
  const Eigen::Matrix3Xd& positions = displayPositions_;
  tissue_trainer::TissueSurface msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = params_.worldFrame;
  msg.sequence = ++surfaceSeq_;
  msg.positions.assign(positions.data(), positions.data() + positions.size());
  msg.triangles_changed = trianglesChanged_;
  // Also once a second: a subscriber whose queue dropped the message that carried them
  // (a renderer busy drawing while the simulation runs at 100 Hz) would never get them.
  if (trianglesChanged_ || (stamp - lastTrianglesStamp_).toSec() >= kTrianglesResendPeriod) {
    for (const tt::Triangle& t : display_.triangles())
      msg.triangles.insert(msg.triangles.end(), t.begin(), t.end());
    trianglesChanged_ = false;
    lastTrianglesStamp_ = stamp;
  }
  surfacePub_.publish(msg);
}

void SimulationNode::publishMarker(const ros::Time& stamp) {
  const Eigen::Matrix3Xd& positions = displayPositions_;
  visualization_msgs::Marker m;
  m.header.stamp = stamp;
  m.header.frame_id = params_.worldFrame;
  m.ns = "tissue";
  m.id = 0;
  m.type = visualization_msgs::Marker::TRIANGLE_LIST;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 1.0;
  m.color.r = tt_nodes::kParenchyma.r;
  m.color.g = tt_nodes::kParenchyma.g;
  m.color.b = tt_nodes::kParenchyma.b;
  m.color.a = 1.0f;
  m.points.reserve(3 * display_.triangles().size());
  for (const tt::Triangle& t : display_.triangles())
    for (int k : t) {
      geometry_msgs::Point p;
      p.x = positions(0, k);
      p.y = positions(1, k);
      p.z = positions(2, k);
      m.points.push_back(p);
    }
  markerPub_.publish(m);
}

void SimulationNode::publishStatus(const tt::StepReport& report, double stepWall,
                                   const tt::ClockStep& planned, double stepTaken,
                                   const ros::Time& stamp) {
  const tt::System& system = scene_.system;
  const double wall = ros::WallTime::now().toSec();
  clock_.emplace_back(wall, system.state.t);
  while (clock_.size() > 2 && wall - clock_.front().first > 1.0) clock_.pop_front();
  const double wallSpan = clock_.back().first - clock_.front().first;
  realTimeFactor_ = wallSpan > 0.0 ? (clock_.back().second - clock_.front().second) / wallSpan : 0.0;
  lastStepWall_ = stepWall;
  maxStepWall_ = std::max(maxStepWall_, stepWall);
  lastStepTaken_ = stepTaken;
  maxStepTaken_ = std::max(maxStepTaken_, stepTaken);
  const bool behind = planned.dropped > 0.0;
  if (behind) {
    ++behindCount_;
    ROS_WARN_THROTTLE(5.0, "simulation behind real time: a frame needed %.1f ms of simulated time, "
                      "more than run.max_frame_time (%.1f ms); %.1f ms of wall time dropped, %.2f s "
                      "since the scene was loaded",
                      1e3 * (planned.step + planned.dropped), 1e3 * frameClock_->maxStep(),
                      1e3 * planned.dropped, frameClock_->totalDropped());
  }

  const tt::FrameStatus measured =
      meter_.measure(system, static_cast<int>(step_), report, params_.damageStrain);
  const tt::FrameLog& log = measured.frame;
  const tt::StrainSummary& strain = measured.strain;
  maxStrain_ = strain.maxStrain;
  tissue_trainer::TissueStatus msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = params_.worldFrame;
  msg.simulation_time = system.state.t;
  msg.step_wall_time = stepWall;
  msg.real_time_factor = realTimeFactor_;
  msg.behind_schedule = behind;
  msg.step_time = stepTaken;
  msg.max_step_time = frameClock_->maxStep();
  msg.time_behind = planned.dropped;
  msg.total_time_behind = frameClock_->totalDropped();
  msg.tool_lag = proxy_.lag();
  msg.substeps = report.substeps;
  msg.rejected_steps = report.rejected;
  msg.newton_iterations = report.newtonIterations;
  msg.linear_iterations = report.linearIterations;
  msg.error_estimate = report.errorEstimate;
  msg.kinetic_energy = log.kineticEnergy;
  msg.elastic_energy = log.elasticEnergy;
  msg.volume_ratio = log.volumeRatio;
  msg.max_displacement = log.maxDisplacement;
  msg.contact_force = lastContact_.f0.norm();
  msg.contact_depth = 0.0;
  for (const tt::ContactPoint& p : lastContact_.points) msg.contact_depth = std::max(msg.contact_depth, p.depth);
  msg.max_strain = strain.maxStrain;
  msg.damage_strain = params_.damageStrain;
  msg.strained_volume = strain.strainedVolume;
  msg.stable = report.ok;
  msg.failure = report.failure;
  const tt::StabilityGuard* guard = tt::guardOf(*scene_.integrator);
  msg.guard_enabled = guard != nullptr;
  msg.guard_step_halvings = guard ? guard->lastFrame().halvings : 0;
  msg.guard_recoveries = guard_.recoveries;
  msg.guard_halvings = guard_.halvings;
  msg.guard_failures = guard_.failures;
  msg.guard_last_reason = guard_.lastReason;
  msg.restarts = static_cast<std::uint32_t>(restarts_);
  msg.resumed_at = resumedAt_;
  statusPub_.publish(msg);
}

void SimulationNode::publishDiagnostics(const ros::SteadyTimerEvent&) {
  if (!haveRobot_ && nh_.hasParam("robot_description")) {
    try {
      readRobotDescription();  // set after the node started
    } catch (const std::exception& e) {
      ROS_ERROR_THROTTLE(10.0, "%s", e.what());
    }
  }
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = ros::Time::now();
  diagnostic_msgs::DiagnosticStatus s;
  s.name = "simulation";
  s.hardware_id = scene_.name;
  const bool slow = realTimeFactor_ < 0.9;
  s.level = !stable_ ? diagnostic_msgs::DiagnosticStatus::ERROR
            : slow || (scene_.contact && !contact_) ? diagnostic_msgs::DiagnosticStatus::WARN
                                                    : diagnostic_msgs::DiagnosticStatus::OK;
  s.message = !stable_ ? "integrator failed: " + failure_
              : slow ? "behind real time"
              : (scene_.contact && !contact_) ? "no instrument (no /robot_description)"
              : restarts_ > 0 ? "running after restart " + std::to_string(restarts_) + ", from the " + startedFrom_
                                              : "running";
  auto add = [&s](const std::string& key, const std::string& value) {
    diagnostic_msgs::KeyValue kv;
    kv.key = key;
    kv.value = value;
    s.values.push_back(kv);
  };
  add("scene", scene_.file);
  add("rate_hz", std::to_string(params_.rate));
  add("real_time_factor", std::to_string(realTimeFactor_));
  add("last_step_ms", std::to_string(1e3 * lastStepWall_));
  add("max_step_ms", std::to_string(1e3 * maxStepWall_));
  add("last_simulated_step_ms", std::to_string(1e3 * lastStepTaken_));
  add("max_simulated_step_ms", std::to_string(1e3 * maxStepTaken_));
  add("max_frame_time_ms", std::to_string(1e3 * frameClock_->maxStep()));
  add("steps_behind_schedule", std::to_string(behindCount_));
  add("time_behind_s", std::to_string(frameClock_->totalDropped()));
  add("tool_proxy_lag_m", std::to_string(proxy_.lag()));
  add("integrator_failures", std::to_string(failures_));
  add("last_failure", failure_);
  add("guard_recoveries", std::to_string(guard_.recoveries));
  add("guard_halvings", std::to_string(guard_.halvings));
  add("guard_failures", std::to_string(guard_.failures));
  add("guard_frames_cut_short", std::to_string(guard_.cutShort));
  add("guard_last_reason", guard_.lastReason);
  add("in_contact", lastContact_.inContact ? "true" : "false");
  add("contact_points", std::to_string(lastContact_.points.size()));
  add("grasped_nodes", std::to_string(lastContact_.graspedNodes.size()));
  add("contact_force_n", std::to_string(lastContact_.f0.norm()));
  add("max_strain", std::to_string(maxStrain_));
  add("tool", toolProblem_.empty() ? "ok" : toolProblem_);
  add("restarts", std::to_string(restarts_));
  add("started_from", startedFrom_);
  add("snapshot_path", params_.snapshotPath);
  add("snapshots_written", std::to_string(snapshotsWritten_));
  add("snapshot_failures", std::to_string(snapshotFailures_));
  add("jaw", haveJaw_ ? std::to_string(jawAngle_) : "no reading (open)");
  array.status.push_back(s);
  diagnosticsPub_.publish(array);
  maxStepWall_ = 0.0;
  maxStepTaken_ = 0.0;
}

bool SimulationNode::onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  scene_.system.state = initialState_;
  if (contact_) contact_->clear();
  stable_ = true;
  failingSteps_ = 0;
  clock_.clear();
  frameClock_->restart();
  proxy_.reset();
  res.success = true;
  res.message = "scene '" + scene_.name + "' reset to its initial state";
  ROS_INFO("%s", res.message.c_str());
  return true;
}

bool SimulationNode::onLoadScene(tissue_trainer::LoadScene::Request& req,
                                 tissue_trainer::LoadScene::Response& res) {
  try {
    loadScene(req.scene_file);
    settle();
  } catch (const std::exception& e) {
    res.success = false;
    res.message = e.what();
    ROS_WARN("load_scene refused, keeping '%s': %s", scene_.name.c_str(), e.what());
    return true;
  }
  clock_.clear();
  stable_ = true;
  failingSteps_ = 0;
  res.success = true;
  res.message = "loaded scene '" + scene_.name + "' (" + std::to_string(scene_.system.numNodes()) +
                " nodes, " + std::to_string(scene_.system.mesh.numTets()) + " tets)";
  ROS_INFO("%s", res.message.c_str());
  return true;
}

}  // namespace tt_nodes
