// stroke_controller: open-loop wing strokes from parameters, published to
// <creature>/wing_command. Run it in the creature's namespace; see
// flapsim_ros::StrokeControllerNode for the parameters.
#include <ros/ros.h>

#include <exception>

#include "flapsim_ros/controller_nodes.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "stroke_controller");
  ros::NodeHandle nh, pnh("~");
  try {
    flapsim_ros::StrokeControllerNode node(nh, pnh);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM("stroke_controller: " << e.what());
    return 1;
  }
  return 0;
}
