// hover_controller: flies the hover creature (make_creature --layout hover) with the core's
// flapsim::HoverController (its gains: private parameters, hover.launch loads the evolved ones),
// from imu (attitude, body rates) and odom (position and velocity: an altimeter and a position
// fix); run it in the creature's namespace (as ann_controller), whose topics these are.
//  - free running: it answers each state (an imu and an odom message of one stamp) at most
//    `rate` times a second of sim time with a wing_command stamped as the state, as soon as both
//    arrive (the simulator's publish_rate sets how fresh the state is: 100 Hz by default);
//  - lockstep (~lockstep, LockstepParams): it steps the paused simulator one control period of
//    1 / `rate` at a time with its command in the step request, each from the state at the
//    period's start: the flight of the core's flyHover, bit-reproducible.
#pragma once

#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>

#include <mutex>
#include <string>
#include <vector>

#include "flapsim/WingCommand.h"
#include "flapsim/hover_controller.h"
#include "flapsim_ros/controller_params.h"
#include "flapsim_ros/param_reader.h"

namespace flapsim_ros {

struct HoverControllerNodeParams : LockstepParams {
  std::string creature;  // for messages: the namespace's (the creature's) name
  double rate = 100.0;   // Hz of sim time
  flapsim::HoverControllerParams controller;
};

/// Private namespace of hover_controller. Keys (all optional): creature (default
/// `default_creature`), rate (100), gains_file (a gains YAML, flapsim/hover_gains.h, read as
/// flight_check --gains reads it: hover.launch passes it), the controller's: altitude (3) and
/// every other field of flapsim::HoverControllerParams by its name (each overrides the file's),
/// and lockstep, lockstep_duration, step_service, step_size, wait_timeout (LockstepParams).
/// Throws ParamError naming the bad key, an unknown (misspelt) key included.
HoverControllerNodeParams parseHoverControllerParams(const XmlRpc::XmlRpcValue& ns,
                                                     const std::string& default_creature);

class HoverControllerNode {
 public:
  /// Throws ParamError or flapsim::InputError on bad parameters.
  HoverControllerNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);

  /// Free running: spins until shutdown. Lockstep: drives the simulator until
  /// lockstep_duration, then returns. Returns false if lockstep failed.
  bool run();

 private:
  /// The sensors of the imu and odom messages last received if both are stamped `stamp`
  /// (ros::Time(0): any equal stamp), with their stamp.
  bool sensorsAt(const ros::Time& stamp, flapsim::HoverSensors& sensors, ros::Time& at) const;
  /// The controller's command for `sensors`, `dt` s after the last, stamped `stamp`.
  flapsim::WingCommand command(const flapsim::HoverSensors& sensors, double dt,
                               const ros::Time& stamp);
  /// Free running: a new state arrived.
  void onState();
  bool runLockstep();

  ros::NodeHandle nh_, pnh_;
  HoverControllerNodeParams params_;
  flapsim::HoverController controller_;
  mutable std::mutex mutex_;  // guards imu_ and odom_ (lockstep: set by the spinner's thread)
  sensor_msgs::Imu::ConstPtr imu_;
  nav_msgs::Odometry::ConstPtr odom_;
  ros::Subscriber imu_sub_, odom_sub_;
  ros::Publisher pub_;
  ros::Time last_;  // stamp of the state last answered
};

}  // namespace flapsim_ros
