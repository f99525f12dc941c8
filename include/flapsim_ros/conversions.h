// Conversions between core structs and ROS messages. No node handles, no
// parameters: pure functions, tested without a master.
#pragma once

#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Transform.h>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <ros/time.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <visualization_msgs/Marker.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "flapsim/ApplyWrench.h"
#include "flapsim/CreatureStates.h"
#include "flapsim/SetState.h"
#include "flapsim/WingCommand.h"
#include "flapsim/creature_model.h"
#include "flapsim/sensors.h"
#include "flapsim/stroke.h"
#include "flapsim/types.h"
#include "flapsim/world.h"
#include "flapsim_ros/params.h"

namespace flapsim_ros {

geometry_msgs::Pose toMsg(const flapsim::Pose& pose);
geometry_msgs::Transform toTransformMsg(const flapsim::Pose& pose);
geometry_msgs::Twist toMsg(const flapsim::Twist& twist);
/// An all-zero quaternion (a default-constructed message) reads as identity;
/// other quaternions are passed on as they are (the world rejects bad ones).
flapsim::Pose fromMsg(const geometry_msgs::Pose& pose);
flapsim::Twist fromMsg(const geometry_msgs::Twist& twist);

/// Sim time of `steps` fixed steps of `step_ns` nanoseconds: exact, no rounding drift.
ros::Time simTime(std::uint64_t steps, std::uint64_t step_ns);
/// A time in seconds with 9 decimals, e.g. "1.150000000".
std::string formatTime(const ros::Time& t);
/// A step size in whole nanoseconds (rounded); >= 1.
std::uint64_t stepNanoseconds(double step_size);

/// Frame id of a creature's link: "<creature>/<link>".
std::string linkFrame(const std::string& creature, const std::string& link);

/// A wing command in core terms: joint names (empty = all wing joints) and strokes.
struct WingCommandRequest {
  std::vector<std::string> joints;
  std::vector<flapsim::StrokeCommand> strokes;
};

/// Checks the message's array lengths (the values and joint names are checked
/// by World::setWingCommands). Throws flapsim::InputError naming the problem.
WingCommandRequest fromMsg(const flapsim::WingCommand& msg);
flapsim::WingCommand toMsg(const WingCommandRequest& request);
/// The wing commands of a flapsim/step request in core terms, converted only (fromMsg):
/// World::setWingCommands checks them, all or nothing. Throws flapsim::InputError for as
/// many commands as creatures, or a message fromMsg refuses (naming the creature).
std::vector<flapsim::CreatureWingCommand> stepCommands(
    const std::vector<std::string>& creatures, const std::vector<flapsim::WingCommand>& commands);

/// Movable joints in URDF order with positions and velocities.
sensor_msgs::JointState jointStateMsg(const flapsim::CreatureModel& model,
                                      const flapsim::CreatureState& state, const ros::Time& stamp);

/// Odometry of the root link: pose in `world_frame`, twist (of the root link
/// frame's origin) in the child frame "<creature>/<root link>", per REP 105.
nav_msgs::Odometry odometryMsg(const std::string& creature, const flapsim::CreatureModel& model,
                               const flapsim::CreatureState& state, const ros::Time& stamp,
                               const std::string& world_frame);

/// A flapsim/set_state request in core terms: the named joints take the given positions and
/// velocities (either list may be empty), the others keep those of `current`. Throws
/// flapsim::InputError naming an unknown, fixed or repeated joint or a list of the wrong
/// length (World::setState checks the values).
flapsim::StateRequest stateRequest(const flapsim::CreatureModel& model,
                                   const flapsim::CreatureState& current,
                                   const flapsim::SetState::Request& req);

/// A flapsim/apply_wrench request in core terms (World::applyWrench checks the values), as
/// given: in the request's reference frame.
flapsim::ExternalWrench fromMsg(const flapsim::ApplyWrench::Request& req);

/// A frame's pose and the twist of its origin.
struct FrameMotion {
  flapsim::Pose pose;
  flapsim::Twist twist;
};
/// `body` (in the world) seen from the reference frame `frame` (in the world), as
/// gazebo_msgs/GetModelState and GetLinkState give it: the pose in the frame, and the
/// difference of the two origins' linear and the two angular velocities, in the frame's axes.
FrameMotion toFrame(const FrameMotion& frame, const FrameMotion& body);
/// The inverse of toFrame: `relative` (in `frame`) in the world.
FrameMotion fromFrame(const FrameMotion& frame, const FrameMotion& relative);
/// A wrench given in the reference frame `frame` (force, torque and point in its axes and
/// about its origin, as gazebo_msgs/ApplyBodyWrench), in the world frame.
flapsim::ExternalWrench toWorld(const flapsim::ExternalWrench& wrench, const flapsim::Pose& frame);

/// The IMU of the root link, frame "<creature>/<root link>": flapsim::imuReading() (the
/// reading the episodes of evolution take): orientation in the world, and in the link's axes
/// its angular velocity and what an accelerometer at its centre of mass reads,
/// `acceleration` - `gravity` (at rest: +g up), each plus `noise` (standard deviations, drawn
/// from `draw`, which returns a standard normal sample); the covariances are the noise
/// variances (the orientation's: of its rotation vector's components).
sensor_msgs::Imu imuMsg(const std::string& creature, const flapsim::CreatureModel& model,
                        const flapsim::CreatureState& state, const flapsim::Vec3& acceleration,
                        const flapsim::Vec3& gravity, const ros::Time& stamp,
                        const flapsim::ImuNoise& noise = flapsim::ImuNoise(),
                        const std::function<double()>& draw = nullptr);

/// An IMU message in core terms (imuMsg's inverse; the orientation normalised). Throws
/// flapsim::InputError for a non-finite value or a zero quaternion.
flapsim::ImuReading fromMsg(const sensor_msgs::Imu& msg);

/// The joint positions and velocities of a joint_states message as one value per joint of
/// `model` (fixed joints and joints the message does not name: 0). Throws
/// flapsim::InputError for a name `model` does not have, a movable joint the message does not
/// name, lists of other lengths than the names or a non-finite value.
void jointVectors(const sensor_msgs::JointState& msg, const flapsim::CreatureModel& model,
                  std::vector<double>& positions, std::vector<double>& velocities);

/// Force arrows: one per aero link from its centre of mass (namespace
/// "<creature>"), and one per cell from its centre (namespace
/// "<creature>/cells") if `params.per_cell` and the cells were recorded.
/// Arrows shorter than 1 micrometre are left out.
std::vector<visualization_msgs::Marker> aeroMarkers(const std::string& creature,
                                                    const std::vector<flapsim::LinkAero>& aero,
                                                    const MarkerParams& params,
                                                    const ros::Time& stamp,
                                                    const std::string& world_frame);

}  // namespace flapsim_ros
