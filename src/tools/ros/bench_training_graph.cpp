// Speed of the distributed training system, measured from outside the nodes over real topics.
//
//   bench_training_graph haptic  [--duration S] [--csv FILE]
//     Plays the device (a pose every 1 ms that steps 1 mm back and forth every 50 ms) and the
//     simulation (a fixed contact model at 100 Hz: f0, K = 200 N/m) against a running
//     haptic_bridge. Device-to-force latency: from publishing a stepped pose to receiving the
//     first wrench that reflects it. Also the bridge's own tick periods (/haptic_bridge/status)
//     and the period between wrenches as received.
//   bench_training_graph graph   [--duration S] [--csv FILE] [--label TEXT]
//     Watches a running training graph: simulation step wall time, status rate, real-time
//     factor, the simulated step taken and the wall time dropped (steps behind schedule), the
//     tool proxy's lag, the first status after the probe started, contact models and wrenches
//     received, bridge periods.
//   bench_training_graph surface_source --vertices N [--rate HZ] [--triangles-every K]
//   bench_training_graph surface_sink   [--duration S] [--csv FILE] [--label TEXT]
//     Topic transport of /bench/surface (tissue_trainer/TissueSurface of N vertices) between
//     two processes: latency from the stamp set just before publish() to the callback, and
//     the bytes per message.
// Each mode prints its result as one "RESULT key=value ..." line and appends it to --csv.
#include <ros/ros.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/WrenchStamped.h>

#include "common/command_line.h"
#include "periodic_clock.h"
#include "tissue_trainer/ContactModel.h"
#include "tissue_trainer/HapticStatus.h"
#include "tissue_trainer/TissueStatus.h"
#include "tissue_trainer/TissueSurface.h"

namespace {

using tt_nodes::monotonicSeconds;

struct Options {
  std::string mode;
  double duration = 20.0;
  std::string csv, label;
  int vertices = 0;
  double rate = 100.0;
  int trianglesEvery = 100;
};

Options parseOptions(int argc, char** argv) {
  tt::tools::CommandLine args(argc, argv,
                              "bench_training_graph haptic|graph|surface_source|surface_sink "
                              "[--duration S] [--csv FILE] [--label TEXT] [--vertices N] "
                              "[--rate HZ] [--triangles-every N]");
  Options o;
  o.duration = args.positiveNumber("--duration", o.duration);
  o.csv = args.text("--csv", "");
  o.label = args.text("--label", "");
  o.vertices = args.positiveInteger("--vertices", 0);
  o.rate = args.positiveNumber("--rate", o.rate);
  o.trianglesEvery = args.positiveInteger("--triangles-every", o.trianglesEvery);
  const std::vector<std::string> mode = args.positional(1);
  args.finish();
  const std::vector<std::string> modes = {"haptic", "graph", "surface_source", "surface_sink"};
  if (mode.empty() || std::find(modes.begin(), modes.end(), mode[0]) == modes.end())
    args.fail("expected a mode: haptic, graph, surface_source or surface_sink, got '" +
              (mode.empty() ? std::string() : mode[0]) + "'");
  o.mode = mode[0];
  return o;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, std::size_t(p * double(v.size())))];
}

double maxOf(const std::vector<double>& v) {
  return v.empty() ? std::nan("") : *std::max_element(v.begin(), v.end());
}

// Key/value pairs in the order added, printed as one RESULT line and appended to a CSV file
// (a header line is written when the file is new).
class Result {
 public:
  void add(const std::string& key, double value, const char* format = "%.6g") {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, value);
    add(key, std::string(buf));
  }
  void add(const std::string& key, const std::string& value) { items_.push_back({key, value}); }

  void emit(const std::string& csvPath) const {
    std::string line = "RESULT";
    for (const auto& kv : items_) line += " " + kv.first + "=" + kv.second;
    std::printf("%s\n", line.c_str());
    if (csvPath.empty()) return;
    const bool fresh = access(csvPath.c_str(), F_OK) != 0;
    FILE* f = std::fopen(csvPath.c_str(), "a");
    if (!f) {
      std::fprintf(stderr, "bench_training_graph: cannot write %s\n", csvPath.c_str());
      return;
    }
    for (std::size_t i = 0; fresh && i < items_.size(); ++i)
      std::fprintf(f, "%s%s", i ? "," : "", items_[i].first.c_str());
    if (fresh) std::fprintf(f, "\n");
    for (std::size_t i = 0; i < items_.size(); ++i)
      std::fprintf(f, "%s%s", i ? "," : "", items_[i].second.c_str());
    std::fprintf(f, "\n");
    std::fclose(f);
  }

 private:
  std::vector<std::pair<std::string, std::string>> items_;
};

