// Online training assessment: feeds the tool tip, contact and tissue status topics into the
// core accumulator, publishes the running report (YAML) on /assessment/summary, and writes
// assessment.yaml + assessment.md (scored against ~reference_bands) and the series CSV files
// to ~output_dir on ~write and on shutdown. The plots are made by assess_bag from the bag.
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <std_msgs/String.h>
#include <std_srvs/Trigger.h>

#include <csignal>
#include <exception>

#include "node_params.h"
#include "session_messages.h"
#include "tissue_trainer/core/assess/assessment_report.h"

namespace {

class AssessmentNode {
 public:
  AssessmentNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, const tt::AssessmentNodeParams& p)
      : params_(p), feeder_(p.settings) {
    const tt::SessionTopics topics;
    const auto hints = ros::TransportHints().tcpNoDelay();
    tipSub_ = nh.subscribe(topics.tip, 10000, &AssessmentNode::onTip, this, hints);
    contactSub_ = nh.subscribe(topics.contact, 1000, &AssessmentNode::onContact, this, hints);
    statusSub_ = nh.subscribe(topics.status, 1000, &AssessmentNode::onStatus, this, hints);
    summaryPub_ = nh.advertise<std_msgs::String>("/assessment/summary", 1);
    writeSrv_ = pnh.advertiseService("write", &AssessmentNode::onWrite, this);
    timer_ = nh.createTimer(ros::Duration(1.0 / p.summaryRate), &AssessmentNode::onTimer, this);
  }

  // Returns the YAML path written.
  std::string write() const {
    const tt::AssessmentReport report = feeder_.report();
    if (!params_.scored) return tt::writeAssessment(report, params_.outputDir, "online");
    const tt::SkillScore score = tt::scoreAssessment(report, params_.bands);
    return tt::writeAssessment(report, params_.outputDir, "online", &score);
  }

 private:
  void onTip(const geometry_msgs::PoseStamped& m) { feeder_.feed(m); }
  void onContact(const tissue_trainer::ContactModel& m) { feeder_.feed(m); }
  void onStatus(const tissue_trainer::TissueStatus& m) { feeder_.feed(m); }

  void onTimer(const ros::TimerEvent&) {
    std_msgs::String msg;
    msg.data = tt::assessmentYaml(feeder_.report(), "online");
    summaryPub_.publish(msg);
  }

  bool onWrite(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    try {
      res.message = write();
      res.success = true;
    } catch (const std::exception& e) {
      res.message = e.what();
      res.success = false;
    }
    return true;
  }

  tt::AssessmentNodeParams params_;
  tt::SessionFeeder feeder_;
  ros::Subscriber tipSub_, contactSub_, statusSub_;
  ros::Publisher summaryPub_;
  ros::ServiceServer writeSrv_;
  ros::Timer timer_;
};

volatile std::sig_atomic_t stopRequested = 0;
void requestStop(int) { stopRequested = 1; }

// Serves callbacks until SIGINT/SIGTERM (roslaunch teardown, Ctrl-C) or a ROS shutdown. After
// a signal it keeps taking messages for a moment, so a replay that has just ended (rosbag
// play exits, roslaunch stops the node) is assessed to its last message.
void spinUntilStopped() {
  ros::CallbackQueue& queue = *ros::getGlobalCallbackQueue();
  while (ros::ok() && !stopRequested) queue.callAvailable(ros::WallDuration(0.05));
  const ros::WallTime drainEnd = ros::WallTime::now() + ros::WallDuration(0.5);
  while (ros::ok() && ros::WallTime::now() < drainEnd) queue.callAvailable(ros::WallDuration(0.05));
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "assessment", ros::init_options::NoSigintHandler);
  std::signal(SIGINT, requestStop);
  std::signal(SIGTERM, requestStop);
  ros::NodeHandle nh, pnh("~");
  tt::AssessmentNodeParams params;
  try {
    params = tt::readAssessmentNodeParams(pnh);
  } catch (const std::exception& e) {
    ROS_FATAL("assessment: %s", e.what());
    return 2;
  }
  AssessmentNode node(nh, pnh, params);
  spinUntilStopped();
  int status = 0;
  try {
    const std::string path = node.write();
    ROS_INFO("assessment: wrote %s", path.c_str());
  } catch (const std::exception& e) {
    ROS_ERROR("assessment: %s", e.what());
    status = 1;
  }
  ros::shutdown();
  return status;
}
