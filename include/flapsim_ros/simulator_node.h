// The simulator node: owns a flapsim::World and maps it to topics and
// services. Single-threaded: callbacks run between steps on the node's own
// callback queue, so the world needs no lock.
#pragma once

#include <dynamic_reconfigure/server.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <std_srvs/Empty.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "flapsim/ApplyWrench.h"
#include "flapsim/ClearWrenches.h"
#include "flapsim/CreatureStates.h"
#include "flapsim/DeleteCreature.h"
#include "flapsim/FlapsimConfig.h"
#include "flapsim/GetPhysics.h"
#include "flapsim/GetState.h"
#include "flapsim/SetPhysics.h"
#include "flapsim/SetState.h"
#include "flapsim/SpawnCreature.h"
#include "flapsim/Step.h"
#include "flapsim/WingCommand.h"
#include "flapsim/world.h"
#include "flapsim_ros/conversions.h"
#include "flapsim_ros/params.h"
#include "flapsim_ros/power_publisher.h"
#include "flapsim_ros/tf_publisher.h"
#include "flapsim_ros/visuals.h"
#include "flapsim_ros/warning_limiter.h"

namespace flapsim_ros {

class SimulatorNode {
 public:
  /// Reads parameters from `pnh` (private) and spawns the configured
  /// creatures. Topics of creatures are relative to `nh`; services and
  /// markers live under `pnh`. Throws ParamError, flapsim::ModelError or
  /// flapsim::InputError for a bad start-up configuration.
  SimulatorNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);
  SimulatorNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, const NodeParams& params);
  ~SimulatorNode();

  /// Steps, paces, publishes and serves until ros::ok() turns false.
  void run();

  const flapsim::World& world() const { return world_; }
  bool paused() const { return paused_; }

 private:
  struct Creature {
    // The creature's own handle (a copy of the node's): roscpp keeps a weak pointer to every
    // publisher and subscriber a handle made until the handle goes, which held each deleted
    // creature's (about 0.7 KB a spawn and delete). Declared first: destroyed last.
    ros::NodeHandle nh;
    std::string name;
    flapsim::CreatureModelPtr model;
    ros::Publisher joint_states;
    ros::Publisher odom;
    ros::Publisher imu;
    std::unique_ptr<PowerPublisher> power;  // <creature>/power
    ros::Subscriber wing_command;
    ros::Publisher description;  // latched URDF text: what a replay needs to draw it
    std::vector<visualization_msgs::Marker> geometry;  // its boxes, for creature_markers
    std::optional<WingCommandRequest> command;         // last valid one, re-applied after reset
    std::uint64_t command_step = 0;  // step count when `command` came (the timeout's start)
    bool command_lapsed = false;     // wing_command_timeout passed since: wings held or released
    double command_lag = 0.0;  // s of sim time: how old the state its last command answered was
    std::string controller;    // the node name of its controller (~creatures' `controller`)
    bool awaiting_controller = false;  // the node holds sim time for its first command
    bool controller_missing = false;   // controller_wait_timeout passed without one
  };
  /// A wing command answering a state (its stamp) older than this (s of sim time) is a
  /// controller falling behind: warned, and shown on /diagnostics.
  static constexpr double kCommandLagWarning = 0.1;
  /// A frame of flapsim/get_state, set_state or apply_wrench's `reference_frame`, in the world.
  struct ReferenceFrame {
    std::string name;      // "" (the world) or "<creature>/<link>"
    std::string creature;  // "" (the world) or the link's creature
    FrameMotion motion;    // in the world
  };

  /// Spawns the creatures of ~creatures, with their wing commands. ParamError naming a bad one.
  void spawnConfigured();
  // Returns (and logs as warnings) the joint values too stiff for an explicit step, which act
  // implicitly (flapsim::implicitJointValues), and the shapes it ignores (flapsim::geometryNotes),
  // each line prefixed with the creature.
  std::vector<std::string> spawn(const std::string& name, const std::string& urdf_xml,
                                 const std::string& source, const flapsim::Pose& pose,
                                 const flapsim::Twist& twist);
  void advertiseCreature(Creature& c, const std::string& urdf_xml);
  void remove(const std::string& name);
  /// Wing commands of a step request: all or nothing; InputError naming the cause.
  void applyWingCommands(const std::vector<std::string>& creatures,
                         const std::vector<flapsim::WingCommand>& commands);
  /// Records a command accepted for `c` now (re-applied after a reset; starts its timeout).
  void commanded(Creature& c, WingCommandRequest request);
  Creature* find(const std::string& name);
  /// `name` as a reference frame for a request about `creature`: "" or the world frame, a
  /// creature (its root link), "<creature>/<link>" (or "<creature>::<link>"), or a link of
  /// `creature`. InputError naming it if there is no such frame.
  ReferenceFrame referenceFrame(const std::string& name, const std::string& creature);

  /// Steps up to `steps` fixed steps in slices, publishing at every publish boundary crossed
  /// and reporting creatures the watchdog froze; stops early on shutdown or once
  /// `wall_budget` seconds of wall time have passed (<= 0: no budget). Returns the steps
  /// taken.
  std::uint64_t advance(std::uint64_t steps, double wall_budget = 0.0);
  /// Steps until the first wing command timeout falls due (UINT64_MAX: none).
  std::uint64_t stepsToTimeout() const;
  /// Holds or releases the wings of each creature whose command timed out at this step.
  void applyTimeouts();
  /// True while the node holds sim time for the first wing command of a creature's controller
  /// (creatures naming a `controller`; unpaused, for up to ~controller_wait_timeout of wall
  /// time): announces the wait, and sends the awaited creatures' state again to controllers
  /// that connected after it went out. Once the time passes it names the controllers that did
  /// not answer and the node runs without them (controller_wait.cpp).
  bool holdForControllers();
  /// Logs each creature the watchdog froze, once, and republishes the diagnostics.
  void reportDivergences();
  void publishDiagnostics();
  void publishAll();
  /// What a new subscriber of /clock, ~aero_markers, ~creature_states or a creature's
  /// joint_states, odom and imu gets at once (so a paused world is seen as soon as rviz, a
  /// recorder or `rostopic echo` connects): the messages of the current step. (/tf: see
  /// TfPublisher.)
  rosgraph_msgs::Clock clockMsg() const;
  tf2_msgs::TFMessage tfMsg(const ros::Time& stamp) const;
  visualization_msgs::MarkerArray aeroMarkerArray(const ros::Time& stamp) const;
  /// ~view_markers: the readout of sim time and height in the camera's frame.
  visualization_msgs::MarkerArray viewMarkerArray(const ros::Time& stamp) const;
  /// Latched ~creature_markers: every creature's geometry (after each spawn and delete).
  void publishCreatureMarkers();
  /// Latched /tf_static: every creature's fixed joints (after each spawn and delete).
  void publishStaticTransforms();
  void publishCreature(const Creature& c, const ros::Time& stamp);
  /// Its joint_states, odom and imu (to their subscribers).
  void publishCreatureState(const Creature& c, const ros::Time& stamp);
  sensor_msgs::Imu imuMsgOf(const Creature& c, const flapsim::CreatureState& s,
                            const ros::Time& stamp);
  /// Moves the view frames (flapsim/view, flapsim/camera) to the creatures at `stamp`.
  void updateView(const ros::Time& stamp);
  ros::Time now() const;
  void restartPacing();
  /// Logs `message` as a warning unless one of this kind about this creature was logged in
  /// the last 10 s (WarningLimiter); then only at debug level.
  void warnThrottled(const std::string& kind, const std::string& creature,
                     const std::string& message);

  // Services and callbacks (simulator_services.cpp).
  /// A refused request: `res` says `refusal` + the error, and a throttled warning too (its
  /// kind: the service, the first word of `refusal`, and the error's kind).
  template <class Response>
  void refuse(Response& res, const std::string& refusal, const std::string& creature,
              const flapsim::InputError& e);
  /// Runs `body`, which fills in `res` (but its `success`); an InputError it throws makes the
  /// request refused (refuse). Returns true (the call itself is answered).
  template <class Response, class Body>
  bool serve(Response& res, const std::string& refusal, const std::string& creature, Body body);
  void advertiseServices();
  void onWingCommand(const std::string& creature, const flapsim::WingCommand::ConstPtr& msg);
  bool onReset(std_srvs::Empty::Request& req, std_srvs::Empty::Response& res);
  bool onPause(std_srvs::Empty::Request& req, std_srvs::Empty::Response& res);
  bool onUnpause(std_srvs::Empty::Request& req, std_srvs::Empty::Response& res);
  bool onStep(flapsim::Step::Request& req, flapsim::Step::Response& res);
  bool onSpawn(flapsim::SpawnCreature::Request& req, flapsim::SpawnCreature::Response& res);
  bool onDelete(flapsim::DeleteCreature::Request& req, flapsim::DeleteCreature::Response& res);
  bool onGetState(flapsim::GetState::Request& req, flapsim::GetState::Response& res);
  bool onSetState(flapsim::SetState::Request& req, flapsim::SetState::Response& res);
  bool onApplyWrench(flapsim::ApplyWrench::Request& req, flapsim::ApplyWrench::Response& res);
  bool onClearWrenches(flapsim::ClearWrenches::Request& req, flapsim::ClearWrenches::Response& res);
  bool onGetPhysics(flapsim::GetPhysics::Request& req, flapsim::GetPhysics::Response& res);
  bool onSetPhysics(flapsim::SetPhysics::Request& req, flapsim::SetPhysics::Response& res);
  flapsim::CreatureStates creatureStatesMsg(const ros::Time& stamp) const;
  /// dynamic_reconfigure: applies what can change while running, all or nothing; a refused
  /// change is logged naming its cause and the config is put back to what runs.
  void onReconfigure(flapsim::FlapsimConfig& config, std::uint32_t level);
  /// Applies a config (dynamic_reconfigure's or flapsim/set_physics'), all or nothing: throws
  /// InputError naming the cause and changes nothing.
  void applyConfig(const flapsim::FlapsimConfig& config);
  /// What runs, as a dynamic_reconfigure config.
  flapsim::FlapsimConfig runningConfig() const;
  flapsim::FlapsimConfig launch_config_;  // what ran at start-up: flapsim/reset restores it

  NodeParams params_;
  ros::CallbackQueue queue_;
  ros::NodeHandle nh_;
  ros::NodeHandle pnh_;
  flapsim::World world_;
  std::uint64_t step_ns_;
  std::uint64_t publish_every_;  // steps between publications
  bool paused_;
  std::uint64_t published_step_ = UINT64_MAX;  // step count of the last publication
  std::uint64_t slice_steps_ = 1;              // steps per slice (see advance())

  std::uint64_t timeout_steps_ = 0;  // wing_command_timeout in steps (0: none)
  bool holding_ = false;             // holding sim time for controllers (holdForControllers)
  double held_ = 0.0;                // s of wall time held for them so far (unpaused)
  ros::WallTime held_wall_;          // of the last check while held and unpaused
  ros::WallTime resent_wall_;        // of the last state sent again to awaited controllers
  std::size_t awaited_count_ = 0;    // creatures held for at the last check

  std::vector<std::unique_ptr<Creature>> creatures_;  // in spawn order
  ros::Publisher clock_pub_, marker_pub_, creature_marker_pub_, diagnostics_pub_;
  ros::Publisher states_pub_;       // ~creature_states
  ros::Publisher view_marker_pub_;  // ~view_markers
  std::unique_ptr<TfPublisher> tf_;
  ros::WallTime clock_wall_;  // of the last /clock while paused
  boost::recursive_mutex reconfigure_mutex_;
  std::unique_ptr<dynamic_reconfigure::Server<flapsim::FlapsimConfig>> reconfigure_;
  std::mt19937_64 imu_rng_;  // the IMU noise, seeded from ~imu/seed
  std::normal_distribution<double> imu_normal_;
  ViewFollower view_{kViewTimeConstant};           // the view frame, updated at each publication
  ViewFollower view_distance_{kViewTimeConstant};  // the camera's distance (in x)
  ros::WallTime diagnostics_wall_;                 // of the last diagnostics
  std::vector<ros::ServiceServer> services_;

  ros::WallTime pace_wall_;      // wall time at the pacing anchor
  std::uint64_t pace_step_ = 0;  // step count at the pacing anchor
  WarningLimiter warnings_;      // throttled warnings by cause
};

}  // namespace flapsim_ros