// The bridge's own loop statistics, sampled from its 10 Hz status.
struct BridgeStatusLog {
  std::mutex m;
  std::vector<double> p50, p99, max, rate;
  bool realtime = false;
  std::uint64_t overruns0 = 0, overruns = 0, ticks0 = 0, ticks = 0;
  std::uint64_t lockMisses0 = 0, lockMisses = 0, dropped0 = 0, dropped = 0;
  bool first = true;

  void restart() {
    std::lock_guard<std::mutex> l(m);
    first = true;
    p50.clear();
    p99.clear();
    max.clear();
    rate.clear();
  }

  void onStatus(const tissue_trainer::HapticStatus::ConstPtr& s) {
    std::lock_guard<std::mutex> l(m);
    if (first) {
      overruns0 = s->overruns;
      ticks0 = s->ticks;
      lockMisses0 = s->input_lock_misses;
      dropped0 = s->wrenches_dropped;
      first = false;
      return;  // its window still holds ticks from before the measurement
    }
    p50.push_back(s->period_p50);
    p99.push_back(s->period_p99);
    max.push_back(s->period_max);
    rate.push_back(s->rate);
    realtime = s->realtime;
    overruns = s->overruns - overruns0;
    ticks = s->ticks - ticks0;
    lockMisses = s->input_lock_misses - lockMisses0;
    dropped = s->wrenches_dropped - dropped0;
  }

  void addTo(Result& r) {
    std::lock_guard<std::mutex> l(m);
    r.add("bridge_rate_hz", percentile(rate, 0.5), "%.1f");
    r.add("bridge_period_p50_us", 1e6 * percentile(p50, 0.5), "%.1f");
    r.add("bridge_period_p99_us", 1e6 * maxOf(p99), "%.1f");
    r.add("bridge_period_max_us", 1e6 * maxOf(max), "%.1f");
    r.add("bridge_overruns", double(overruns), "%.0f");
    r.add("bridge_ticks", double(ticks), "%.0f");
    r.add("bridge_realtime", realtime ? "1" : "0");
    r.add("bridge_lock_misses", double(lockMisses), "%.0f");
    r.add("bridge_wrenches_dropped", double(dropped), "%.0f");
  }
};

// Inter-arrival times of messages at this process, in monotonic seconds.
struct ArrivalLog {
  std::vector<double> gaps;
  double last = -1.0;
  std::size_t count = 0;
  void arrived(double t) {
    if (last >= 0.0) gaps.push_back(t - last);
    last = t;
    ++count;
  }
  void addTo(Result& r, const std::string& prefix) const {
    r.add(prefix + "_received", double(count), "%.0f");
    r.add(prefix + "_gap_p50_us", 1e6 * percentile(gaps, 0.5), "%.1f");
    r.add(prefix + "_gap_p99_us", 1e6 * percentile(gaps, 0.99), "%.1f");
    r.add(prefix + "_gap_max_us", 1e6 * maxOf(gaps), "%.1f");
  }
};

bool waitForSubscribers(const std::vector<ros::Publisher*>& pubs, double timeout) {
  const double end = monotonicSeconds() + timeout;
  while (monotonicSeconds() < end && ros::ok()) {
    bool all = true;
    for (ros::Publisher* p : pubs) all = all && p->getNumSubscribers() > 0;
    if (all) return true;
    ros::WallDuration(0.05).sleep();
  }
  return false;
}

// ---- haptic: device-to-force latency against a real bridge ---------------------------------

constexpr double kStiffness = 200.0;   // N/m
constexpr double kStep = 0.001;        // m: device step, -0.2 N of force
constexpr double kStepPeriod = 0.05;   // s between steps

class HapticProbe {
 public:
  explicit HapticProbe(ros::NodeHandle& nh) {
    const ros::TransportHints hints = ros::TransportHints().tcpNoDelay();
    posePub_ = nh.advertise<geometry_msgs::PoseStamped>("device/measured_cp", 100);
    modelPub_ = nh.advertise<tissue_trainer::ContactModel>("tissue/contact", 10);
    wrenchSub_ = nh.subscribe("device/servo_cf", 1000, &HapticProbe::onWrench, this, hints);
    statusSub_ = nh.subscribe("haptic_bridge/status", 10, &BridgeStatusLog::onStatus, &status_);
  }

