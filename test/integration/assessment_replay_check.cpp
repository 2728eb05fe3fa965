// Online and offline assessment agree: publishes a scripted 4 s session (tip at 1 kHz with
// three reaches, contact and tissue status at 100 Hz with one force excursion above the
// threshold, one non-finite tip sample), waits until the assessment node has counted every
// message, calls its ~write service, shuts it down (it writes its report again), stops rosbag
// record through its XML-RPC shutdown (which closes the bag), runs assess_bag on the bag and
// compares the two reports.
#include <gtest/gtest.h>
#include <ros/master.h>
#include <ros/network.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <std_msgs/String.h>
#include <std_srvs/Trigger.h>
#include <sys/wait.h>
#include <xmlrpcpp/XmlRpcClient.h>
#include <yaml-cpp/yaml.h>

#include <geometry_msgs/PoseStamped.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <fstream>
#include <limits>
#include <mutex>
#include <string>

#include "tissue_trainer/ContactModel.h"
#include "tissue_trainer/TissueStatus.h"

namespace fs = std::filesystem;

namespace {

constexpr int kTipMessages = 4001;      // 0 .. 4 s at 1 kHz, one of them non-finite
constexpr int kPhysicsMessages = 401;   // 0 .. 4 s at 100 Hz

double minimumJerk(double s) {
  s = std::min(1.0, std::max(0.0, s));
  return 10 * std::pow(s, 3) - 15 * std::pow(s, 4) + 6 * std::pow(s, 5);
}

// Three 3 cm reaches along x of 0.6 s each, starting at 0.3, 1.5 and 2.7 s.
double tipX(double t) {
  double x = 0.0;
  for (int k = 0; k < 3; ++k) x += 0.03 * minimumJerk((t - 0.3 - 1.2 * k) / 0.6);
  return x;
}

// In contact over [1, 3) s with |f| = 2 sin(pi (t - 1) / 2) N: above 1.5 N once.
double contactForce(double t) { return t >= 1.0 && t < 3.0 ? 2.0 * std::sin(M_PI * (t - 1.0) / 2.0) : 0.0; }

bool waitFor(const std::function<bool()>& done, double seconds) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < end) {
    ros::spinOnce();
    if (done()) return true;
    ros::WallDuration(0.01).sleep();
  }
  return done();
}

std::size_t received(const YAML::Node& samples, const char* stream) {
  const YAML::Node s = samples[stream];
  return s["accepted"].as<std::size_t>() + s["non_finite"].as<std::size_t>() +
         s["out_of_order"].as<std::size_t>();
}

// What `rosnode kill` does: the node's XML-RPC shutdown; roscpp then returns from spin, and
// rosbag record writes its queue and closes (renames) the bag.
bool shutdownNode(const std::string& name) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = name;
  if (!ros::master::execute("lookupNode", args, result, payload, true)) return false;
  std::string host;
  std::uint32_t port = 0;
  if (!ros::network::splitURI(static_cast<std::string>(payload), host, port)) return false;
  XmlRpc::XmlRpcClient client(host.c_str(), static_cast<int>(port), "/");
  XmlRpc::XmlRpcValue call, reply;
  call[0] = ros::this_node::getName();
  call[1] = std::string("assessment_replay: session recorded");
  return client.execute("shutdown", call, reply);
}

std::string assessBag() { return (fs::read_symlink("/proc/self/exe").parent_path() / "assess_bag").string(); }

