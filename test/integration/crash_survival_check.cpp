// Crash survival of the training graph (crash_survival.test): with the tool pressed into the
// liver, the simulation is killed with SIGKILL. The haptic bridge's wrench must stay finite,
// bounded and at 1 kHz and fade to zero; the simulation must respawn within ~2 s and continue
// from its snapshot (its time near where it died); the force must come back smoothly; the
// bag must keep growing and the assessment report must mark the restart.
#include <geometry_msgs/WrenchStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <tissue_trainer/ContactModel.h>
#include <tissue_trainer/TissueStatus.h>

#include <signal.h>
#include <sys/types.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "node_api.h"

namespace {

double now() { return ros::WallTime::now().toSec(); }

struct Wrench {
  double arrival, stamp, norm;
  bool finite;
};
struct Model {
  double arrival, stamp;  // wall clock at arrival; the simulation's stamp (same host)
  bool inContact;
  std::uint64_t sequence;
};
struct Status {
  double arrival, simulationTime, resumedAt;
  std::uint32_t restarts;
};

struct Watch {
  std::mutex mutex;
  std::vector<Wrench> wrenches;
  std::vector<Model> models;
  std::vector<Status> statuses;
};


double param(const std::string& name) {
  double v = std::nan("");
  ros::param::get("~" + name, v);
  return v;
}

std::uintmax_t fileSize(const std::string& path) {
  std::error_code ec;
  const std::uintmax_t n = std::filesystem::file_size(path, ec);
  return ec ? 0 : n;
}

TEST(CrashSurvival, BridgeFadesSimulationResumesFromSnapshotRecordingAndReportGoOn) {
  ros::NodeHandle nh;
  Watch w;
  auto sub1 = nh.subscribe<geometry_msgs::WrenchStamped>(
      "/device/servo_cf", 2000, [&](const geometry_msgs::WrenchStamped::ConstPtr& m) {
        const auto& f = m->wrench.force;
        const bool finite = std::isfinite(f.x) && std::isfinite(f.y) && std::isfinite(f.z);
        std::lock_guard<std::mutex> lock(w.mutex);
        w.wrenches.push_back({now(), m->header.stamp.toSec(), std::sqrt(f.x * f.x + f.y * f.y + f.z * f.z), finite});
      }, ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  auto sub2 = nh.subscribe<tissue_trainer::ContactModel>(
      "/tissue/contact", 200, [&](const tissue_trainer::ContactModel::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(w.mutex);
        w.models.push_back({now(), m->header.stamp.toSec(), static_cast<bool>(m->in_contact),
                            m->sequence});
      }, ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  auto sub3 = nh.subscribe<tissue_trainer::TissueStatus>(
      "/tissue/status", 200, [&](const tissue_trainer::TissueStatus::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(w.mutex);
        w.statuses.push_back({now(), m->simulation_time, m->resumed_at, m->restarts});
      });
  ros::AsyncSpinner spinner(2);
  spinner.start();

  const double maxForce = param("max_force"), modelTimeout = param("model_timeout");
  const double fadeTime = param("fade_time"), rate = param("rate");
  const double resumeTime = param("resume_time"), maxForceRate = param("max_force_rate");
  ASSERT_TRUE(std::isfinite(maxForce) && std::isfinite(modelTimeout) && std::isfinite(fadeTime) &&
              std::isfinite(resumeTime) && std::isfinite(maxForceRate));
  std::string bag, assessmentDir;
  ASSERT_TRUE(ros::param::get("~bag", bag) && ros::param::get("~assessment_dir", assessmentDir));

  // 1. Wait for a steady press: in contact and a force at the device for 1 s.
  double pressedSince = -1.0;
  const double waitStart = now();
  while (now() - waitStart < 60.0) {
    ros::WallDuration(0.05).sleep();
    std::lock_guard<std::mutex> lock(w.mutex);
    const bool pressed = !w.models.empty() && w.models.back().inContact && !w.wrenches.empty() &&
                         w.wrenches.back().norm > 0.02;
    if (!pressed) pressedSince = -1.0;
    else if (pressedSince < 0.0) pressedSince = now();
    if (pressedSince > 0.0 && now() - pressedSince > 1.0) break;
  }
  ASSERT_GT(pressedSince, 0.0) << "the tool never pressed the liver steadily";

  // 2. SIGKILL the simulation.
  const int pid = tt_test::nodePid("/simulation");
  ASSERT_GT(pid, 0) << "no pid for /simulation";
  double forceBefore = 0.0;
  std::size_t modelsBefore = 0, wrenchesBefore = 0;
  {
    std::lock_guard<std::mutex> lock(w.mutex);
    forceBefore = w.wrenches.back().norm;
    modelsBefore = w.models.size();
    wrenchesBefore = w.wrenches.size();
  }
  const double killWall = now();
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  const std::uintmax_t bagAtKill = fileSize(bag);

  // 3. Watch for 5 s.
  ros::WallDuration(5.0).sleep();
  std::vector<Wrench> wrenches;
  std::vector<Model> models;
  std::vector<Status> statuses;
  {
    std::lock_guard<std::mutex> lock(w.mutex);
    wrenches.assign(w.wrenches.begin() + static_cast<long>(wrenchesBefore), w.wrenches.end());
    models.assign(w.models.begin(), w.models.end());
    statuses = w.statuses;
  }

  // The last model of the process that died and the first of the new one (its sequence
  // starts again).
  double lastOldModel = 0.0, firstNewModel = -1.0;
  for (std::size_t i = std::max<std::size_t>(modelsBefore, 1); i < models.size(); ++i)
    if (models[i].sequence <= models[i - 1].sequence) {
      lastOldModel = models[i - 1].arrival;
      firstNewModel = models[i].arrival;
      break;
    }
  ASSERT_GT(firstNewModel, 0.0) << "no contact model from a restarted simulation within 5 s";
  const double gap = firstNewModel - lastOldModel;
  std::printf("crash_survival: force before the kill %.3f N; contact-model gap %.3f s "
              "(kill to the first new model %.3f s)\n", forceBefore, gap, firstNewModel - killWall);
  EXPECT_LT(firstNewModel - killWall, 2.5);

  // This node may connect to the new simulation later than the bridge and miss its first
  // models (they are not latched): the new models began (sequence - 1) steps before the first
  // one seen here, one step period (measured on the old models) each.
  ASSERT_GE(modelsBefore, 2u);
  const Model& firstOld = models.front();
  const Model& lastSeenOld = models[modelsBefore - 1];
  const double modelPeriod = (lastSeenOld.stamp - firstOld.stamp) /
                            static_cast<double>(lastSeenOld.sequence - firstOld.sequence);
  const Model* firstNew = nullptr;
  for (const Model& m : models)
    if (m.arrival == firstNewModel) firstNew = &m;
  ASSERT_NE(firstNew, nullptr);
  const double newModelsFrom = std::min(
      firstNewModel, firstNew->stamp - (static_cast<double>(firstNew->sequence) - 1.0) * modelPeriod);
  std::printf("crash_survival: first new model seen here has sequence %llu; the new models began "
              "%.3f s before it arrived\n", static_cast<unsigned long long>(firstNew->sequence),
              firstNewModel - newModelsFrom);

  // The bridge: finite, bounded, ~1 kHz throughout, zero from model_timeout + fade_time after
  // the last model until the new models.
  const double zeroFrom = lastOldModel + modelTimeout + fadeTime + 0.02;
  int nonFinite = 0, above = 0, nonZeroInGap = 0, inGap = 0;
  for (const Wrench& x : wrenches) {
    if (!x.finite) ++nonFinite;
    if (x.norm > maxForce + 1e-9) ++above;
    if (x.arrival > zeroFrom && x.arrival < newModelsFrom) {
      ++inGap;
      if (x.norm != 0.0) ++nonZeroInGap;
    }
  }
  EXPECT_EQ(nonFinite, 0);
  EXPECT_EQ(above, 0);
  EXPECT_GT(inGap, 0);
  EXPECT_EQ(nonZeroInGap, 0) << "of " << inGap << " wrenches between the fade and the restart";
  ASSERT_GE(wrenches.size(), 2u);
  const double span = wrenches.back().stamp - wrenches.front().stamp;
  const double measuredRate = (wrenches.size() - 1) / span;
  std::printf("crash_survival: bridge %.1f Hz over the %.2f s after the kill\n", measuredRate, span);
  EXPECT_GT(measuredRate, 0.95 * rate);

  // The force comes back smoothly: over the bridge's resume ramp (resume_time after the first
  // new model, with a margin) no tick changes it by more than a tenth of what it reaches; after
  // it, the tissue's own dynamics move it, within the bridge's rate limit.
  const double rampEnd = newModelsFrom + resumeTime + 0.05;
  double peakAfter = 0.0, rampStep = 0.0, largestStep = 0.0;
  for (std::size_t i = 1; i < wrenches.size(); ++i) {
    if (wrenches[i].arrival < newModelsFrom) continue;
    peakAfter = std::max(peakAfter, wrenches[i].norm);
    const double step = std::abs(wrenches[i].norm - wrenches[i - 1].norm);
    largestStep = std::max(largestStep, step);
    if (wrenches[i].arrival <= rampEnd) rampStep = std::max(rampStep, step);
  }
  std::printf("crash_survival: force after the restart up to %.3f N; largest step %.4f N in the "
              "resume ramp, %.4f N in the 5 s\n", peakAfter, rampStep, largestStep);
  EXPECT_GT(peakAfter, 0.02) << "no force after the restart";
  EXPECT_LT(rampStep, 0.1 * peakAfter + 1e-3);
  EXPECT_LE(largestStep, maxForceRate / rate + 1e-9);

  // The simulation resumed from its snapshot: time near where it died, not from 0.
  // The process that died published its status after writing its snapshot, so the kill can
  // fall between the two: the snapshot may then be one step newer than the last status seen.
  std::size_t firstResumed = 0;
  while (firstResumed < statuses.size() && statuses[firstResumed].restarts == 0) ++firstResumed;
  ASSERT_LT(firstResumed, statuses.size()) << "no status from a restarted simulation";
  ASSERT_GE(firstResumed, 2u) << "fewer than two statuses from the simulation before the kill";
  const Status* resumed = &statuses[firstResumed];
  const double diedAt = statuses[firstResumed - 1].simulationTime;
  std::printf("crash_survival: died at t = %.3f s, resumed at t = %.3f s (first status %.3f s "
              "after the kill)\n", diedAt, resumed->resumedAt, resumed->arrival - killWall);
  EXPECT_GE(resumed->resumedAt, diedAt - 0.75);
  // That one step varies with the real-time clock, up to the scene's longest frame
  // (run.max_frame_time, 100 ms here). (Bounded by the length of the step before, the test
  // failed once: resumed at 4.06228 s, the last status at 4.0602 s.)
  constexpr double kLongestFrame = 0.1;  // s
  EXPECT_LE(resumed->resumedAt, diedAt + kLongestFrame + 1e-9);
  EXPECT_GE(resumed->simulationTime, resumed->resumedAt);
  EXPECT_LT(resumed->simulationTime, diedAt + 0.5);

  // The recorder kept recording, and the assessment marks the restart.
  const std::uintmax_t bagNow = fileSize(bag);
  std::printf("crash_survival: bag %s %ju -> %ju bytes over the 5 s\n", bag.c_str(), bagAtKill, bagNow);
  EXPECT_GT(bagNow, bagAtKill + 10000);
  std_srvs::Trigger write;
  ASSERT_TRUE(ros::service::call("/assessment/write", write)) << "no /assessment/write";
  ASSERT_TRUE(write.response.success) << write.response.message;
  std::ifstream md(assessmentDir + "/assessment.md");
  std::stringstream text;
  text << md.rdbuf();
  EXPECT_NE(text.str().find("Simulation restarted at t = "), std::string::npos) << text.str();
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "crash_survival_check");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