  int run(const Options& o) {
    if (!waitForSubscribers({&posePub_, &modelPub_}, 20.0)) {
      std::fprintf(stderr, "bench_training_graph: no haptic_bridge subscribed within 20 s\n");
      return 1;
    }
    std::thread models([&] { publishModels(o.duration + 1.5); });
    playDevice(1.0, false);  // the force fades in over resume_time
    {
      std::lock_guard<std::mutex> l(m_);
      measuring_ = true;
      arrivals_ = ArrivalLog();
    }
    status_.restart();
    playDevice(o.duration, true);
    models.join();
    Result r;
    r.add("mode", "haptic");
    r.add("duration_s", o.duration, "%.1f");
    {
      std::lock_guard<std::mutex> l(m_);
      r.add("latency_samples", double(latencies_.size()), "%.0f");
      r.add("latency_p50_us", 1e6 * percentile(latencies_, 0.5), "%.1f");
      r.add("latency_p99_us", 1e6 * percentile(latencies_, 0.99), "%.1f");
      r.add("latency_max_us", 1e6 * maxOf(latencies_), "%.1f");
      r.add("steps_missed", double(missed_), "%.0f");
      arrivals_.addTo(r, "wrench");
    }
    status_.addTo(r);
    r.emit(o.csv);
    return 0;
  }

 private:
  // 1 kHz device poses; every kStepPeriod the position toggles by kStep along x.
  void playDevice(double duration, bool measure) {
    geometry_msgs::PoseStamped p;
    p.header.frame_id = "world";
    p.pose.orientation.w = 1.0;
    tt_nodes::PeriodicClock clock(0.001);
    const int ticks = int(std::lround(duration * 1000.0));
    const int ticksPerStep = int(std::lround(kStepPeriod * 1000.0));
    for (int i = 0; i < ticks && ros::ok(); ++i) {
      clock.waitNext();
      if (i % ticksPerStep == 0) {
        std::lock_guard<std::mutex> l(m_);
        if (measure && waiting_) ++missed_;
        stepped_ = !stepped_;
        waiting_ = measure;
        sentAt_ = monotonicSeconds();
      }
      p.header.stamp = ros::Time::now();
      p.pose.position.x = stepped_ ? kStep : 0.0;
      posePub_.publish(p);
    }
  }

  void publishModels(double duration) {
    tissue_trainer::ContactModel m;
    m.header.frame_id = "world";
    m.in_contact = true;
    m.force.y = 1.0;
    for (int i = 0; i < 3; ++i) m.stiffness[4 * i] = kStiffness;
    ros::WallRate rate(100.0);
    const double end = monotonicSeconds() + duration;
    for (std::uint64_t seq = 1; monotonicSeconds() < end && ros::ok(); ++seq) {
      m.header.stamp = ros::Time::now();
      m.sequence = seq;
      m.simulation_time = 0.01 * double(seq);
      modelPub_.publish(m);
      rate.sleep();
    }
  }

  void onWrench(const geometry_msgs::WrenchStamped::ConstPtr& w) {
    const double now = monotonicSeconds();
    std::lock_guard<std::mutex> l(m_);
    if (!measuring_) return;
    arrivals_.arrived(now);
    const double expected = stepped_ ? -kStiffness * kStep : 0.0;
    if (waiting_ && std::abs(w->wrench.force.x - expected) < 0.01 * kStiffness * kStep) {
      latencies_.push_back(now - sentAt_);
      waiting_ = false;
    }
  }

  ros::Publisher posePub_, modelPub_;
  BridgeStatusLog status_;
  std::mutex m_;
  bool measuring_ = false, stepped_ = false, waiting_ = false;
  double sentAt_ = 0.0;
  std::size_t missed_ = 0;
  std::vector<double> latencies_;
  ArrivalLog arrivals_;
  ros::Subscriber wrenchSub_, statusSub_;  // last: destroyed first
};

// ---- graph: a running training session seen from outside -----------------------------------

class GraphProbe {
 public:
  explicit GraphProbe(ros::NodeHandle& nh) {
    tissueSub_ = nh.subscribe("tissue/status", 1000, &GraphProbe::onTissue, this);
    contactSub_ = nh.subscribe("tissue/contact", 1000, &GraphProbe::onContact, this,
                               ros::TransportHints().tcpNoDelay());
    wrenchSub_ = nh.subscribe("device/servo_cf", 1000, &GraphProbe::onWrench, this,
                              ros::TransportHints().tcpNoDelay());
    statusSub_ = nh.subscribe("haptic_bridge/status", 10, &BridgeStatusLog::onStatus, &bridge_);
  }

