// network_probe: records what the device side of the training graph sees, for the two-host
// test (test/integration/two_hosts.sh) and the degraded-network benchmark (scripts/bench_network):
//   network_probe --duration S --out DIR [--contact TOPIC]... [--topics T1,T2,...]
//                 [--mark-force F --mark-file FILE]
// Writes into DIR (times are wall-clock seconds, comparable between processes and network
// namespaces of one machine):
//   servo.csv    every /device/servo_cf wrench: receive time, stamp, force
//   contact.csv  every message on each --contact topic: topic, receive time, stamp, sequence,
//                in_contact, |f0|
//   status.csv   every /haptic_bridge/status
//   enable.csv   every /device/enable
//   topics.csv   for each --topics topic (any type): messages received, first receive time
// With --mark-file, FILE is written (the time, one line) when |force| first exceeds F.
#include <geometry_msgs/WrenchStamped.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>
#include <topic_tools/shape_shifter.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/command_line.h"
#include "tissue_trainer/ContactModel.h"
#include "tissue_trainer/HapticStatus.h"

namespace {

struct Options {
  double duration = 0.0;
  std::string out;
  std::vector<std::string> contactTopics;
  std::vector<std::string> topics;
  double markForce = 0.0;
  std::string markFile;
};

Options parse(int argc, char** argv) {
  tt::tools::CommandLine args(argc, argv,
                              "network_probe --duration S --out DIR [--contact TOPIC]... "
                              "[--topics T1,T2,...] [--mark-force F --mark-file FILE]");
  Options o;
  o.duration = args.positiveNumber("--duration", 0.0);
  o.out = args.text("--out", "");
  o.contactTopics = args.texts("--contact");
  o.topics = args.list("--topics", {});
  o.markForce = args.positiveNumber("--mark-force", 0.0);
  o.markFile = args.text("--mark-file", "");
  args.finish();
  if (o.duration <= 0.0) args.fail("--duration is required");
  if (o.out.empty()) args.fail("--out is required");
  if (o.markFile.empty() != (o.markForce <= 0.0))
    args.fail("--mark-force and --mark-file go together");
  return o;
}

double now() { return ros::WallTime::now().toSec(); }

struct TopicCount {
  std::uint64_t count = 0;
  double first = 0.0;
};

class Probe {
 public:
  Probe(ros::NodeHandle& nh, const Options& o) : options_(o) {
    const ros::TransportHints hints = ros::TransportHints().tcpNoDelay();
    subs_.push_back(nh.subscribe("/device/servo_cf", 5000, &Probe::onServo, this, hints));
    subs_.push_back(nh.subscribe("/haptic_bridge/status", 100, &Probe::onStatus, this, hints));
    subs_.push_back(nh.subscribe("/device/enable", 100, &Probe::onEnable, this, hints));
    for (const std::string& topic : o.contactTopics)
      subs_.push_back(nh.subscribe<tissue_trainer::ContactModel>(
          topic, 1000, [this, topic](const tissue_trainer::ContactModel::ConstPtr& m) { onContact(topic, *m); },
          ros::VoidConstPtr(), hints));
    for (const std::string& topic : o.topics) {
      counts_[topic];
      subs_.push_back(nh.subscribe<topic_tools::ShapeShifter>(
          topic, 100, [this, topic](const topic_tools::ShapeShifter::ConstPtr&) { onAny(topic); }));
    }
    servo_.reserve(static_cast<std::size_t>(o.duration * 1100));
  }

  void write() const {
    const std::string& d = options_.out;
    writeFile(d + "/servo.csv", "recv,stamp,seq,fx,fy,fz\n", servo_);
    writeFile(d + "/contact.csv", "topic,recv,stamp,sequence,in_contact,f0\n", contact_);
    writeFile(d + "/status.csv",
              "recv,rate,period_p99,model_age,has_model,watchdog_tripped,watchdog_trips,gain,ticks,"
              "models_accepted,models_stale,force_clamped,rate_limited,non_finite_forces,device_fresh,"
              "enabled,fx,fy,fz\n",
              status_);
    writeFile(d + "/enable.csv", "recv,enabled\n", enable_);
    std::vector<std::string> rows;
    for (const auto& [topic, c] : counts_)
      rows.push_back(topic + "," + std::to_string(c.count) + "," + number(c.first) + "\n");
    writeFile(d + "/topics.csv", "topic,count,first_recv\n", rows);
  }

 private:
  static std::string number(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
  }
  static std::string join(std::initializer_list<double> values) {
    std::string s;
    for (double v : values) s += (s.empty() ? "" : ",") + number(v);
    return s + "\n";
  }
  static void writeFile(const std::string& path, const std::string& header,
                        const std::vector<std::string>& rows) {
    std::ofstream f(path);
    f << header;
    for (const auto& r : rows) f << r;
    if (!f) std::fprintf(stderr, "network_probe: cannot write %s\n", path.c_str());
  }

  void onServo(const geometry_msgs::WrenchStamped& m) {
    const double t = now();
    const auto& f = m.wrench.force;
    servo_.push_back(join({t, m.header.stamp.toSec(), double(m.header.seq), f.x, f.y, f.z}));
    if (!marked_ && !options_.markFile.empty() && std::hypot(f.x, f.y, f.z) > options_.markForce) {
      marked_ = true;
      std::ofstream(options_.markFile) << number(t) << "\n";
    }
  }
  void onContact(const std::string& topic, const tissue_trainer::ContactModel& m) {
    contact_.push_back(topic + "," + join({now(), m.header.stamp.toSec(), double(m.sequence),
                                           m.in_contact ? 1.0 : 0.0,
                                           std::hypot(m.force.x, m.force.y, m.force.z)}));
  }
  void onStatus(const tissue_trainer::HapticStatus& m) {
    status_.push_back(join({now(), m.rate, m.period_p99, m.model_age, double(m.has_model),
                            double(m.watchdog_tripped), double(m.watchdog_trips), m.gain,
                            double(m.ticks), double(m.models_accepted), double(m.models_stale),
                            double(m.force_clamped), double(m.rate_limited),
                            double(m.non_finite_forces), double(m.device_fresh),
                            double(m.enabled), m.force.x, m.force.y, m.force.z}));
  }
  void onEnable(const std_msgs::Bool& m) { enable_.push_back(join({now(), m.data ? 1.0 : 0.0})); }
  void onAny(const std::string& topic) {
    TopicCount& c = counts_[topic];
    if (c.count++ == 0) c.first = now();
  }

  Options options_;
  std::vector<ros::Subscriber> subs_;
  std::vector<std::string> servo_, contact_, status_, enable_;
  std::map<std::string, TopicCount> counts_;
  bool marked_ = false;
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "network_probe", ros::init_options::AnonymousName);
  const Options options = parse(argc, argv);
  ros::NodeHandle nh;
  Probe probe(nh, options);
  ros::AsyncSpinner spinner(1);  // one thread: the callbacks never run at the same time
  spinner.start();
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(options.duration);
  while (ros::ok() && ros::WallTime::now() < end) ros::WallDuration(0.01).sleep();
  spinner.stop();
  probe.write();
  std::printf("network_probe: recorded %.1f s into %s\n", options.duration, options.out.c_str());
  return 0;
}
