// A hover flight: the hover creature flown by flapsim::HoverController in a World, with the
// figures of issue 24's target (height band, attitude, vertical oscillation per stroke,
// mechanical power) and the figure of merit. Used by flight_check --hover and the tests.
// ROS-free; no clock.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>

#include "flapsim/creature_model.h"
#include "flapsim/evolve.h"
#include "flapsim/hover_controller.h"
#include "flapsim/sensors.h"
#include "flapsim/world.h"

namespace flapsim {

struct HoverFlightParams {
  double duration = 60.0;              // s
  double settle = 10.0;                // s before the figures count
  double control_period = 0.01;        // s between controller updates (the node's IMU rate: 100 Hz)
  double start_roll = 0.0;             // rad, about x
  double start_pitch = 0.0;            // rad, about y
  Vec3 start_rate = Vec3::Zero();      // rad/s: the root's angular velocity at the start (world)
  std::optional<double> start_height;  // m, of the root link's origin; none: the setpoint
  /// The IMU's orientation and angular velocity noise (imuReading, normals from a generator
  /// seeded with noise_seed); 0: the exact state, as the simulator's IMU by default.
  ImuNoise imu_noise;
  std::uint64_t noise_seed = 0;
  bool end_on_flip = false;  // the root's up axis below the horizon ends the flight
  /// An episode's disturbances beyond the wind and the IMU's noise (flight_check --hover
  /// --real-air; none by default, and none in the hover preset's episodes): with `gusts`, the
  /// gusts of `gust_start` at their times (applyEpisodeGusts, with gusts' sizes and
  /// durations), the gyro bias of `gust_start` added to the IMU's angular velocity, and the
  /// altimeter's noise of `gusts` (altitude_noise, m) on the height the controller reads.
  std::optional<EpisodeParams> gusts;
  EpisodeStart gust_start;
  /// A bench's hook (bench/hover_oracle): called with each update's time (s) and the strokes
  /// the controller gave for it, it may replace them; none: the controller's strokes fly.
  std::function<void(double time, std::array<StrokeCommand, 2>& strokes)> override_strokes;
  WorldParams world;  // its air's wind included (ground off by default)
  HoverFlightParams() { world.ground = false; }
};

/// Empty if valid, else a message naming the bad field.
std::string validateHoverFlightParams(const HoverFlightParams& params);

struct HoverFlightResult {
  // After the settling time:
  double min_height = 0.0, max_height = 0.0;  // m, of the root link's origin
  double min_upright = 1.0;                   // lowest up-component of the root body
  /// m: the largest height range within one stroke period (at the frequency commanded).
  double max_stroke_oscillation = 0.0;
  double positive_power = 0.0;  // W: the motors' mean positive mechanical power
  double net_power = 0.0;       // W: their mean net power
  double mean_frequency = 0.0;  // Hz, commanded
  /// m: rms of the height less the setpoint over the steps after the settling time (NaN if
  /// none).
  double altitude_rms = 0.0;
  /// rad: the mean over the steps after the settling time of the root's bank,
  /// asin(world_up . body_left) (> 0: right side low).
  double mean_bank = 0.0;
  bool flipped = false;       // the root's up axis went below the horizon (end_on_flip: it ended)
  Vec3 drift = Vec3::Zero();  // m: the root's horizontal offset from its start at the end
  double mass = 0.0;          // kg
  // From t = 0:
  double start_tilt = 0.0;      // rad: the root's tilt at the start (start roll and pitch)
  double lowest_upright = 1.0;  // lowest up-component of the root body over the whole flight
  double largest_bank = 0.0;    // rad: the largest |bank| of the root over it (as mean_bank's)
  double lowest_height = 0.0;   // m, of the root link's origin, over the whole flight
  /// m: how far the root link's origin sank below both its start height and the setpoint.
  double start_sag = 0.0;
  double specificPower() const { return mass > 0.0 ? positive_power / mass : 0.0; }
};

/// Flies `model` (make_creature --layout hover: wings kHoverWingJoints) from
/// `params.start_height` (`controller`'s altitude if none), level but for the start roll and
/// pitch, for `params.duration` (less after a flip with end_on_flip). Throws InputError
/// for bad parameters.
HoverFlightResult flyHover(const CreatureModelPtr& model, const HoverControllerParams& controller,
                           const HoverFlightParams& params);

/// The area a creature's wings sweep with `amplitude` (rad, each way) about their stroke
/// hinges: per wing joint, amplitude x r^2 (a sector of 2 amplitude), r the farthest corner of
/// the wing's boxes from the hinge's axis (m^2).
double strokeDiskArea(const CreatureModel& model, double amplitude);

/// The ideal (actuator-disk, momentum theory) power to hover a weight (N) on a disk of `area`
/// (m^2) in air of `density`: sqrt(W^3 / (2 rho A)). The figure of merit of a flier is this
/// over its mechanical power.
double idealHoverPower(double weight, double density, double area);

}  // namespace flapsim
