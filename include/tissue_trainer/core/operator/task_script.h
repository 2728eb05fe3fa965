#pragma once
// A scripted training task: time-stamped keyframes of the instrument tip position (world, m)
// and the jaw opening (rad), each labelled with its phase, interpolated with minimum-jerk
// profiles (zero velocity and acceleration at every keyframe). Loaded from YAML with strict
// validation: every error is one InputError line "FILE:LINE: key: what was expected".
#include <Eigen/Core>
#include <string>
#include <vector>

namespace tt {

// The phases a keyframe may name (the segment that ends at the keyframe is in its phase).
// start: the pose the script begins in; approach: move toward the tissue; palpate: press into
// it; grasp: close the jaw on it; retract: pull the grasped tissue; release: let go (open the
// jaw or lift off); withdraw: leave the tissue; hold: stay.
const std::vector<std::string>& taskPhases();

struct Keyframe {
  double time = 0.0;              // s from the start of the task, strictly increasing
  std::string phase;
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();  // world, m
  double jaw = 0.0;               // rad, opening angle (0 = closed)
};

struct TaskSample {
  Eigen::Vector3d tip;            // target tip position (world, m)
  Eigen::Vector3d tipVelocity;    // its time derivative (m/s)
  double jaw = 0.0;               // rad
  const std::string* phase = nullptr;  // the keyframe phase of the current segment
  bool finished = false;          // t at or past the last keyframe
};

class TaskScript {
 public:
  // Throws std::invalid_argument for fewer than one keyframe, a first time other than 0,
  // times not strictly increasing, unknown phases, non-finite values or a negative jaw.
  explicit TaskScript(std::vector<Keyframe> keyframes, std::string name = "task");

  // Reads the YAML file (format in config/tasks/README.md); throws InputError.
  static TaskScript load(const std::string& path);

  const std::string& name() const { return name_; }
  const std::vector<Keyframe>& keyframes() const { return keyframes_; }
  double duration() const { return keyframes_.back().time; }
  // The first keyframe of the given phase, or nullptr.
  const Keyframe* find(const std::string& phase) const;

  // Target at time t (before 0: the first keyframe; after the end: the last one).
  TaskSample sample(double t) const;

 private:
  std::vector<Keyframe> keyframes_;
  std::string name_;
};

}  // namespace tt
