// flapsim_node: the simulator node. Everything but main() lives in
// src/ros/ (SimulatorNode, parameter loader, message conversions).
#include <ros/ros.h>

#include <exception>

#include "flapsim_ros/simulator_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "flapsim");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  try {
    flapsim_ros::SimulatorNode node(nh, pnh);
    node.run();
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM("flapsim: " << e.what());
    return 1;
  }
  return 0;
}
