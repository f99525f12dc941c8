// ann_controller: the evolved network on every unit of a creature, from tf to
// <creature>/wing_command. Run it in the creature's namespace; see
// flapsim_ros::AnnControllerParams for the parameters.
#include <ros/ros.h>

#include <exception>

#include "flapsim_ros/controller_nodes.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "ann_controller");
  ros::NodeHandle nh, pnh("~");
  try {
    flapsim_ros::AnnControllerNode node(nh, pnh);
    return node.run() ? 0 : 1;
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM("ann_controller: " << e.what());
    return 1;
  }
}
