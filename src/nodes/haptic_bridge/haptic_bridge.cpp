#include "haptic_bridge.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <diagnostic_msgs/DiagnosticArray.h>

#include "contact_conversion.h"
#include "periodic_clock.h"
#include "tissue_trainer/HapticStatus.h"

namespace tt_nodes {

namespace {

constexpr int kRealtimePriority = 80;
// The publisher thread sends what the loop produced; below the loop, above everything else,
// so that a busy machine delays the wrench as little as the loop.
constexpr int kPublisherPriority = 70;
constexpr double kShutdownMargin = 0.2;  // s: stop() gives up fading after fade_time + this

geometry_msgs::Vector3 toMsg(const Eigen::Vector3d& v) {
  geometry_msgs::Vector3 m;
  m.x = v.x();
  m.y = v.y();
  m.z = v.z();
  return m;
}

diagnostic_msgs::KeyValue keyValue(const std::string& key, double value) {
  diagnostic_msgs::KeyValue kv;
  kv.key = key;
  kv.value = std::to_string(value);
  return kv;
}

// Turns the loop's monotonic times into ROS times (wall or simulated). The offset between the
// two clocks is read between two monotonic reads; a read that the thread was preempted in keeps
// the previous offset, so that a preemption does not show in the stamps. What is left (the
// offset's jitter within a read, under 50 us) never steps a stamp back: a stamp up to 1 ms
// before the previous one is taken as equal to it (a larger step back is the ROS clock's own,
// such as a replayed bag starting again).
class RosStamper {
 public:
  ros::Time stampOf(double monotonicTime) {
    const int attempts = known_ ? 1 : kFirstAttempts;  // the first offset is taken in any case
    for (int i = 1; i <= attempts; ++i) {
      const double before = monotonicSeconds();
      const double rosNow = ros::Time::now().toSec();
      const double after = monotonicSeconds();
      if (after - before <= kMaxReadSeconds || (!known_ && i == attempts)) {
        offset_ = rosNow - 0.5 * (before + after);
        known_ = true;
        break;
      }
    }
    double t = monotonicTime + offset_;
    if (t < last_ && last_ - t < kMaxJitterSeconds) t = last_;
    last_ = t;
    return t > 0.0 ? ros::Time(t) : ros::Time::now();
  }

 private:
  static constexpr double kMaxJitterSeconds = 1e-3;
  static constexpr double kMaxReadSeconds = 50e-6;
  static constexpr int kFirstAttempts = 20;
  double offset_ = 0.0;
  double last_ = 0.0;
  bool known_ = false;
};

}  // namespace

HapticBridge::HapticBridge(ros::NodeHandle& nh, ros::NodeHandle& privateNh,
                           const BridgeParams& params)
    : params_(params), pipeline_(params.pipeline) {
  snapshotEvery_ = std::max(1, static_cast<int>(std::lround(params_.rate / 10.0)));
  device_.enabled = !params_.requireEnable;

  const ros::TransportHints hints = ros::TransportHints().tcpNoDelay();
  servoPub_ = nh.advertise<geometry_msgs::WrenchStamped>("device/servo_cf", 100);
  statusPub_ = privateNh.advertise<tissue_trainer::HapticStatus>("status", 10);
  diagnosticsPub_ = nh.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
  deviceSub_ = nh.subscribe("device/measured_cp", 100, &HapticBridge::onDevicePose, this, hints);
  contactSub_ = nh.subscribe("tissue/contact", 100, &HapticBridge::onContact, this, hints);
  if (params_.requireEnable)
    enableSub_ = nh.subscribe("device/enable", 10, &HapticBridge::onEnable, this, hints);
  statusTimer_ = nh.createWallTimer(ros::WallDuration(0.1), [this](const ros::WallTimerEvent&) {
    publishStatus();
  });
  diagnosticsTimer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) {
    publishDiagnostics();
  });
}

HapticBridge::~HapticBridge() { stop(); }

void HapticBridge::start() {
  running_ = true;
  thread_ = std::thread([this] { loop(); });
  publisher_ = std::thread([this] { publishForces(); });
}

void HapticBridge::stop() {
  fadingOut_ = true;
  if (thread_.joinable()) thread_.join();
  running_ = false;
  forces_.wake();
  if (publisher_.joinable()) publisher_.join();
}

void HapticBridge::onDevicePose(const geometry_msgs::PoseStamped::ConstPtr& msg) {
  const auto& p = msg->pose.position;
  const Eigen::Vector3d x(p.x, p.y, p.z);
  const double now = monotonicSeconds();
  std::lock_guard<std::mutex> lock(inputMutex_);
  if (!x.allFinite()) {
    ++device_.nonFinite;
    return;
  }
  device_.position = x;
  device_.receivedAt = now;
}

