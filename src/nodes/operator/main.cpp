// operator: the scripted trainee. A 1 kHz loop (absolute deadlines on CLOCK_MONOTONIC) plays
// the task script (~task) through a virtual hand that the device force (/device/servo_cf)
// pushes, solves the trocar IK for the hand position and publishes what a haptic device
// would: /device/measured_js, /device/measured_cp and the deadman /device/enable.
//
// As a device driver must, it protects the hand on its own: a force older than force_timeout
// (the bridge died or the network failed) counts as zero, and the magnitude of what it
// receives is clamped to force_limit (anyone on the ROS network can publish /device/servo_cf).
//
// The task clock starts only when the simulation is there: the hand holds the first keyframe
// until the first /tissue/status arrives (at most wait_for_simulation s), then start_delay.
#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/WrenchStamped.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Bool.h>

#include <cmath>

#include "eigen_msgs.h"
#include "periodic_clock.h"
#include "tissue_trainer/core/haptics/loop_stats.h"
#include "tissue_trainer/core/kinematics/tip_ik.h"
#include "tissue_trainer/TissueStatus.h"
#include "tissue_trainer/core/operator/task_script.h"
#include "tissue_trainer/core/operator/task_start.h"
#include "tissue_trainer/core/operator/virtual_hand.h"
#include "urdf_chain.h"

namespace tt::nodes {
namespace {

using tt_nodes::monotonicSeconds;

constexpr int kMaxLagTicks = 100;  // a tick this many periods late restarts the deadlines
constexpr double kMaxStampLag = 0.05;  // s a message's stamp may trail the wall clock

struct Settings {
  std::string task;
  double rate, startDelay, waitForSimulation, forceTimeout, forceLimit, roll;
  bool shutdownAtEnd;
  HandGains gains;
};

Settings readSettings(const ros::NodeHandle& pn) {
  Settings s;
  s.task = requiredStringParam(pn, "task");
  s.rate = numberParam(pn, "rate", 1000.0, 1.0, 10000.0);
  s.startDelay = numberParam(pn, "start_delay", 1.0, 0.0, 3600.0);
  s.waitForSimulation = numberParam(pn, "wait_for_simulation", 60.0, 0.0, 3600.0);
  s.forceTimeout = numberParam(pn, "force_timeout", 0.05, 0.0, 10.0);
  s.forceLimit = numberParam(pn, "force_limit", 5.0, 0.0, 1000.0);
  s.roll = numberParam(pn, "roll", 0.0, -M_PI, M_PI);
  const std::string end = stringParam(pn, "on_end", "hold");
  if (end != "hold" && end != "shutdown")
    throw std::runtime_error("~on_end: expected 'hold' or 'shutdown', got '" + end + "'");
  s.shutdownAtEnd = end == "shutdown";
  s.gains.mass = numberParam(pn, "hand_mass", s.gains.mass, 1e-4, 100.0);
  s.gains.stiffness = numberParam(pn, "hand_stiffness", s.gains.stiffness, 1e-3, 1e7);
  s.gains.damping = numberParam(pn, "hand_damping", s.gains.damping, 0.0, 1e6);
  return s;
}

class Operator {
 public:
  Operator(ros::NodeHandle& nh, ros::NodeHandle& pn)
      : settings_(readSettings(pn)),
        task_(TaskScript::load(settings_.task)),
        chain_(chainFromParameter(nh, stringParam(pn, "description_param", "/robot_description"),
                                  stringParam(pn, "tip_link", "instrument_tip"))),
        hand_(settings_.gains, task_.sample(0.0).tip),
        start_(settings_.waitForSimulation, settings_.startDelay),
        stats_(4096, 2.0 / settings_.rate) {
    ik_.variables = trocarPositionVariables(chain_);
    roll_ = chain_.variableIndex("roll");
    jaw_ = chain_.variableIndex("jaw");
    q_ = chain_.clamp(Eigen::VectorXd::Zero(chain_.numVariables()));
    if (roll_ >= 0) q_[roll_] = settings_.roll;
    // Start from the IK of the first keyframe, from a seed pointing down the shaft.
    const kin::IkResult first = kin::solveTipPosition(chain_, hand_.position(), q_, ik_);
    if (!first.reached())
      ROS_WARN("operator: the first keyframe is %.4f m out of the instrument's reach", first.error);
    q_ = first.q;
    js_.name.clear();
    for (const auto& v : chain_.variables()) js_.name.push_back(v.name);
    js_.position.resize(js_.name.size());
    js_.velocity.resize(js_.name.size());
    cp_.header.frame_id = chain_.links()[0];
    jsPub_ = nh.advertise<sensor_msgs::JointState>("device/measured_js", 10);
    cpPub_ = nh.advertise<geometry_msgs::PoseStamped>("device/measured_cp", 10);
    enablePub_ = nh.advertise<std_msgs::Bool>("device/enable", 1, true);
    forceSub_ = nh.subscribe("device/servo_cf", 10, &Operator::onForce, this,
                             ros::TransportHints().tcpNoDelay());
    if (start_.wait() == TaskStart::Wait::kWaiting) {
      statusSub_ = nh.subscribe("tissue/status", 1, &Operator::onStatus, this);
      ROS_INFO("operator: holding the first keyframe until the simulation's first %s (at most %.1f s)",
               statusSub_.getTopic().c_str(), settings_.waitForSimulation);
    }
    ROS_INFO("operator: task '%s' (%zu keyframes, %.2f s) at %.0f Hz, %.2f s after the wait; at the end: %s",
             task_.name().c_str(), task_.keyframes().size(), task_.duration(), settings_.rate,
             settings_.startDelay, settings_.shutdownAtEnd ? "shutdown" : "hold");
  }

