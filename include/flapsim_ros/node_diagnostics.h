// The simulator node's /diagnostics: one status per creature (frozen, waiting for its
// controller or run without it, its wing command timed out or lagging, or running).
#pragma once

#include <ros/ros.h>

#include "flapsim/world.h"
#include "flapsim_ros/creature_registry.h"
#include "flapsim_ros/params.h"

namespace flapsim_ros {

/// A wing command answering a state (its stamp) older than this (s of sim time) is a
/// controller falling behind: warned, and shown on /diagnostics.
constexpr double kCommandLagWarning = 0.1;

class NodeDiagnostics {
 public:
  /// The arguments outlive it.
  NodeDiagnostics(const ros::NodeHandle& nh, const flapsim::World& world,
                  const CreatureRegistry& creatures, const NodeParams& params);
  void publish();
  /// s of wall time since the last publication.
  double age() const { return (ros::WallTime::now() - last_).toSec(); }

 private:
  const flapsim::World& world_;
  const CreatureRegistry& creatures_;
  const NodeParams& params_;
  ros::Publisher pub_;
  ros::WallTime last_;  // of the last publication
};

}  // namespace flapsim_ros
