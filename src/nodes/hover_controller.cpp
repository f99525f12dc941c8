// hover_controller: the hover creature's hand-designed controller (flapsim::HoverController)
// on its IMU and odometry, free running or in lockstep (flapsim_ros::HoverControllerNode).
#include <ros/ros.h>

#include "flapsim_ros/hover_controller_node.h"
#include "flapsim_ros/node_main.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "hover_controller");
  return flapsim_ros::runNode("hover_controller", [] {
    flapsim_ros::HoverControllerNode node(ros::NodeHandle(), ros::NodeHandle("~"));
    return node.run() ? 0 : 1;
  });
}