  void run() {
    const double dt = 1.0 / settings_.rate;
    const long enableEvery = std::max(1L, std::lround(settings_.rate / 100.0));  // ~100 Hz
    tt_nodes::PeriodicClock clock(dt);
    const double start = monotonicSeconds();
    // The hand's state after tick k is the state at origin + k dt: the messages carry that
    // time, not the time they happen to be sent, so a late tick (a busy machine) and the
    // catch-up after it do not show as jumps of the tip's speed in the recorded session.
    ros::Time origin = ros::Time::now();
    std::string phase;
    for (long tick = 0; ros::ok(); ++tick) {
      ros::spinOnce();
      const double now = monotonicSeconds();
      stats_.record(now);
      const double t = start_.taskTime(tick * dt, simulationSeen_);
      if (!startReported_ && start_.wait() != TaskStart::Wait::kWaiting) reportStart();
      const TaskSample target = task_.sample(t);
      const bool running = t >= 0.0 && !target.finished;
      const Eigen::Vector3d force =
          running && now - forceTime_ <= settings_.forceTimeout ? force_ : Eigen::Vector3d::Zero();
      hand_.step(target.tip, target.tipVelocity, force, dt);
      // A tick more than kMaxStampLag behind the wall clock moves the stamps' origin up, so a
      // long stall never makes the pose look old to the simulation (its tool timeout: 0.2 s).
      const ros::Time wall = ros::Time::now();
      if ((wall - (origin + ros::Duration(tick * dt))).toSec() > kMaxStampLag)
        origin = wall - ros::Duration(tick * dt);
      step(target.jaw, dt, origin + ros::Duration(tick * dt));
      if (running && *target.phase != phase) {
        phase = *target.phase;
        ROS_INFO("operator: t = %.2f s, phase %s", t, phase.c_str());
      }
      if (running != enabled_ || tick % enableEvery == 0) {
        enabled_ = running;
        std_msgs::Bool msg;
        msg.data = running;
        enablePub_.publish(msg);
      }
      if (target.finished && !reportedEnd_) {
        reportedEnd_ = true;
        report(now - start);
        if (settings_.shutdownAtEnd) {
          ros::Duration(0.2).sleep();  // let the last messages (enable false) go out
          ros::requestShutdown();
          break;
        }
      }
      if (clock.waitNext(kMaxLagTicks)) {  // the deadlines restart from now, and so do the stamps
        ++resyncs_;
        origin = ros::Time::now() - ros::Duration((tick + 1) * dt);
      }
    }
  }

 private:
  void onStatus(const tissue_trainer::TissueStatus&) { simulationSeen_ = true; }

