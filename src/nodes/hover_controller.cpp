// hover_controller: the hover creature's hand-designed controller (flapsim::HoverController)
// on its IMU and odometry, free running or in lockstep (flapsim_ros::HoverControllerNode).
#include <ros/ros.h>

#include "flapsim_ros/hover_controller_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "hover_controller");
  try {
    flapsim_ros::HoverControllerNode node(ros::NodeHandle(), ros::NodeHandle("~"));
    return node.run() ? 0 : 1;
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM("hover_controller: " << e.what());
    return 1;
  }
}
