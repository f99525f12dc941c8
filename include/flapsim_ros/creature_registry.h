// The simulator node's creatures: spawned into the world with their topics, markers and fixed
// transforms, found by name, deleted; and the throttled warnings about them.
#pragma once

#include <ros/ros.h>
#include <visualization_msgs/Marker.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "flapsim/WingCommand.h"
#include "flapsim/world.h"
#include "flapsim_ros/creature_publishers.h"
#include "flapsim_ros/params.h"
#include "flapsim_ros/tf_publisher.h"
#include "flapsim_ros/warning_limiter.h"

namespace flapsim_ros {

/// What the node keeps of a spawned creature besides the world's state.
struct NodeCreature {
  // The creature's own handle (a copy of the node's): roscpp keeps a weak pointer to every
  // publisher and subscriber a handle made until the handle goes, which held each deleted
  // creature's (about 0.7 KB a spawn and delete). Declared first: destroyed last.
  ros::NodeHandle nh;
  std::string name;
  flapsim::CreatureModelPtr model;
  std::unique_ptr<CreaturePublishers> topics;
  ros::Subscriber wing_command;
  std::vector<visualization_msgs::Marker> geometry;  // its shapes, for ~creature_markers
  double command_lag = 0.0;  // s of sim time: how old the state its last command answered was
  std::string controller;    // the node name of its controller (~creatures' `controller`)
  bool awaiting_controller = false;  // the node holds sim time for its first command
  bool controller_missing = false;   // controller_wait_timeout passed without one
  /// A wing command was accepted: the controller it waited for answered.
  void commanded() { awaiting_controller = controller_missing = false; }
};

class CreatureRegistry {
 public:
  using WingCommandHandler =
      std::function<void(const std::string& creature, const flapsim::WingCommand::ConstPtr&)>;
  /// `params` (the node's, as they change) and the rest outlive it. Latched
  /// ~creature_markers under `pnh`; creature topics under `nh`.
  CreatureRegistry(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, const NodeParams& params,
                   flapsim::World& world, TfPublisher& tf);
  ~CreatureRegistry();
  /// Where each creature's wing commands go (set before the first spawn).
  void onWingCommand(WingCommandHandler handler) { on_command_ = std::move(handler); }

  /// Spawns `name` from URDF text (`source` names it in errors): into the world, with its
  /// topics. InputError (or ModelError) naming the cause. Returns (and logs as warnings) the
  /// joint values too stiff for an explicit step (flapsim::implicitJointValues) and the
  /// shapes it ignores (flapsim::geometryNotes), each line prefixed with the creature.
  std::vector<std::string> spawn(const std::string& name, const std::string& urdf_xml,
                                 const std::string& source, const flapsim::Pose& pose,
                                 const flapsim::Twist& twist);
  /// From the world and the node; InputError if unknown.
  void remove(const std::string& name);
  NodeCreature* find(const std::string& name);
  const NodeCreature* find(const std::string& name) const;
  const std::vector<std::unique_ptr<NodeCreature>>& all() const { return creatures_; }
  /// Every creature at one step: read from the world once.
  std::vector<CreatureSnapshot> snapshot(const ros::Time& stamp) const;
  /// Latched ~creature_markers (every creature's geometry) and /tf_static (their fixed
  /// joints): after each spawn and delete, and at start-up.
  void publishLatched(const ros::Time& stamp);

  /// Logs `message` as a warning unless one of this kind about this creature was logged in
  /// the last 10 s (WarningLimiter); then only at debug level. A name that is not a
  /// creature's counts as none (the cause holds no caller's text).
  void warn(const std::string& kind, const std::string& creature, const std::string& message);

 private:
  ros::NodeHandle nh_;
  const NodeParams& params_;
  flapsim::World& world_;
  TfPublisher& tf_;
  ros::Publisher markers_;  // ~creature_markers
  ImuNoiseSource imu_noise_;
  WingCommandHandler on_command_;
  std::vector<std::unique_ptr<NodeCreature>> creatures_;  // in spawn order
  WarningLimiter warnings_;
};

}  // namespace flapsim_ros