  void reportStart() {
    startReported_ = true;
    statusSub_.shutdown();
    if (start_.wait() == TaskStart::Wait::kSimulation)
      ROS_INFO("operator: the simulation's first status came %.2f s after start; the task starts in %.2f s",
               start_.waitEnded(), settings_.startDelay);
    else if (start_.wait() == TaskStart::Wait::kTimedOut)
      ROS_WARN("operator: no simulation status within wait_for_simulation = %.1f s; starting the task "
               "without it in %.2f s", settings_.waitForSimulation, settings_.startDelay);
  }

  void onForce(const geometry_msgs::WrenchStamped& msg) {
    Eigen::Vector3d f(msg.wrench.force.x, msg.wrench.force.y, msg.wrench.force.z);
    if (!f.allFinite()) {
      ++badForces_;
      ROS_WARN_THROTTLE(2.0, "operator: %lu non-finite forces on /device/servo_cf ignored", badForces_);
      return;
    }
    const double magnitude = f.norm();
    if (magnitude > settings_.forceLimit) {
      ++clampedForces_;
      ROS_WARN_THROTTLE(2.0, "operator: %lu forces above force_limit %.2f N clamped (last %.2f N)",
                        clampedForces_, settings_.forceLimit, magnitude);
      f *= settings_.forceLimit / magnitude;
    }
    force_ = f;
    forceTime_ = monotonicSeconds();
  }

  // IK of the hand position, then publish the device's joints and tip pose.
  void step(double jaw, double dt, const ros::Time& stamp) {
    const Eigen::VectorXd previous = q_;
    const kin::IkResult ik = kin::solveTipPosition(chain_, hand_.position(), q_, ik_);
    q_ = ik.q;
    if (jaw_ >= 0) q_[jaw_] = std::min(std::max(jaw, chain_.variables()[jaw_].lower), chain_.variables()[jaw_].upper);
    if (!ik.reached()) {
      ++unreachable_;
      ROS_WARN_THROTTLE(2.0, "operator: hand %.4f m out of reach (%lu ticks so far)", ik.error, unreachable_);
    }
    js_.header.stamp = stamp;
    for (int i = 0; i < chain_.numVariables(); ++i) {
      js_.position[i] = q_[i];
      js_.velocity[i] = (q_[i] - previous[i]) / dt;
    }
    jsPub_.publish(js_);
    cp_.header.stamp = stamp;
    cp_.pose = poseMsg(chain_.tipPose(q_));
    cpPub_.publish(cp_);
  }

  void report(double elapsed) const {
    const LoopStats s = stats_.summary();
    ROS_INFO("operator: task '%s' done after %.2f s; loop over the last %zu ticks: %.1f Hz, period "
             "p50 %.3f ms, p99 %.3f ms, max %.3f ms; %lu overruns (> 2 periods), %lu resyncs, "
             "%lu unreachable ticks",
             task_.name().c_str(), elapsed, s.ticks, s.rate, 1e3 * s.periodP50, 1e3 * s.periodP99,
             1e3 * s.periodMax, static_cast<unsigned long>(stats_.totalOverruns()), resyncs_, unreachable_);
  }

  Settings settings_;
  TaskScript task_;
  kin::Chain chain_;
  VirtualHand hand_;
  TaskStart start_;
  bool simulationSeen_ = false, startReported_ = false;
  LoopStatsWindow stats_;
  kin::IkOptions ik_;
  Eigen::VectorXd q_;
  int roll_ = -1, jaw_ = -1;
  Eigen::Vector3d force_ = Eigen::Vector3d::Zero();
  double forceTime_ = -1e9;
  bool enabled_ = false, reportedEnd_ = false;
  unsigned long badForces_ = 0, clampedForces_ = 0, unreachable_ = 0, resyncs_ = 0;
  sensor_msgs::JointState js_;
  geometry_msgs::PoseStamped cp_;
  ros::Publisher jsPub_, cpPub_, enablePub_;
  ros::Subscriber forceSub_, statusSub_;
};

}  // namespace
}  // namespace tt::nodes

int main(int argc, char** argv) {
  ros::init(argc, argv, "operator");
  ros::NodeHandle nh, pn("~");
  try {
    tt::nodes::Operator node(nh, pn);
    node.run();
  } catch (const std::exception& e) {
    ROS_FATAL("operator: %s", e.what());
    return 2;
  }
  return 0;
}
