// <creature>/power (flapsim/MotorPower): the mechanical power of a creature's motors, as
// means over the window since the last message and over the last kPowerAverageWindow of sim
// time, from the world's running counters (flapsim::World::power).
#pragma once

#include <ros/ros.h>

#include <deque>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "flapsim/MotorPower.h"
#include "flapsim/world.h"

namespace flapsim_ros {

/// The message for the window between two readings of a creature's counters, `before` (taken
/// earlier; a reading with more time than `now`, or none (time 0), starts the window at the
/// counters' zero: a reset or a spawn) and `now`. Joints: the model's movable joints.
/// The averages' window, `average_from` the reading that starts it (the same rule as `before`).
flapsim::MotorPower powerMsg(const flapsim::CreatureModel& model,
                             const flapsim::CreaturePower& before,
                             const flapsim::CreaturePower& now, const ros::Time& stamp,
                             const flapsim::CreaturePower& average_from);

/// The window of MotorPower's averages: 1 s of sim time, several strokes of every creature
/// here (a 10 ms message window swung between 6 and 86 W/kg on the hover creature).
constexpr double kPowerAverageWindow = 1.0;

class PowerPublisher {
 public:
  /// The counters as they are now, and the stamp to give them.
  using Current = std::function<std::pair<flapsim::CreaturePower, ros::Time>()>;
  /// `queue`: the topic's publisher queue (messages). A new subscriber gets a message of
  /// `current()` at once (so `rostopic echo -n1` answers while the world is paused).
  PowerPublisher(ros::NodeHandle& nh, const std::string& creature, flapsim::CreatureModelPtr model,
                 int queue, Current current);
  /// Publishes the means since the last call if anyone listens; the window restarts either way.
  void publish(const flapsim::CreaturePower& power, const ros::Time& stamp);
  void shutdown() { pub_.shutdown(); }

 private:
  // The reading that starts the averages' window ending at `now`.
  const flapsim::CreaturePower& averageFrom(const flapsim::CreaturePower& now) const;

  ros::Publisher pub_;
  flapsim::CreatureModelPtr model_;
  Current current_;
  flapsim::CreaturePower last_;
  std::deque<flapsim::CreaturePower> history_;  // readings of the last kPowerAverageWindow
};

}  // namespace flapsim_ros