  int run(const Options& o) {
    started_ = monotonicSeconds();
    const double deadline = started_ + 60.0;
    while (ros::ok() && monotonicSeconds() < deadline) {  // until the simulation steps
      {
        std::lock_guard<std::mutex> l(m_);
        if (tissueCount_ > 10) break;
      }
      ros::WallDuration(0.05).sleep();
    }
    ros::WallDuration(1.0).sleep();  // past start-up
    {
      std::lock_guard<std::mutex> l(m_);
      measuring_ = true;
    }
    bridge_.restart();
    const double t0 = monotonicSeconds();
    ros::WallDuration(o.duration).sleep();
    const double elapsed = monotonicSeconds() - t0;
    std::lock_guard<std::mutex> l(m_);
    measuring_ = false;
    Result r;
    r.add("mode", "graph");
    r.add("label", o.label);
    r.add("duration_s", elapsed, "%.2f");
    r.add("steps", double(stepWall_.size()), "%.0f");
    r.add("step_rate_hz", double(stepWall_.size()) / elapsed, "%.1f");
    r.add("step_wall_p50_ms", 1e3 * percentile(stepWall_, 0.5), "%.3f");
    r.add("step_wall_p99_ms", 1e3 * percentile(stepWall_, 0.99), "%.3f");
    r.add("step_wall_max_ms", 1e3 * maxOf(stepWall_), "%.3f");
    r.add("real_time_factor_p50", percentile(rtf_, 0.5), "%.3f");
    r.add("step_time_p50_ms", 1e3 * percentile(stepTime_, 0.5), "%.3f");
    r.add("step_time_max_ms", 1e3 * maxOf(stepTime_), "%.3f");
    r.add("steps_behind", double(behind_), "%.0f");
    r.add("time_behind_s", lastBehind_ - firstBehind_, "%.3f");
    r.add("tool_lag_max_mm", 1e3 * maxToolLag_, "%.2f");
    r.add("first_status_s", firstStatus_ - started_, "%.2f");
    r.add("unstable_steps", double(unstable_), "%.0f");
    r.add("peak_contact_force_n", peakForce_, "%.3f");
    r.add("peak_displacement_mm", 1e3 * peakDisplacement_, "%.2f");
    r.add("contact_depth_max_mm", 1e3 * peakDepth_, "%.2f");
    r.add("contact_share", stepWall_.empty() ? 0.0 : double(inContact_) / stepWall_.size(), "%.3f");
    contacts_.addTo(r, "contact");
    wrenches_.addTo(r, "wrench");
    bridge_.addTo(r);
    r.emit(o.csv);
    return stepWall_.empty() ? 1 : 0;
  }

 private:
  void onTissue(const tissue_trainer::TissueStatus::ConstPtr& s) {
    std::lock_guard<std::mutex> l(m_);
    if (++tissueCount_ == 1) firstStatus_ = monotonicSeconds();
    if (!measuring_) return;
    if (stepWall_.empty()) firstBehind_ = s->total_time_behind - s->time_behind;
    lastBehind_ = s->total_time_behind;
    stepTime_.push_back(s->step_time);
    maxToolLag_ = std::max(maxToolLag_, s->tool_lag);
    stepWall_.push_back(s->step_wall_time);
    rtf_.push_back(s->real_time_factor);
    if (s->behind_schedule) ++behind_;
    if (!s->stable) ++unstable_;
    peakForce_ = std::max(peakForce_, s->contact_force);
    peakDepth_ = std::max(peakDepth_, s->contact_depth);
    if (s->contact_force > 0.0) ++inContact_;
    peakDisplacement_ = std::max(peakDisplacement_, s->max_displacement);
  }
  void onContact(const tissue_trainer::ContactModel::ConstPtr&) {
    const double now = monotonicSeconds();
    std::lock_guard<std::mutex> l(m_);
    if (measuring_) contacts_.arrived(now);
  }
  void onWrench(const geometry_msgs::WrenchStamped::ConstPtr&) {
    const double now = monotonicSeconds();
    std::lock_guard<std::mutex> l(m_);
    if (measuring_) wrenches_.arrived(now);
  }

