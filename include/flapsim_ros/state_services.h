// The simulator node's services on a creature's state and the forces on it: flapsim/get_state,
// set_state, apply_wrench and clear_wrenches, each in a reference frame of the world, of a
// creature or of one of its links (as gazebo_msgs' services take them).
#pragma once

#include <ros/ros.h>

#include <string>
#include <vector>

#include "flapsim/ApplyWrench.h"
#include "flapsim/ClearWrenches.h"
#include "flapsim/GetState.h"
#include "flapsim/SetState.h"
#include "flapsim/world.h"
#include "flapsim_ros/conversions.h"
#include "flapsim_ros/creature_registry.h"
#include "flapsim_ros/params.h"
#include "flapsim_ros/world_publishers.h"

namespace flapsim_ros {

/// How far a creature's collision shapes reach below the ground, if they do and the world has
/// one ("" if not): what a spawn or a set_state reply adds.
std::string belowGround(const flapsim::CreatureModel& model, const flapsim::CreatureState& state,
                        bool ground);

class StateServices {
 public:
  /// Advertised under `pnh`; the arguments outlive it.
  StateServices(const ros::NodeHandle& pnh, flapsim::World& world, CreatureRegistry& creatures,
                WorldPublishers& publishers, const NodeParams& params);

 private:
  /// A frame of a request's `reference_frame`, in the world.
  struct ReferenceFrame {
    std::string name;      // "" (the world) or "<creature>/<link>"
    std::string creature;  // "" (the world) or the link's creature
    FrameMotion motion;    // in the world
  };
  /// `name` as a reference frame for a request about `creature`: "" or the world frame, a
  /// creature (its root link), "<creature>/<link>" (or "<creature>::<link>"), or a link of
  /// `creature`. InputError naming it if there is no such frame.
  ReferenceFrame referenceFrame(const std::string& name, const std::string& creature);
  bool onGetState(flapsim::GetState::Request& req, flapsim::GetState::Response& res);
  bool onSetState(flapsim::SetState::Request& req, flapsim::SetState::Response& res);
  bool onApplyWrench(flapsim::ApplyWrench::Request& req, flapsim::ApplyWrench::Response& res);
  bool onClearWrenches(flapsim::ClearWrenches::Request& req, flapsim::ClearWrenches::Response& res);

  flapsim::World& world_;
  CreatureRegistry& creatures_;
  WorldPublishers& publishers_;
  const NodeParams& params_;
  std::vector<ros::ServiceServer> services_;
};

}  // namespace flapsim_ros
