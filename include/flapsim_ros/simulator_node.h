// The simulator node: owns a flapsim::World and composes the parts that map it to topics and
// services. Single-threaded: callbacks run between steps on the node's own callback queue, so
// the world needs no lock.
#pragma once

#include <ros/callback_queue.h>
#include <ros/ros.h>

#include <memory>

#include "flapsim/world.h"
#include "flapsim_ros/controller_wait.h"
#include "flapsim_ros/creature_registry.h"
#include "flapsim_ros/node_diagnostics.h"
#include "flapsim_ros/params.h"
#include "flapsim_ros/physics_config.h"
#include "flapsim_ros/simulator_services.h"
#include "flapsim_ros/state_services.h"
#include "flapsim_ros/stepper.h"
#include "flapsim_ros/tf_publisher.h"
#include "flapsim_ros/world_publishers.h"

namespace flapsim_ros {

class SimulatorNode {
 public:
  /// Reads parameters from `pnh` (private) and spawns the configured
  /// creatures. Topics of creatures are relative to `nh`; services and
  /// markers live under `pnh`. Throws ParamError, flapsim::ModelError or
  /// flapsim::InputError for a bad start-up configuration.
  SimulatorNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);
  SimulatorNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, const NodeParams& params);

  /// Steps, paces, publishes and serves until ros::ok() turns false.
  void run();

  const flapsim::World& world() const { return world_; }
  bool paused() const { return stepper_->paused(); }

 private:
  /// Spawns the creatures of ~creatures, with their wing commands. ParamError naming a bad one.
  void spawnConfigured();

  NodeParams params_;
  ros::CallbackQueue queue_;
  ros::NodeHandle nh_;
  ros::NodeHandle pnh_;
  flapsim::World world_;
  std::unique_ptr<TfPublisher> tf_;
  std::unique_ptr<CreatureRegistry> creatures_;
  std::unique_ptr<NodeDiagnostics> diagnostics_;
  std::unique_ptr<WorldPublishers> publishers_;
  std::unique_ptr<Stepper> stepper_;
  std::unique_ptr<PhysicsConfig> physics_;
  std::unique_ptr<ControllerWait> wait_;
  std::unique_ptr<SimulatorServices> services_;
  std::unique_ptr<StateServices> state_services_;
  ros::WallTime clock_wall_;  // of the last /clock while paused
};

}  // namespace flapsim_ros
