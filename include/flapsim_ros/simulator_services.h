// The simulator node's control of the simulation: flapsim/reset, pause, unpause, step, spawn,
// delete, get_physics and set_physics, and each creature's <creature>/wing_command. They run on
// the node's queue between steps.
#pragma once

#include <ros/ros.h>
#include <std_srvs/Empty.h>

#include <string>
#include <vector>

#include "flapsim/DeleteCreature.h"
#include "flapsim/GetPhysics.h"
#include "flapsim/SetPhysics.h"
#include "flapsim/SpawnCreature.h"
#include "flapsim/Step.h"
#include "flapsim/WingCommand.h"
#include "flapsim/world.h"
#include "flapsim_ros/creature_registry.h"
#include "flapsim_ros/node_diagnostics.h"
#include "flapsim_ros/params.h"
#include "flapsim_ros/physics_config.h"
#include "flapsim_ros/stepper.h"
#include "flapsim_ros/tf_publisher.h"
#include "flapsim_ros/world_publishers.h"

namespace flapsim_ros {

/// The parts of the node the services act on (all outlive the services).
struct SimulationParts {
  flapsim::World& world;
  CreatureRegistry& creatures;
  WorldPublishers& publishers;
  TfPublisher& tf;
  Stepper& stepper;
  PhysicsConfig& physics;
  NodeDiagnostics& diagnostics;
  const NodeParams& params;
};

class SimulatorServices {
 public:
  /// Advertised under `pnh`.
  SimulatorServices(const ros::NodeHandle& pnh, const SimulationParts& parts);
  /// A creature's wing command: applied (World::setWingCommands checks it) or refused with a
  /// throttled warning; its lag (the age of the state it answers) is watched.
  void onWingCommand(const std::string& creature, const flapsim::WingCommand::ConstPtr& msg);

 private:
  bool onReset(std_srvs::Empty::Request& req, std_srvs::Empty::Response& res);
  bool onPause(std_srvs::Empty::Request& req, std_srvs::Empty::Response& res);
  bool onUnpause(std_srvs::Empty::Request& req, std_srvs::Empty::Response& res);
  bool onStep(flapsim::Step::Request& req, flapsim::Step::Response& res);
  bool onSpawn(flapsim::SpawnCreature::Request& req, flapsim::SpawnCreature::Response& res);
  bool onDelete(flapsim::DeleteCreature::Request& req, flapsim::DeleteCreature::Response& res);
  bool onGetPhysics(flapsim::GetPhysics::Request& req, flapsim::GetPhysics::Response& res);
  bool onSetPhysics(flapsim::SetPhysics::Request& req, flapsim::SetPhysics::Response& res);

  SimulationParts parts_;
  std::vector<ros::ServiceServer> services_;
};

}  // namespace flapsim_ros
