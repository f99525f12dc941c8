// Real air for one flight outside flight_check: what flight_check --real-air draws for its first
// start from a seed (the steady wind, the gyro bias, the roll torque and the push on a wing with
// their times), for the disturbance node and afc.launch real_air:=true, so that the ROS flight
// meets the disturbances of flight_check --real-air --seed N. ROS-free; no clock.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "flapsim/cli_args.h"
#include "flapsim/creature_model.h"
#include "flapsim/flight_check.h"

namespace flapsim {

/// What a real-air flight draws (realAirParams' settings, episodeStarts' draws).
struct RealAirDraws {
  Vec3 wind = Vec3::Zero();       // m/s, world frame, steady from t = 0
  Vec3 gyro_bias = Vec3::Zero();  // rad/s, added to the gyro's reading
  /// N m about the root link's x axis as it points when the torque starts (its sign drawn);
  /// 0: none.
  double torque = 0.0;
  double torque_time = 0.0;      // s of sim time
  double torque_duration = 0.0;  // s
  /// N, vertical in the world (> 0: up; its sign drawn) at force_link's centre of mass; 0: none.
  double force = 0.0;
  double force_time = 0.0;      // s of sim time
  double force_duration = 0.0;  // s
  std::string force_link;       // a wing drawn among the creature's
};

/// How hard real air's two impulses are on a creature: the roll rate each would give it held
/// rigid (its joints as spawned, level) in vacuum, its angular impulse over the creature's roll
/// inertia about its centre of mass: the torque's, and the push's on the wing whose centre of
/// mass lies farthest from the creature's along y. The air's damping and the controller are
/// what must keep the real rate far below these.
struct RealAirSpinUp {
  RealAirImpulses impulses;   // realAirImpulses(model)
  double roll_inertia = 0.0;  // kg m^2, about the x axis through the centre of mass
  double push_arm = 0.0;      // m: the pushed wing's centre of mass from the creature's, along y
  double torque_rate = 0.0;   // rad/s: torque x its duration / roll_inertia
  double push_rate = 0.0;     // rad/s: push x push_arm x its duration / roll_inertia
};
RealAirSpinUp realAirSpinUp(const CreatureModel& model);

/// flight_check --real-air's line about them.
std::string realAirSpinUpLine(const RealAirSpinUp& s);

/// How to draw them.
struct RealAirDrawParams {
  std::uint64_t seed = FlightCheckParams().seed;  // flight_check --seed
  /// s: flight_check --duration; the torque's and the push's times are drawn in its 10-60 %.
  double duration = FlightCheckParams().duration;
  std::optional<double> torque;  // N m: this size instead of real air's (>= 0; 0: none)
  std::optional<double> force;   // N: this push instead of real air's (>= 0; 0: none)
};

/// The draws of flight_check --real-air --seed `params.seed` --duration `params.duration` for
/// its first start (every start's draws come from streams of their own: the first start's are
/// the same whatever --starts), on `model`, with the magnitudes of realAirParams (afc_1:
/// 0.043 N m, 0.90 N) unless given. Deterministic. Throws InputError naming a bad parameter.
RealAirDraws realAirDraws(const CreatureModel& model, const RealAirDrawParams& params);

/// One line per disturbance for a log: the wind, the gyro bias, the torque and the push with
/// their times, durations and link.
std::string describeRealAirDraws(const RealAirDraws& draws);

/// The options of `disturbance --print` (the disturbance node's draws without ROS: what
/// afc.launch real_air:=true gives the simulator's air/wind and the controller's ~gyro_bias).
struct RealAirPrintOptions {
  RealAirDrawParams draw;
  std::string urdf;           // the creature's URDF file (required)
  std::string print = "all";  // wind, gyro_bias or all
};

/// `disturbance --print`'s flags over `options`.
CliParser realAirPrintCli(RealAirPrintOptions& options);

/// What `disturbance --print` writes: `wind` and `gyro_bias` as a YAML list of three numbers
/// (every bit of the double), `all` as describeRealAirDraws.
std::string realAirPrint(const RealAirPrintOptions& options, const RealAirDraws& draws);

}  // namespace flapsim
