#pragma once
// The haptic bridge node: a dedicated loop thread runs tt::HapticPipeline at ~rate; each
// tick's force goes through a lock-free queue to a publisher thread that sends
// /device/servo_cf (so the loop never allocates or waits in roscpp). Subscriber callbacks (on
// an AsyncSpinner) hand the latest device pose, enable input and contact models to the loop
// through small mutex-protected copies that the loop only try-locks (when a callback holds
// the lock, the tick runs on the inputs it took last). Timers publish the status (10 Hz) and
// /diagnostics (1 Hz). stop() fades the force to zero before the loop ends, and the last
// wrench sent is exactly zero.
//
// Unsafe inputs: a device pose with NaN/Inf is dropped and counted (the last finite pose
// stays); when no finite pose arrived within device_timeout (or none yet), the tick runs with
// the enable input false, so the safety filter fades the force to zero within fade_time and
// brings it back over resume_time once poses are fresh again. Malformed contact models are
// dropped and counted by the extrapolator; a stale contact model trips the watchdog.
#include <ros/ros.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <thread>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/WrenchStamped.h>
#include <std_msgs/Bool.h>

#include "bridge_params.h"
#include "force_sample_queue.h"
#include "tissue_trainer/ContactModel.h"
#include "tissue_trainer/core/haptics/haptic_pipeline.h"

namespace tt_nodes {

class HapticBridge {
 public:
  HapticBridge(ros::NodeHandle& nh, ros::NodeHandle& privateNh, const BridgeParams& params);
  ~HapticBridge();

  void start();  // starts the loop and publisher threads
  // Fades the force out (as a released deadman does, within fade_time), sends a zero wrench
  // and joins both threads. Waits at most fade_time + 0.2 s.
  void stop();

 private:
  struct DeviceInput {
    Eigen::Vector3d position = Eigen::Vector3d::Zero();
    double receivedAt = -1e300;  // monotonic s; never
    bool enabled = false;
    double enableAt = -1e300;  // monotonic s of the last /device/enable message
    std::uint64_t nonFinite = 0;
  };
  struct PendingModel {
    tt::ContactModel model;
    double receivedAt = 0.0;
  };
  struct Snapshot {
    tt::LoopStats loop;
    std::uint64_t ticks = 0, overruns = 0;
    bool hasModel = false;
    double modelAge = 0.0, extrapolationDistance = 0.0;
    tt::ExtrapolatorCounters models;
    std::uint64_t modelsDropped = 0, inputLockMisses = 0;
    bool deviceFresh = false, enabled = false;
    std::uint64_t deviceNonFinite = 0, deviceStaleTicks = 0;
    double gain = 0.0;
    bool watchdogTripped = false;
    tt::SafetyCounters safety;
    Eigen::Vector3d force = Eigen::Vector3d::Zero();
  };
  static constexpr std::size_t kModelQueue = 16;

  void onDevicePose(const geometry_msgs::PoseStamped::ConstPtr& msg);
  void onEnable(const std_msgs::Bool::ConstPtr& msg);
  void onContact(const tissue_trainer::ContactModel::ConstPtr& msg);

  void loop();
  void tick();
  bool takeInputs(std::size_t& models);
  void publishForces();
  void submit(const PendingModel& pending, const Eigen::Vector3d& xDevice);
  bool trySnapshot(double now, const DeviceInput& device, bool fresh);

  void publishStatus();
  void publishDiagnostics();

  BridgeParams params_;
  ros::Subscriber deviceSub_, enableSub_, contactSub_;
  ros::Publisher servoPub_, statusPub_, diagnosticsPub_;
  ros::WallTimer statusTimer_, diagnosticsTimer_;

  std::mutex inputMutex_;  // device_, models_
  DeviceInput device_;
  std::array<PendingModel, kModelQueue> models_;
  std::size_t modelsHead_ = 0, modelsCount_ = 0;
  std::uint64_t modelsDropped_ = 0;  // queue overflow: the oldest waiting model is dropped

  std::mutex snapshotMutex_;
  Snapshot snapshot_;

  // Owned by the loop thread.
  tt::HapticPipeline pipeline_;
  std::array<PendingModel, kModelQueue> taken_;
  DeviceInput lastDevice_;
  std::uint64_t inputLockMisses_ = 0;
  Eigen::Vector3d lastX0_ = Eigen::Vector3d::Zero();
  std::uint64_t deviceStaleTicks_ = 0;
  int ticksSinceSnapshot_ = 0;
  int snapshotEvery_ = 100;

  ForceSampleQueue forces_;
  std::atomic<bool> running_{false};
  std::atomic<bool> fadingOut_{false};
  std::atomic<bool> realtime_{false};
  std::thread thread_, publisher_;
};

}  // namespace tt_nodes