void HapticBridge::onEnable(const std_msgs::Bool::ConstPtr& msg) {
  std::lock_guard<std::mutex> lock(inputMutex_);
  device_.enabled = msg->data;
  device_.enableAt = monotonicSeconds();
}

void HapticBridge::onContact(const tissue_trainer::ContactModel::ConstPtr& msg) {
  PendingModel pending;
  pending.model = toCore(*msg);
  pending.receivedAt = monotonicSeconds();
  std::lock_guard<std::mutex> lock(inputMutex_);
  if (modelsCount_ == kModelQueue) {  // the loop stalled: keep the newest models
    modelsHead_ = (modelsHead_ + 1) % kModelQueue;
    --modelsCount_;
    ++modelsDropped_;
  }
  models_[(modelsHead_ + modelsCount_) % kModelQueue] = pending;
  ++modelsCount_;
}

void HapticBridge::loop() {
  const std::string refused = tryRealtime(kRealtimePriority);
  realtime_ = refused.empty();
  if (realtime_)
    ROS_INFO("haptic_bridge: loop thread runs SCHED_FIFO priority %d", kRealtimePriority);
  else
    ROS_WARN("haptic_bridge: SCHED_FIFO refused (%s); the loop runs at normal priority",
             refused.c_str());
  PeriodicClock clock(1.0 / params_.rate);
  const double fadeLimit = params_.pipeline.safety.fadeTime + kShutdownMargin;
  double fadeStart = -1.0;
  while (ros::ok()) {
    clock.waitNext();
    tick();
    if (!fadingOut_) continue;
    const double now = monotonicSeconds();
    if (fadeStart < 0.0) fadeStart = now;
    const bool faded = pipeline_.safety().gain() == 0.0 && pipeline_.safety().output().isZero();
    if (faded || now - fadeStart > fadeLimit) break;
  }
  ForceSample zero;  // the last wrench is exactly zero, whatever happened before
  zero.tick = pipeline_.loopStats().totalTicks() + 1;
  zero.time = monotonicSeconds();
  forces_.push(zero);
}

// Publishes the loop's force samples as they come (roscpp may allocate and lock here).
void HapticBridge::publishForces() {
  tryRealtime(kPublisherPriority);  // refused: it runs at normal priority, as the loop says
  geometry_msgs::WrenchStamped wrench;
  wrench.header.frame_id = "world";
  ForceSample sample;
  RosStamper stamper;
  for (bool more = true; more;) {
    more = running_;  // read before draining: nothing pushed before stop() is lost
    forces_.wait(0.1);
    while (forces_.pop(sample)) {
      wrench.header.seq = static_cast<std::uint32_t>(sample.tick);
      wrench.header.stamp = stamper.stampOf(sample.time);
      wrench.wrench.force = toMsg(sample.force);
      servoPub_.publish(wrench);
    }
  }
}

void HapticBridge::tick() {
  std::size_t n = 0;
  if (!takeInputs(n)) ++inputLockMisses_;
  DeviceInput device = lastDevice_;
  const double now = monotonicSeconds();
  for (std::size_t i = 0; i < n; ++i) submit(taken_[i], device.position);

  const bool fresh = now - device.receivedAt <= params_.deviceTimeout;
  if (!fresh) ++deviceStaleTicks_;
  // A deadman that stopped publishing counts as released, like a silent device.
  device.enabled = device.enabled && !fadingOut_ &&
                   (!params_.requireEnable || now - device.enableAt <= params_.deviceTimeout);
  ForceSample sample;
  sample.force = pipeline_.tick(device.position, now, fresh && device.enabled);
  sample.tick = pipeline_.loopStats().totalTicks();
  sample.time = now;
  forces_.push(sample);

  if (++ticksSinceSnapshot_ >= snapshotEvery_ && trySnapshot(now, device, fresh))
    ticksSinceSnapshot_ = 0;
}

// Copies the callbacks' latest inputs without waiting: false when a callback holds the lock
// (this tick then runs on the inputs taken last; waiting models come next tick).
bool HapticBridge::takeInputs(std::size_t& models) {
  std::unique_lock<std::mutex> lock(inputMutex_, std::try_to_lock);
  if (!lock.owns_lock()) return false;
  lastDevice_ = device_;
  for (models = 0; models < modelsCount_; ++models)
    taken_[models] = models_[(modelsHead_ + models) % kModelQueue];
  modelsHead_ = modelsCount_ = 0;
  return true;
}

void HapticBridge::submit(const PendingModel& pending, const Eigen::Vector3d& xDevice) {
  if (pipeline_.submit(pending.model, pending.receivedAt, xDevice) == tt::ModelVerdict::kAccepted)
    lastX0_ = pending.model.x0;
}

