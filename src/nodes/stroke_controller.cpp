// stroke_controller: open-loop wing strokes from parameters, published to
// <creature>/wing_command. Run it in the creature's namespace; see
// flapsim_ros::StrokeControllerNode for the parameters.
#include <ros/ros.h>

#include <exception>

#include "flapsim_ros/controller_nodes.h"
#include "flapsim_ros/node_main.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "stroke_controller");
  return flapsim_ros::runNode("stroke_controller", [] {
    flapsim_ros::StrokeControllerNode node(ros::NodeHandle(), ros::NodeHandle("~"));
    ros::spin();
    return 0;
  });
}