int run(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(AssessmentReplay, OfflineReportEqualsOnline) {
  ros::NodeHandle nh, pnh("~");
  std::string session, config;
  bool keep = false;
  ASSERT_TRUE(pnh.getParam("session", session));
  ASSERT_TRUE(pnh.getParam("config", config));
  pnh.getParam("keep", keep);
  const std::string bagPath = session + ".bag";

  ros::Publisher tipPub = nh.advertise<geometry_msgs::PoseStamped>("/instrument/measured_cp", 4000);
  ros::Publisher contactPub = nh.advertise<tissue_trainer::ContactModel>("/tissue/contact", 500);
  ros::Publisher statusPub = nh.advertise<tissue_trainer::TissueStatus>("/tissue/status", 500);
  std::mutex mutex;
  YAML::Node summary;
  ros::Subscriber summarySub = nh.subscribe<std_msgs::String>(
      "/assessment/summary", 10, [&](const std_msgs::String::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex);
        summary = YAML::Load(m->data);
      });

  // The assessment node and rosbag record must both hear the session from its first message.
  ASSERT_TRUE(waitFor([&] {
    return tipPub.getNumSubscribers() >= 2 && contactPub.getNumSubscribers() >= 2 &&
           statusPub.getNumSubscribers() >= 2;
  }, 60.0)) << "assessment node or rosbag record did not subscribe";

  // The scripted session: stamps are exact multiples of 1 ms after a start time.
  const ros::Time start = ros::Time::now();
  ros::WallRate rate(1000.0);
  for (int i = 0; i < kTipMessages; ++i) {
    const double t = i / 1000.0;
    geometry_msgs::PoseStamped tip;
    tip.header.stamp = start + ros::Duration(t);
    tip.header.frame_id = "world";
    tip.pose.position.x = i == 2222 ? std::numeric_limits<double>::quiet_NaN() : -0.05 + tipX(t);
    tip.pose.position.y = 0.1;
    tip.pose.position.z = 0.05;
    tip.pose.orientation.w = 1.0;
    tipPub.publish(tip);
    if (i % 10 == 0) {
      const double f = contactForce(t);
      tissue_trainer::ContactModel contact;
      contact.header = tip.header;
      contact.sequence = static_cast<std::uint64_t>(i / 10);
      contact.in_contact = f > 0.0;
      contact.tool_position = tip.pose.position;
      contact.force.y = f;
      contact.simulation_time = t;
      contactPub.publish(contact);
      tissue_trainer::TissueStatus status;
      status.header = tip.header;
      status.simulation_time = t;
      status.max_strain = 0.1 * f;
      status.damage_strain = 0.15;
      status.strained_volume = 1e-7 * std::max(0.0, f - 1.5);
      status.stable = true;
      statusPub.publish(status);
    }
    rate.sleep();
  }

  // The node has counted every message (its summary comes once a second).
  ASSERT_TRUE(waitFor([&] {
    std::lock_guard<std::mutex> lock(mutex);
    return summary && received(summary["samples"], "tip") == kTipMessages &&
           received(summary["samples"], "force") == kPhysicsMessages &&
           received(summary["samples"], "status") == kPhysicsMessages;
  }, 30.0)) << "the assessment node did not receive every message";
  std_srvs::Trigger write;
  ASSERT_TRUE(ros::service::waitForService("/assessment/write", 10000));
  ASSERT_TRUE(ros::service::call("/assessment/write", write));
  ASSERT_TRUE(write.response.success) << write.response.message;
  EXPECT_EQ(write.response.message, session + "/online/assessment.yaml");
  EXPECT_TRUE(fs::exists(session + "/online/assessment.md"));

  // The report the node writes when it is shut down is the one compared below.
  fs::remove_all(session + "/online");
  ASSERT_TRUE(shutdownNode("/assessment"));
  ASSERT_TRUE(waitFor([&] { return fs::exists(session + "/online/assessment.yaml"); }, 30.0))
      << "the assessment node wrote no report on shutdown";

  // Stop the recorder once it has had time to take the last messages off its socket, and
  // wait until it has closed the bag (rosbag renames NAME.bag.active to NAME.bag).
  ros::WallDuration(2.0).sleep();
  ASSERT_TRUE(shutdownNode("/record"));
  ASSERT_TRUE(waitFor([&] { return fs::exists(bagPath) && !fs::exists(bagPath + ".active"); }, 30.0))
      << bagPath << " was not closed";

  const std::string offlineDir = session + "/offline";
  ASSERT_EQ(run(assessBag() + " " + bagPath + " --out " + offlineDir + " --config " + config +
                " > " + session + "/assess_bag.out"), 0)
      << readFile(session + "/assess_bag.out");
  const YAML::Node online = YAML::LoadFile(session + "/online/assessment.yaml");
  const YAML::Node offline = YAML::LoadFile(offlineDir + "/assessment.yaml");

  for (const char* stream : {"tip", "force", "status"})
    for (const char* count : {"accepted", "non_finite", "out_of_order"})
      EXPECT_EQ(online["samples"][stream][count].as<std::size_t>(),
                offline["samples"][stream][count].as<std::size_t>()) << stream << " " << count;
  EXPECT_EQ(online["samples"]["tip"]["non_finite"].as<int>(), 1);
  ASSERT_EQ(online["metrics"].size(), offline["metrics"].size());
  for (const auto& item : online["metrics"]) {
    const std::string key = item.first.as<std::string>();
    const double a = item.second.as<double>(), b = offline["metrics"][key].as<double>();
    EXPECT_LE(std::abs(a - b), 1e-9 * std::max(std::abs(a), std::abs(b))) << key << ": online " << a
                                                                           << ", offline " << b;
  }
  EXPECT_EQ(online["no_data"].size(), 0u);
  EXPECT_EQ(offline["no_data"].size(), 0u);

  // The script's own numbers.
  const YAML::Node m = offline["metrics"];
  EXPECT_NEAR(m["task_time"].as<double>(), 4.0, 1e-6);
  EXPECT_NEAR(m["path_length"].as<double>(), 0.09, 1e-6);
  EXPECT_EQ(m["movements"].as<int>(), 3);
  EXPECT_EQ(m["excessive_force_events"].as<int>(), 1);
  EXPECT_NEAR(m["contact_time"].as<double>(), 1.99, 1e-6);  // first sample at 1.01 s (f(1) = 0)
  EXPECT_NEAR(m["peak_force"].as<double>(), 2.0, 1e-9);
  EXPECT_NEAR(m["force_integral"].as<double>(), 8.0 / M_PI, 0.01);
  EXPECT_NEAR(m["peak_strain"].as<double>(), 0.2, 1e-9);
  std::printf("%s", readFile(session + "/assess_bag.out").c_str());

  // The score against the package's bands, the four plots embedded in the page, and a
  // learning curve of two sessions (the same bag twice).
  EXPECT_TRUE(offline["score"]["overall"].IsDefined());
  EXPECT_TRUE(online["score"]["overall"].IsDefined());
  const std::string page = readFile(offlineDir + "/assessment.md");
  for (const char* png : {"tip_path.png", "speed.png", "force.png", "strain.png"}) {
    EXPECT_GT(fs::exists(offlineDir + "/" + png) ? fs::file_size(offlineDir + "/" + png) : 0u, 1000u) << png;
    EXPECT_NE(page.find(std::string("](") + png + ")"), std::string::npos) << png;
  }
  const std::string curve = session + "/curve";
  ASSERT_EQ(run(assessBag() + " " + bagPath + " " + bagPath + " --out " + curve + " > " + session +
                "/curve.out 2>&1"), 0)
      << readFile(session + "/curve.out");
  const std::string stem = fs::path(bagPath).stem().string();
  EXPECT_TRUE(fs::exists(curve + "/01_" + stem + "/assessment.yaml"));
  EXPECT_TRUE(fs::exists(curve + "/02_" + stem + "/speed.png"));
  EXPECT_TRUE(fs::exists(curve + "/learning_curve.png"));
  const std::string table = readFile(curve + "/learning_curve.md");
  EXPECT_NE(table.find("| 2 | ["), std::string::npos) << table;

  // --scene: the scene's rest surface beside the report (a triangle a row, 9 coordinates),
  // drawn under the tip path; a scene that does not load: one line and exit 2.
  const std::string scene = (fs::path(config).parent_path() / "scenes" / "liver_palpation.yaml").string();
  const std::string drawn = session + "/drawn";
  ASSERT_EQ(run(assessBag() + " " + bagPath + " --scene " + scene + " --out " + drawn + " > " + session +
                "/drawn.out 2>&1"), 0)
      << readFile(session + "/drawn.out");
  const std::string surface = readFile(drawn + "/tissue_surface.csv");
  EXPECT_EQ(surface.rfind("ax,ay,az,bx,by,bz,cx,cy,cz\n", 0), 0u) << surface.substr(0, 80);
  EXPECT_GT(std::count(surface.begin(), surface.end(), '\n'), 100) << "too few triangles";
  EXPECT_EQ(surface.find("nan"), std::string::npos);
  EXPECT_GT(fs::file_size(drawn + "/tip_path.png"), 1000u);
  EXPECT_EQ(run(assessBag() + " " + bagPath + " --scene " + session + "/none.yaml --out " + drawn + " 2>" +
                session + "/err"), 2);
  const std::string sceneError = readFile(session + "/err");
  EXPECT_EQ(sceneError.rfind("assess_bag: --scene: ", 0), 0u) << sceneError;
  EXPECT_EQ(std::count(sceneError.begin(), sceneError.end(), '\n'), 1) << sceneError;

  // assess_bag: one error line and exit 2 for a missing bag and for a bag without the topics.
  EXPECT_EQ(run(assessBag() + " " + session + "/none.bag --out " + offlineDir + " 2>" + session + "/err"), 2);
  EXPECT_NE(readFile(session + "/err").find("cannot read the bag"), std::string::npos) << readFile(session + "/err");
  {
    rosbag::Bag partial(session + "/partial.bag", rosbag::bagmode::Write);
    geometry_msgs::PoseStamped tip;
    tip.header.stamp = start;
    partial.write("/instrument/measured_cp", start, tip);
  }
  EXPECT_EQ(run(assessBag() + " " + session + "/partial.bag 2>" + session + "/err"), 2);
  EXPECT_EQ(readFile(session + "/err"),
            "assess_bag: " + session + "/partial.bag: missing topics: /tissue/contact, /tissue/status\n");

  if (!keep && !HasFailure()) {
    fs::remove_all(session);
    fs::remove(bagPath);
  }
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "assessment_replay_check");
  return RUN_ALL_TESTS();
}
