// <creature>/power (flapsim/MotorPower): the mechanical power of a creature's motors, as
// means over the window since the last message, from the world's running counters
// (flapsim::World::power).
#pragma once

#include <ros/ros.h>

#include <string>
#include <vector>

#include "flapsim/MotorPower.h"
#include "flapsim/world.h"

namespace flapsim_ros {

/// The message for the window between two readings of a creature's counters, `before` (taken
/// earlier; a reading with more time than `now`, or none (time 0), starts the window at the
/// counters' zero: a reset or a spawn) and `now`. Joints: the model's movable joints.
flapsim::MotorPower powerMsg(const flapsim::CreatureModel& model,
                             const flapsim::CreaturePower& before,
                             const flapsim::CreaturePower& now, const ros::Time& stamp);

class PowerPublisher {
 public:
  /// `queue`: the topic's publisher queue (messages).
  PowerPublisher(ros::NodeHandle& nh, const std::string& creature, flapsim::CreatureModelPtr model,
                 int queue);
  /// Publishes the means since the last call if anyone listens; the window restarts either way.
  void publish(const flapsim::CreaturePower& power, const ros::Time& stamp);
  void shutdown() { pub_.shutdown(); }

 private:
  ros::Publisher pub_;
  flapsim::CreatureModelPtr model_;
  flapsim::CreaturePower last_;
};

}  // namespace flapsim_ros
