// What of the simulator node's physics and pacing can change while it runs (real-time factor,
// publication rate, wind, air density, drag coefficient, gravity, markers): the
// dynamic_reconfigure server and the config that flapsim/set_physics, flapsim/get_physics and
// flapsim/reset (back to the start-up values) read and write, applied all or nothing.
#pragma once

#include <dynamic_reconfigure/server.h>
#include <ros/ros.h>

#include <cstdint>
#include <functional>
#include <memory>

#include "flapsim/FlapsimConfig.h"
#include "flapsim/world.h"
#include "flapsim_ros/creature_registry.h"
#include "flapsim_ros/params.h"

namespace flapsim_ros {

class PhysicsConfig {
 public:
  /// The server under `pnh` (its callbacks on `pnh`'s queue), starting from what runs (the
  /// node's parameters, not the cfg defaults). `changed` is called after each applied change
  /// (pacing starts again). The arguments outlive it.
  PhysicsConfig(const ros::NodeHandle& pnh, flapsim::World& world, NodeParams& params,
                CreatureRegistry& creatures, std::function<void()> changed);
  /// What runs, as a dynamic_reconfigure config.
  flapsim::FlapsimConfig running() const;
  /// Applies a config (dynamic_reconfigure's or flapsim/set_physics'), all or nothing: throws
  /// InputError naming the cause and changes nothing. dynamic_reconfigure then shows it.
  void apply(const flapsim::FlapsimConfig& config);
  /// Back to what ran at start-up (flapsim/reset); a warning if that is refused now.
  void restoreLaunch();

 private:
  void applyQuietly(const flapsim::FlapsimConfig& config);
  /// dynamic_reconfigure: applies what can change while running, all or nothing; a refused
  /// change is logged naming its cause and the config is put back to what runs.
  void onReconfigure(flapsim::FlapsimConfig& config);

  flapsim::World& world_;
  NodeParams& params_;
  CreatureRegistry& creatures_;
  std::function<void()> changed_;
  flapsim::FlapsimConfig launch_;  // what ran at start-up: flapsim/reset restores it
  boost::recursive_mutex mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<flapsim::FlapsimConfig>> server_;
};

}  // namespace flapsim_ros
