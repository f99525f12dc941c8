// flapsim_node: the simulator node. Everything but main() lives in
// src/ros/ (SimulatorNode, parameter loader, message conversions).
#include <ros/ros.h>

#include <exception>

#include "flapsim_ros/node_main.h"
#include "flapsim_ros/simulator_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "flapsim");
  return flapsim_ros::runNode("flapsim", [] {
    flapsim_ros::SimulatorNode node(ros::NodeHandle(), ros::NodeHandle("~"));
    node.run();
    return 0;
  });
}