// Copies the state for the status timers; never waits for the lock (retried next tick).
bool HapticBridge::trySnapshot(double now, const DeviceInput& device, bool fresh) {
  std::unique_lock<std::mutex> lock(snapshotMutex_, std::try_to_lock);
  if (!lock.owns_lock()) return false;
  const tt::ForceExtrapolator& e = pipeline_.extrapolator();
  const tt::SafetyFilter& s = pipeline_.safety();
  Snapshot& o = snapshot_;
  o.loop = pipeline_.loopStats().summary();
  o.ticks = pipeline_.loopStats().totalTicks();
  o.overruns = pipeline_.loopStats().totalOverruns();
  o.hasModel = e.hasModel();
  o.modelAge = e.modelAge(now);
  o.extrapolationDistance = e.hasModel() ? (device.position - lastX0_).norm() : 0.0;
  o.models = e.counters();
  o.inputLockMisses = inputLockMisses_;
  o.deviceFresh = fresh;
  o.enabled = device.enabled;
  o.deviceNonFinite = device.nonFinite;
  o.deviceStaleTicks = deviceStaleTicks_;
  o.gain = s.gain();
  o.watchdogTripped = s.watchdogTripped();
  o.safety = s.counters();
  o.force = s.output();
  return true;
}

void HapticBridge::publishStatus() {
  Snapshot o;
  {
    std::lock_guard<std::mutex> lock(snapshotMutex_);
    o = snapshot_;
  }
  {
    std::lock_guard<std::mutex> lock(inputMutex_);
    o.modelsDropped = modelsDropped_;
  }
  tissue_trainer::HapticStatus m;
  m.header.stamp = ros::Time::now();
  m.rate = o.loop.rate;
  m.period_p50 = o.loop.periodP50;
  m.period_p99 = o.loop.periodP99;
  m.period_max = o.loop.periodMax;
  m.overruns = o.overruns;
  m.ticks = o.ticks;
  m.realtime = realtime_;
  m.has_model = o.hasModel;
  m.model_age = o.modelAge;
  m.extrapolation_distance = o.extrapolationDistance;
  m.models_accepted = o.models.accepted;
  m.models_malformed = o.models.malformed;
  m.models_stale = o.models.staleSequence;
  m.model_resets = o.models.restarts;
  m.models_dropped = o.modelsDropped;
  m.input_lock_misses = o.inputLockMisses;
  m.wrenches_dropped = forces_.dropped();
  m.device_fresh = o.deviceFresh;
  m.enabled = o.enabled;
  m.device_non_finite = o.deviceNonFinite;
  m.device_stale_ticks = o.deviceStaleTicks;
  m.gain = o.gain;
  m.watchdog_tripped = o.watchdogTripped;
  m.watchdog_trips = o.safety.watchdogTrips;
  m.force_clamped = o.safety.forceClamped;
  m.rate_limited = o.safety.rateLimited;
  m.non_finite_forces = o.safety.nonFiniteInputs;
  m.time_faults = o.safety.timeFaults;
  m.force = toMsg(o.force);
  statusPub_.publish(m);
}

void HapticBridge::publishDiagnostics() {
  Snapshot o;
  {
    std::lock_guard<std::mutex> lock(snapshotMutex_);
    o = snapshot_;
  }
  diagnostic_msgs::DiagnosticStatus d;
  d.name = "haptic_bridge: force loop";
  d.hardware_id = "haptic_device";
  d.level = diagnostic_msgs::DiagnosticStatus::OK;
  d.message = "ok";
  if (o.loop.rate < 0.95 * params_.rate) {
    d.level = diagnostic_msgs::DiagnosticStatus::WARN;
    d.message = "loop rate below 95% of the nominal rate";
  } else if (!o.deviceFresh) {
    d.level = diagnostic_msgs::DiagnosticStatus::WARN;
    d.message = "no fresh device pose: force faded out";
  } else if (o.watchdogTripped) {
    d.level = diagnostic_msgs::DiagnosticStatus::WARN;
    d.message = o.hasModel ? "contact model stale: force faded out" : "no contact model yet";
  } else if (!o.enabled) {
    d.message = "disabled by /device/enable";
  }
  d.values = {keyValue("rate_hz", o.loop.rate), keyValue("period_p50_s", o.loop.periodP50),
              keyValue("period_p99_s", o.loop.periodP99), keyValue("period_max_s", o.loop.periodMax),
              keyValue("overruns", double(o.overruns)), keyValue("model_age_s", o.modelAge),
              keyValue("gain", o.gain), keyValue("watchdog_trips", double(o.safety.watchdogTrips)),
              keyValue("models_malformed", double(o.models.malformed)),
              keyValue("device_non_finite", double(o.deviceNonFinite)),
              keyValue("realtime", realtime_ ? 1.0 : 0.0)};
  diagnostic_msgs::DiagnosticArray a;
  a.header.stamp = ros::Time::now();
  a.status.push_back(d);
  diagnosticsPub_.publish(a);
}

}  // namespace tt_nodes
