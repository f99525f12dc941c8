// ann_controller: the evolved network on every unit of a creature, from tf to
// <creature>/wing_command. Run it in the creature's namespace; see
// flapsim_ros::AnnControllerParams for the parameters.
#include <ros/ros.h>

#include <exception>

#include "flapsim_ros/controller_nodes.h"
#include "flapsim_ros/node_main.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "ann_controller");
  return flapsim_ros::runNode("ann_controller", [] {
    flapsim_ros::AnnControllerNode node(ros::NodeHandle(), ros::NodeHandle("~"));
    return node.run() ? 0 : 1;
  });
}
