// Parameters of the simulator node, read in one place into plain structs.
// The parser works on an XmlRpc value (testable without a master); the loader
// fetches the node's private namespace and resolves `urdf_param` entries.
#pragma once

#include <ros/node_handle.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "flapsim/stroke.h"
#include "flapsim/types.h"
#include "flapsim/world.h"
#include "flapsim_ros/param_reader.h"  // ParamError

namespace flapsim_ros {

/// One creature to spawn at start-up. Exactly one URDF source is set.
struct CreatureSpec {
  std::string name;
  std::string urdf_file;   // path to a URDF file
  std::string urdf_param;  // name of a parameter holding URDF text
  std::string urdf_xml;    // URDF text (also filled in from urdf_param by the loader)
  flapsim::Pose pose;      // root link in the world frame
  flapsim::Twist twist;    // root velocity, world frame
  /// Optional stroke for all wing joints from t = 0 (one entry) or per wing
  /// joint in URDF order.
  std::vector<flapsim::StrokeCommand> wing_command;
  /// The node name of the controller that commands it (e.g. "/hover/hover_controller"); not
  /// empty: the simulation does not step until its first wing command arrives (or
  /// `controller_wait_timeout` passes), so that the controller flies it from t = 0.
  std::string controller;
};

/// Force arrows on `~aero_markers`.
struct MarkerParams {
  bool enabled = true;
  double scale = 2.0;     // arrow length per force, m/N
  bool per_cell = false;  // also one arrow per surface cell (costs time)
  double width = 0.012;   // arrow shaft diameter, m
};

/// `<creature>/imu`: Gaussian noise (standard deviations; 0: none) from a seeded generator,
/// so a run with noise repeats exactly.
struct ImuParams {
  double orientation_noise = 0.0;          // rad (each rotation-vector component, root frame)
  double angular_velocity_noise = 0.0;     // rad/s
  double linear_acceleration_noise = 0.0;  // m/s^2
  int seed = 0;
};

/// What a creature's wings do once `wing_command_timeout` passes without a command: "hold"
/// (the wing motors hold the wings where they are) or "release" (the wing joints go passive).
using CommandTimeoutAction = flapsim::CommandTimeout::Action;

/// The frame flapsim/camera (the view of config/flapsim.rviz): it looks at flapsim/view, the
/// creatures' smoothed centroid, from `yaw` and `pitch` (rad, rviz's orbit angles) at
/// `distance`, or farther when the creatures spread: far enough to keep them all in view.
struct ViewParams {
  double distance = 2.5;  // m, the least distance
  double yaw = 0.8;       // rad, about world z from +x
  double pitch = 0.35;    // rad, above the horizontal
};

struct NodeParams {
  flapsim::WorldParams world;
  double publish_rate = 100.0;    // Hz of sim time (rounded to whole steps), in [0.01, 1e6]
  double real_time_factor = 1.0;  // sim seconds per wall second; 0 = as fast as possible
  /// flapsim/step requests for more steps are refused (the node serves nothing while it
  /// steps a request).
  int max_steps_per_call = 100000;
  /// Directories flapsim/spawn may read `urdf_file` from (and below): a list, or a string of
  /// ':'-separated directories (a launch argument). Not set or "": the directories on
  /// ROS_PACKAGE_PATH and the node's working directory (the loader's defaults; the parser
  /// leaves it empty).
  std::vector<std::string> urdf_roots;
  /// s of sim time after a creature's last wing command (topic, flapsim/step or its
  /// `wing_command` parameter) at which its wings stop beating; 0: never.
  double wing_command_timeout = 0.0;
  CommandTimeoutAction wing_command_timeout_action = CommandTimeoutAction::kHold;
  /// s of wall time, while unpaused, the node holds sim time for the first wing command of
  /// each creature that names a `controller`; then it says which never answered and runs
  /// without them. 0: no wait.
  double controller_wait_timeout = 30.0;
  ViewParams view;
  bool paused = false;  // start paused
  std::string world_frame = "world";
  MarkerParams markers;
  ImuParams imu;
  std::vector<CreatureSpec> creatures;
  std::vector<std::string> unknown_keys;  // top-level keys this node does not read
};

/// Parses the node's private namespace given as an XmlRpc struct (missing
/// keys keep their defaults). Throws ParamError naming the bad parameter.
NodeParams parseNodeParams(const XmlRpc::XmlRpcValue& params);

/// Parses one entry of `creatures`.
/// `where` names the entry in messages, e.g. "creatures[2]".
CreatureSpec parseCreatureSpec(const XmlRpc::XmlRpcValue& entry, const std::string& where);

/// Empty if `name` can be a creature name (a ROS graph name component used in
/// topic and frame names: a letter, then letters, digits or '_'), else why not.
std::string validateCreatureName(const std::string& name);

/// Reads `pnh`'s namespace from the parameter server and parses it; fills in
/// `urdf_xml` of creatures that name a `urdf_param` (resolved relative to `pnh`).
NodeParams loadNodeParams(const ros::NodeHandle& pnh);

/// Sim time a subscriber of the state topics (/clock, /tf, odom, imu, joint_states, power) may
/// fall behind before its oldest messages are dropped: at rtf 0 and in lockstep the node runs
/// ahead of a recorder, which used to lose messages from a 10-message queue.
constexpr double kPublishQueueSeconds = 10.0;
/// Those topics' queue: kPublishQueueSeconds of messages at publish_rate, in [10, 10,000].
int publishQueueSize(const NodeParams& p);
/// Steps between publications: 1 / (publish_rate step_size), rounded, at least 1.
std::uint64_t publishEvery(const NodeParams& p);

}  // namespace flapsim_ros