  BridgeStatusLog bridge_;
  std::mutex m_;
  bool measuring_ = false;
  std::size_t tissueCount_ = 0, behind_ = 0, unstable_ = 0, inContact_ = 0;
  double peakForce_ = 0.0, peakDisplacement_ = 0.0;  // the press's force, the tissue's displacement
  double peakDepth_ = 0.0;                           // the tool's deepest point in the tissue
  double started_ = 0.0, firstStatus_ = 0.0, firstBehind_ = 0.0, lastBehind_ = 0.0, maxToolLag_ = 0.0;
  std::vector<double> stepWall_, stepTime_, rtf_;
  ArrivalLog contacts_, wrenches_;
  ros::Subscriber tissueSub_, contactSub_, wrenchSub_, statusSub_;  // last: destroyed first
};

// ---- surface transport between two processes -------------------------------------------------

int surfaceSource(ros::NodeHandle& nh, const Options& o) {
  if (o.vertices < 3) {
    std::fprintf(stderr, "bench_training_graph: surface_source needs --vertices N (N >= 3)\n");
    return 2;
  }
  ros::Publisher pub = nh.advertise<tissue_trainer::TissueSurface>("bench/surface", 10);
  tissue_trainer::TissueSurface msg;
  msg.header.frame_id = "world";
  msg.positions.resize(3 * std::size_t(o.vertices));
  for (std::size_t i = 0; i < msg.positions.size(); ++i) msg.positions[i] = 0.001f * float(i % 97);
  const std::size_t triangles = 2 * std::size_t(o.vertices);  // a closed surface: F ~ 2V
  ros::WallRate rate(o.rate);
  for (std::uint64_t seq = 1; ros::ok(); ++seq) {
    msg.sequence = seq;
    msg.triangles_changed = seq % std::uint64_t(o.trianglesEvery) == 1;
    msg.triangles.assign(msg.triangles_changed ? 3 * triangles : 0, 0u);
    msg.header.stamp = ros::Time::now();
    pub.publish(msg);
    rate.sleep();
  }
  return 0;
}

int surfaceSink(ros::NodeHandle& nh, const Options& o) {
  std::mutex m;
  std::vector<double> latency, latencyWithTriangles;
  std::size_t bytes = 0, bytesWithTriangles = 0, vertices = 0;
  bool measuring = false;
  ros::Subscriber sub = nh.subscribe<tissue_trainer::TissueSurface>(
      "bench/surface", 100,
      [&](const tissue_trainer::TissueSurface::ConstPtr& s) {
        const double dt = (ros::Time::now() - s->header.stamp).toSec();
        std::lock_guard<std::mutex> l(m);
        if (!measuring) return;
        const std::size_t size = ros::serialization::serializationLength(*s);
        vertices = s->positions.size() / 3;
        if (s->triangles.empty()) {
          latency.push_back(dt);
          bytes = size;
        } else {
          latencyWithTriangles.push_back(dt);
          bytesWithTriangles = size;
        }
      },
      ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  ros::WallDuration(2.0).sleep();  // connection up
  {
    std::lock_guard<std::mutex> l(m);
    measuring = true;
  }
  ros::WallDuration(o.duration).sleep();
  std::lock_guard<std::mutex> l(m);
  measuring = false;
  Result r;
  r.add("mode", "surface");
  r.add("label", o.label);
  r.add("vertices", double(vertices), "%.0f");
  r.add("messages", double(latency.size() + latencyWithTriangles.size()), "%.0f");
  r.add("bytes", double(bytes), "%.0f");
  r.add("latency_p50_us", 1e6 * percentile(latency, 0.5), "%.1f");
  r.add("latency_p99_us", 1e6 * percentile(latency, 0.99), "%.1f");
  r.add("latency_max_us", 1e6 * maxOf(latency), "%.1f");
  r.add("bytes_with_triangles", double(bytesWithTriangles), "%.0f");
  r.add("latency_with_triangles_p50_us", 1e6 * percentile(latencyWithTriangles, 0.5), "%.1f");
  r.emit(o.csv);
  return latency.empty() ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "bench_training_graph", ros::init_options::AnonymousName);
  const Options o = parseOptions(argc, argv);
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  int rc = 2;
  // The spinner's threads are joined before a probe goes out of scope: no callback may
  // reach a destroyed probe.
  if (o.mode == "haptic") {
    HapticProbe probe(nh);
    rc = probe.run(o);
    spinner.stop();
  } else if (o.mode == "graph") {
    GraphProbe probe(nh);
    rc = probe.run(o);
    spinner.stop();
  } else if (o.mode == "surface_source") {
    rc = surfaceSource(nh, o);
  } else if (o.mode == "surface_sink") {
    rc = surfaceSink(nh, o);
  } else {
    std::fprintf(stderr, "bench_training_graph: unknown mode '%s'\n", o.mode.c_str());
  }
  ros::shutdown();
  return rc;
}
