#pragma once
// Session messages -> assessment samples, shared by the node and assess_bag so that a live
// session and its recorded bag feed the accumulator the same numbers. Times are header stamps
// (not receive or bag times), taken relative to a reference second so that doubles keep
// sub-microsecond resolution.
#include <geometry_msgs/PoseStamped.h>
#include <ros/time.h>

#include <string>

#include "tissue_trainer/ContactModel.h"
#include "tissue_trainer/TissueStatus.h"
#include "tissue_trainer/core/assess/session_assessor.h"

namespace tt {

struct SessionTopics {
  std::string tip = "/instrument/measured_cp";
  std::string contact = "/tissue/contact";
  std::string status = "/tissue/status";
};

class SessionFeeder {
 public:
  explicit SessionFeeder(const AssessmentSettings& settings) : assessor_(settings) {}

  bool feed(const geometry_msgs::PoseStamped& m) {
    const auto& p = m.pose.position;
    return assessor_.addTip(time(m.header.stamp), Eigen::Vector3d(p.x, p.y, p.z));
  }
  // The force is f0 while in contact, zero otherwise. A sequence number that does not rise
  // means a restarted simulation (each process numbers its models from 1).
  bool feed(const tissue_trainer::ContactModel& m) {
    const Eigen::Vector3d f = m.in_contact ? Eigen::Vector3d(m.force.x, m.force.y, m.force.z)
                                           : Eigen::Vector3d::Zero();
    const bool restarted = haveSequence_ && m.sequence <= lastSequence_;
    haveSequence_ = true;
    lastSequence_ = m.sequence;
    return assessor_.addForce(time(m.header.stamp), f, m.in_contact, restarted);
  }
  bool feed(const tissue_trainer::TissueStatus& m) {
    return assessor_.addStatus(time(m.header.stamp), m.max_strain, m.strained_volume);
  }

  AssessmentReport report() const { return assessor_.report(); }

 private:
  // Seconds since the whole second of the first stamp seen (any topic).
  double time(const ros::Time& stamp) {
    if (!haveReference_) {
      referenceSec_ = stamp.sec;
      haveReference_ = true;
    }
    return (static_cast<double>(stamp.sec) - static_cast<double>(referenceSec_)) + 1e-9 * stamp.nsec;
  }

  SessionAssessor assessor_;
  bool haveReference_ = false;
  bool haveSequence_ = false;
  std::uint64_t lastSequence_ = 0;
  std::uint32_t referenceSec_ = 0;
};

}  // namespace tt
