// Ends a training session after a wall-clock duration: launched as a required node, its exit
// makes roslaunch shut every node down cleanly (the recorder closes its bag, the assessment
// writes its report).
//   session_timer SECONDS
#include <ros/ros.h>

#include <cmath>
#include <cstdlib>

int main(int argc, char** argv) {
  ros::init(argc, argv, "session_timer");
  char* end = nullptr;
  const double seconds = argc == 2 ? std::strtod(argv[1], &end) : NAN;
  if (argc != 2 || end == argv[1] || *end != '\0' || !std::isfinite(seconds) || seconds <= 0.0) {
    ROS_FATAL("session_timer: expected one argument, the session duration in seconds (> 0), got '%s'",
              argc >= 2 ? argv[1] : "");
    return 2;
  }
  ros::NodeHandle node;
  ROS_INFO("session ends in %.1f s", seconds);
  const ros::WallTime end_time = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < end_time) ros::WallDuration(0.05).sleep();
  if (!ros::ok()) return 0;
  ROS_INFO("session time is over; shutting down");
  return 0;
}
