// Parameters of the controller nodes (stroke_controller, ann_controller),
// read in one place into plain structs, and the messages they publish. Pure
// functions of XmlRpc values: testable without a master.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <optional>
#include <string>
#include <vector>

#include "flapsim/WingCommand.h"
#include "flapsim/ann.h"
#include "flapsim/stroke.h"
#include "flapsim_ros/param_reader.h"
#include "flapsim_ros/params.h"  // validateCreatureName

namespace flapsim_ros {

/// stroke_controller: an open-loop stroke per wing pair.
struct StrokeControllerParams {
  std::string creature;  // topic <creature>/wing_command
  int pairs = 1;
  double rate = 10.0;          // Hz (sim time) of re-publication
  double reread_period = 0.5;  // s (wall) between re-reads of the parameters
  // One entry per wing pair (left and right wing get the same stroke).
  std::vector<flapsim::StrokeCommand> strokes;
};

/// Private namespace of stroke_controller. Keys (all optional):
///   creature (default `default_creature`), pairs (1), rate (10),
///   reread_period (0.5), downstroke_rate (40), upstroke_rate (10),
///   amplitude (0.8): each of the last three a number (every pair) or a list
///   with one number per pair; shape (triangle, or sine: flapsim::StrokeShape) for every
///   pair. Throws ParamError naming the bad key.
StrokeControllerParams parseStrokeControllerParams(const XmlRpc::XmlRpcValue& ns,
                                                   const std::string& default_creature);

/// The message: all wing joints in URDF order (joint_names empty), two
/// entries (left, right) per pair.
flapsim::WingCommand strokeCommandMsg(const std::vector<flapsim::StrokeCommand>& strokes);

/// Where ann_controller reads the units from.
enum class AttitudeSource {
  /// The sensors (flapsim/sensors.h), as a real creature would: <creature>/imu (the root
  /// link's orientation and gyro, with the simulator's imu noise), <creature>/joint_states
  /// (the encoders: the other units of a chain through forward kinematics of
  /// <creature>/robot_description) and the altimeter, <creature>/odom's z plus
  /// altitude_noise. The topics are under the simulator's namespace (the parent of
  /// step_service's: /afc/imu for the default /flapsim/step).
  kImu,
  /// The exact orientations of the unit bodies from tf, world -> <creature>/unit<k>_body,
  /// and the root frame's height (the ground truth; no gyro: a network with rate inputs is
  /// refused).
  kTf,
};

/// Lockstep (ann_controller, hover_controller; tests, exact replays): the node drives a paused
/// flapsim_node itself: it reads the state at t, calls step for one control period with its
/// command in the request (not on the topic), and repeats until lockstep_duration (0: forever).
struct LockstepParams {
  bool lockstep = false;
  double lockstep_duration = 0.0;  // s of sim time
  std::string step_service = "/flapsim/step";
  // s, the simulator's step (for the steps per control period); 0 (unset): the parameter
  // step_size next to step_service (/flapsim/step_size), else 0.001.
  double step_size = 0.0;
  double wait_timeout = 30.0;  // s (wall) for connections and the state in lockstep
};

/// Reads the keys lockstep, lockstep_duration, step_service, step_size and wait_timeout into
/// `p`. Throws ParamError naming the bad key.
void readLockstepParams(const ParamReader& d, LockstepParams& p);

/// ann_controller: the evolved network on every unit of a creature.
struct AnnControllerParams : LockstepParams {
  std::string creature;      // tf frames <creature>/unit<k>_body, topic <creature>/wing_command
  std::string weights_file;  // YAML written by `evolve` (required)
  int pairs = 1;
  AttitudeSource attitude_source = AttitudeSource::kImu;
  std::optional<double> altitude;  // m: the root link frame's height to hold; unset: climb
  double altitude_noise = 0.0;     // m: the altimeter's standard deviation (imu source)
  double velocity_noise = 0.0;     // m/s: the ground-speed sensor's, per axis (imu source)
  /// rad/s: a constant bias added to the gyro's reading (imu source), in the IMU's axes, as
  /// flight_check's --gyro-bias adds a start's (afc.launch real_air:=true: the one drawn).
  flapsim::Vec3 gyro_bias = flapsim::Vec3::Zero();
  int noise_seed = 0;  // seeds the altimeter's and ground speed's noise
  std::string world_frame = "world";
  double rate = 0.0;  // Hz (sim time); 0: 1 / control_period of the weights file
  // Lockstep (LockstepParams; tests, exact replays): read the unit bodies at t from tf.
  bool lockstep_wait_for_start = false;  // wait for a call of ~start before stepping
  // Lockstep only (set without lockstep: ParamError): the creatures this node flies and steps
  // together, each with the network on its `pairs` units (a flock in one lockstep); empty:
  // {creature}.
  std::vector<std::string> lockstep_creatures;
};

/// Private namespace of ann_controller. Keys: weights (required), creature,
/// pairs, attitude_source (imu or tf), altitude, altitude_noise, velocity_noise, gyro_bias
/// (three numbers, each within +-1000 rad/s; with attitude_source tf: ParamError), noise_seed,
/// world_frame,
/// rate, lockstep, lockstep_duration,
/// lockstep_wait_for_start, lockstep_creatures, step_service, step_size, wait_timeout.
/// Throws ParamError naming the bad key.
AnnControllerParams parseAnnControllerParams(const XmlRpc::XmlRpcValue& ns,
                                             const std::string& default_creature);

/// Empty if ann_controller's parameters suit the network `network` of their weights file, else
/// the reason naming the parameter (`altitude_key`, `attitude_source_key`: their resolved
/// names): ~attitude_source tf for a network that reads the gyro's rates (tf has none), and
/// ~altitude for a network without an altitude input (it could only climb).
std::string annControllerMismatch(const AnnControllerParams& params,
                                  const flapsim::FlapControllerParams& network,
                                  const std::string& attitude_source_key,
                                  const std::string& altitude_key);

/// The message for one set of strokes in FlapUnitLayout order (joint names
/// given, so only the unit wings are driven).
flapsim::WingCommand annCommandMsg(const flapsim::FlapUnitLayout& layout,
                                   const std::vector<flapsim::StrokeCommand>& strokes);

/// The last component of a namespace ("/flock/afc3" -> "afc3"), "" for "/".
std::string namespaceBasename(const std::string& ns);

}  // namespace flapsim_ros
