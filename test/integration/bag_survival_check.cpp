// Recordings that survive (bag_survival.test): publishes 3 s of a session on the three
// assessment topics, SIGKILLs rosbag record, and checks that assess_bag assesses the
// .bag.active it left (saying on stdout that it reindexed a copy) and that replay_bag plays it; then that a
// truncated and a garbage bag give exit code 2 and one error line, never a crash.
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <signal.h>
#include <sys/wait.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>

#include "node_api.h"
#include "tissue_trainer/ContactModel.h"
#include "tissue_trainer/TissueStatus.h"

namespace fs = std::filesystem;

namespace {

bool waitFor(const std::function<bool()>& done, double seconds) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < end) {
    ros::spinOnce();
    if (done()) return true;
    ros::WallDuration(0.01).sleep();
  }
  return done();
}


std::string besideMe(const std::string& exe) {
  return (fs::read_symlink("/proc/self/exe").parent_path() / exe).string();
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

struct Outcome {
  int exitCode;  // -1: ended by a signal
  std::string out, err;
};

Outcome run(const std::string& command, const std::string& stem) {
  const int status = std::system((command + " > " + stem + ".out 2> " + stem + ".err").c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, readFile(stem + ".out"), readFile(stem + ".err")};
}

std::size_t lines(const std::string& text) { return std::count(text.begin(), text.end(), '\n'); }

void publishSession(double seconds) {
  ros::NodeHandle nh;
  ros::Publisher tipPub = nh.advertise<geometry_msgs::PoseStamped>("/instrument/measured_cp", 100);
  ros::Publisher contactPub = nh.advertise<tissue_trainer::ContactModel>("/tissue/contact", 100);
  ros::Publisher statusPub = nh.advertise<tissue_trainer::TissueStatus>("/tissue/status", 100);
  ASSERT_TRUE(waitFor([&] {
    return tipPub.getNumSubscribers() >= 1 && contactPub.getNumSubscribers() >= 1 &&
           statusPub.getNumSubscribers() >= 1;
  }, 60.0)) << "rosbag record did not subscribe";
  ros::WallRate rate(100.0);
  for (int i = 0; i < seconds * 100; ++i) {
    const ros::Time stamp = ros::Time::now();
    const double t = i / 100.0;
    geometry_msgs::PoseStamped tip;
    tip.header.stamp = stamp;
    tip.pose.position.x = 0.01 * t;
    tip.pose.orientation.w = 1.0;
    tipPub.publish(tip);
    tissue_trainer::ContactModel contact;
    contact.header.stamp = stamp;
    contact.sequence = i + 1;
    contact.in_contact = t > 1.0;
    contact.force.z = contact.in_contact ? 0.5 : 0.0;
    contactPub.publish(contact);
    tissue_trainer::TissueStatus status;
    status.header.stamp = stamp;
    status.simulation_time = t;
    status.stable = true;
    statusPub.publish(status);
    ros::spinOnce();
    rate.sleep();
  }
  ros::WallDuration(0.5).sleep();  // let rosbag record write what it received
}

TEST(BagSurvival, AKilledRecordingIsAssessedAndBadBagsGiveOneLine) {
  ros::NodeHandle pnh("~");
  std::string session, replayBag;
  ASSERT_TRUE(pnh.getParam("session", session));
  ASSERT_TRUE(pnh.getParam("replay_bag", replayBag));
  fs::create_directories(session);

  publishSession(3.0);
  const int pid = tt_test::nodePid("/record");
  ASSERT_GT(pid, 0) << "no pid for /record";
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  const std::string active = session + ".bag.active";
  ASSERT_TRUE(waitFor([&] { return fs::exists(active); }, 5.0)) << "no " << active;
  ros::WallDuration(0.3).sleep();
  EXPECT_FALSE(fs::exists(session + ".bag"));
  const auto activeSize = fs::file_size(active);

  // assess_bag on the unindexed bag: one line saying so, then the report of what it holds.
  const Outcome a = run(besideMe("assess_bag") + " " + active + " --out " + session + "/report",
                    session + "/assess_active");
  std::printf("assess_bag on the .bag.active (%ju bytes): exit %d\n%s%s", static_cast<std::uintmax_t>(activeSize),
              a.exitCode, a.err.c_str(), a.out.c_str());
  ASSERT_EQ(a.exitCode, 0) << a.err;
  EXPECT_EQ(a.err, "");
  EXPECT_NE(a.out.find("unindexed"), std::string::npos) << a.out;
  const YAML::Node report = YAML::LoadFile(session + "/report/assessment.yaml");
  EXPECT_GT(report["samples"]["tip"]["accepted"].as<int>(), 200);
  EXPECT_GT(report["samples"]["force"]["accepted"].as<int>(), 200);
  EXPECT_GT(report["metrics"]["contact_time"].as<double>(), 1.0);
  EXPECT_EQ(fs::file_size(active), activeSize) << "the original must not be touched";

  // replay_bag plays it too (what replay.launch runs), saying so.
  const Outcome r = run(replayBag + " " + active + " --quiet --topics /tissue/status", session + "/replay_active");
  EXPECT_EQ(r.exitCode, 0) << r.err << r.out;
  EXPECT_NE((r.err + r.out).find("unindexed"), std::string::npos) << r.err << r.out;

  // A good bag, truncated: one line, exit 2.
  const std::string good = session + "/good.bag";
  {
    rosbag::Bag bag(good, rosbag::bagmode::Write);
    for (int i = 0; i < 2000; ++i) {
      tissue_trainer::TissueStatus s;
      s.header.stamp = ros::Time(100.0 + i * 0.01);
      s.failure = std::string(100, 'x');
      bag.write("/tissue/status", s.header.stamp, s);
    }
  }
  const std::string truncated = session + "/truncated.bag";
  {
    const std::string bytes = readFile(good);
    std::ofstream(truncated, std::ios::binary).write(bytes.data(), static_cast<long>(bytes.size() / 2));
  }
  const std::string garbage = session + "/garbage.bag";
  {
    std::mt19937 rng(3);
    std::string bytes = "#ROSBAG V2.0\n";
    for (int i = 0; i < 20000; ++i) bytes += static_cast<char>(rng());
    std::ofstream(garbage, std::ios::binary).write(bytes.data(), static_cast<long>(bytes.size()));
  }
  const std::string text = session + "/text.bag";
  std::ofstream(text) << "not a bag\n";
  for (const std::string& bad : {truncated, garbage, text, session + "/missing.bag"}) {
    const Outcome b = run(besideMe("assess_bag") + " " + bad + " --out " + session + "/bad", session + "/bad");
    std::printf("assess_bag %s: exit %d: %s", bad.c_str(), b.exitCode, b.err.c_str());
    EXPECT_EQ(b.exitCode, 2) << bad;
    EXPECT_EQ(lines(b.err), 1u) << bad << ": " << b.err;
    EXPECT_EQ(b.err.rfind("assess_bag: " + bad, 0), 0u) << b.err;
    const Outcome p = run(replayBag + " " + bad + " --quiet", session + "/bad_replay");
    std::printf("replay_bag %s: exit %d: %s", bad.c_str(), p.exitCode, p.err.c_str());
    EXPECT_EQ(p.exitCode, 2) << bad;
    EXPECT_EQ(lines(p.err), 1u) << bad << ": " << p.err;
  }
  fs::remove_all(session);
  fs::remove(active);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "bag_survival_check");
  return RUN_ALL_TESTS();
}
