// The simulation node (see simulation_node.h and docs/nodes.md).
#include <ros/ros.h>

#include "simulation_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "simulation");
  tt_nodes::SimulationNode node(ros::NodeHandle(), ros::NodeHandle("~"));
  if (!node.start()) return 2;
  ros::spin();
  return 0;
}
