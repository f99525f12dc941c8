// The simulator node's wait for its creatures' controllers: a creature that names a
// `controller` in ~creatures holds sim time until that controller's first wing command, as a
// scenario waits for rviz and the recorder, so the controller flies it from t = 0 (before, a
// free-running controller's first command came some 0.7 s of sim time late, the creature
// falling meanwhile).
#pragma once

#include <ros/ros.h>

#include <cstddef>

#include "flapsim/world.h"
#include "flapsim_ros/creature_registry.h"
#include "flapsim_ros/node_diagnostics.h"
#include "flapsim_ros/params.h"
#include "flapsim_ros/stepper.h"

namespace flapsim_ros {

class ControllerWait {
 public:
  /// The arguments outlive it.
  ControllerWait(const flapsim::World& world, CreatureRegistry& creatures,
                 NodeDiagnostics& diagnostics, Stepper& stepper, const NodeParams& params);
  /// True while the node holds sim time for the first wing command of a creature's controller
  /// (creatures naming a `controller`; unpaused, for up to ~controller_wait_timeout of wall
  /// time): announces the wait, and sends the awaited creatures' state again to controllers
  /// that connected after it went out. Once the time passes it names the controllers that did
  /// not answer and the node runs without them.
  bool hold();

 private:
  /// The wait is over (every awaited controller answered, or the time passed): pacing starts
  /// again from now, and the diagnostics say so.
  void end();

  const flapsim::World& world_;
  CreatureRegistry& creatures_;
  NodeDiagnostics& diagnostics_;
  Stepper& stepper_;
  const NodeParams& params_;
  bool holding_ = false;           // holding sim time for controllers
  double held_ = 0.0;              // s of wall time held for them so far (unpaused)
  ros::WallTime held_wall_;        // of the last check while held and unpaused
  ros::WallTime resent_wall_;      // of the last state sent again to awaited controllers
  std::size_t awaited_count_ = 0;  // creatures held for at the last check
};

}  // namespace flapsim_ros
