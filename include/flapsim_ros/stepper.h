// How the simulator node advances the world: in slices between callback rounds, publishing at
// every publication boundary it crosses, reporting the creatures the watchdog froze and the
// wing commands that timed out, paced to the real-time factor in wall time, or paused.
#pragma once

#include <ros/callback_queue.h>
#include <ros/ros.h>

#include <cstdint>

#include "flapsim/world.h"
#include "flapsim_ros/creature_registry.h"
#include "flapsim_ros/node_diagnostics.h"
#include "flapsim_ros/params.h"
#include "flapsim_ros/world_publishers.h"

namespace flapsim_ros {

class Stepper {
 public:
  /// The arguments outlive it; `params` as they change (publish_rate, real_time_factor).
  Stepper(flapsim::World& world, CreatureRegistry& creatures, WorldPublishers& publishers,
          NodeDiagnostics& diagnostics, const NodeParams& params);

  bool paused() const { return paused_; }
  void setPaused(bool paused) { paused_ = paused; }

  /// Steps up to `steps` fixed steps in slices, publishing at every publication boundary
  /// crossed and reporting creatures the watchdog froze and commands that timed out; stops
  /// early on shutdown or once `wall_budget` seconds of wall time have passed (<= 0: no
  /// budget). Returns the steps taken.
  std::uint64_t advance(std::uint64_t steps, double wall_budget = 0.0);
  /// Runs to the next publication (or a slice of wall time), serves `queue`, then waits as the
  /// real-time factor asks (serving `queue` meanwhile).
  void runSlice(ros::CallbackQueue& queue);
  /// Pacing starts again from now (after a pause, a reset, a change of the factor).
  void restartPacing();

 private:
  /// Logs each creature the watchdog froze and each wing command that timed out (a throttled
  /// warning), once, and republishes the diagnostics.
  void reportEvents();

  flapsim::World& world_;
  CreatureRegistry& creatures_;
  WorldPublishers& publishers_;
  NodeDiagnostics& diagnostics_;
  const NodeParams& params_;
  bool paused_;
  std::uint64_t slice_steps_ = 1;  // steps per slice (see advance())
  ros::WallTime pace_wall_;        // wall time at the pacing anchor
  std::uint64_t pace_step_ = 0;    // step count at the pacing anchor
};

}  // namespace flapsim_ros
