// The landmark fitting node (see landmark_fitting_node.h and docs/nodes.md).
#include <ros/ros.h>

#include "landmark_fitting_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "landmark_fitting");
  tt_nodes::LandmarkFittingNode node(ros::NodeHandle(), ros::NodeHandle("~"));
  if (!node.start()) return 2;
  ros::spin();
  return 0;
}
