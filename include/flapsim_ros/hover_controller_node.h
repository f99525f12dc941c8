// hover_controller: flies the hover creature (make_creature --layout hover) with the core's
// hand-designed flapsim::HoverController, from imu (attitude, body rates) and odom (position
// and velocity: an altimeter and a position fix), publishing wing_command at `rate` Hz of sim
// time; run it in the creature's namespace (as ann_controller), whose topics these are.
#pragma once

#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>

#include <string>
#include <vector>

#include "flapsim/hover_controller.h"
#include "flapsim_ros/param_reader.h"

namespace flapsim_ros {

struct HoverControllerNodeParams {
  std::string creature;  // for messages: the namespace's (the creature's) name
  double rate = 100.0;   // Hz of sim time
  flapsim::HoverControllerParams controller;
  std::vector<std::string> unknown_keys;
};

/// Private namespace of hover_controller. Keys (all optional): creature (default
/// `default_creature`), rate (100), and the controller's: altitude (3), trim_frequency,
/// amplitude, feather (flapsim::HoverControllerParams). Throws ParamError naming the bad key.
HoverControllerNodeParams parseHoverControllerParams(const XmlRpc::XmlRpcValue& ns,
                                                     const std::string& default_creature);

class HoverControllerNode {
 public:
  /// Throws ParamError or flapsim::InputError on bad parameters.
  HoverControllerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);

 private:
  void onTimer(const ros::TimerEvent& event);

  ros::NodeHandle nh_, pnh_;
  HoverControllerNodeParams params_;
  flapsim::HoverController controller_;
  sensor_msgs::Imu::ConstPtr imu_;
  nav_msgs::Odometry::ConstPtr odom_;
  ros::Subscriber imu_sub_, odom_sub_;
  ros::Publisher pub_;
  ros::Timer timer_;
  ros::Time last_;
};

}  // namespace flapsim_ros
