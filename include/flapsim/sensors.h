// What a controller of flap units measures, and how: an IMU on the root link (orientation,
// angular velocity and specific force, each with seeded Gaussian noise), the joint encoders
// (exact joint positions and velocities), and an altimeter (the root link frame's height
// with Gaussian noise; through ROS the creature's odometry z stands in for it). The simulator
// node's <creature>/imu and the episodes of evolution read the root through the same
// imuReading() and the units through the same unitSensing(), so what was evolved is what
// flies through ROS. The node's IMU has no delay: the reading stamped t is the state at t, and
// a lockstep controller commands [t, t + P) from it, as an episode does. ROS-free; no clock.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "flapsim/creature_model.h"
#include "flapsim/types.h"
#include "flapsim/world.h"

namespace flapsim {

/// Standard deviations of the IMU's noise (0: exact).
struct ImuNoise {
  /// rad: each component of a rotation vector in the root frame, q_sensed = q exp(n).
  double orientation = 0.0;
  double angular_velocity = 0.0;     // rad/s, per axis
  double linear_acceleration = 0.0;  // m/s^2, per axis
};

/// Empty if every value is finite and in [0, 1000], else a message naming the bad one.
std::string validateImuNoise(const ImuNoise& noise);

/// The root link's IMU: its orientation in the world; in its own axes its angular velocity
/// and the specific force an accelerometer at its centre of mass reads (acceleration -
/// gravity: at rest +g up).
struct ImuReading {
  Quat orientation = Quat::Identity();
  Vec3 angular_velocity = Vec3::Zero();
  Vec3 linear_acceleration = Vec3::Zero();
};

/// The reading of `state`'s root link given its centre of mass's `acceleration`, plus
/// `noise`. The standard normals come from `normal` in a fixed order: for each axis x, y, z
/// the angular velocity's then the acceleration's, then the orientation's three (a zero
/// deviation draws nothing), so a seeded generator repeats a run exactly.
ImuReading imuReading(const CreatureState& state, const Vec3& acceleration, const Vec3& gravity,
                      const ImuNoise& noise, const std::function<double()>& normal);

/// The ground-speed sensor (odometry's twist): `velocity` (m/s, the root's, in its own axes)
/// plus `noise` (m/s) per axis, the standard normals drawn from `normal` for x, y, z in turn
/// (noise 0 draws nothing). Episodes and ann_controller read the root's speed through it.
Vec3 groundSpeedReading(const Vec3& velocity, double noise, const std::function<double()>& normal);

/// A complementary attitude filter on the root IMU's orientation (an extension; the paper's
/// controller reads the exact attitude). Each update turns the estimate by the gyro over the
/// interval (the mean of the previous and this reading's angular velocity, times dt), then
/// moves it the fraction dt / (time_constant + dt) of the way to the reading's orientation.
/// White orientation noise of deviation s is left at about s sqrt(a / (2 - a)), a that
/// fraction (0.1 rad at dt 0.02 s, time_constant 0.2 s: 0.022 rad); the gyro carries the
/// estimate between readings, so a turn is followed without the lag of a plain low-pass.
/// time_constant 0: the reading passes unchanged. The first update (and the first after
/// reset()) takes the reading as it is.
class AttitudeFilter {
 public:
  /// Throws InputError unless time_constant is finite and in [0, 1000] s.
  explicit AttitudeFilter(double time_constant = 0.0);
  /// `reading` with its orientation replaced by the estimate after it, dt (s, > 0) after the
  /// previous update.
  ImuReading update(const ImuReading& reading, double dt);
  /// update() for a reading taken at time `t_ns` (ns, any clock: a ROS stamp's toNSec()):
  /// stepped by the time since the previous call's (in s, (t_ns - previous) x 1e-9, so k x
  /// 0.02 s stamps step by exactly 0.02); the same time again gives the same estimate without
  /// a step, and an earlier one (the world was reset) restarts the filter.
  ImuReading updateAt(const ImuReading& reading, std::int64_t t_ns);
  void reset() {
    estimate_.reset();
    time_.reset();
  }
  double timeConstant() const { return time_constant_; }

 private:
  double time_constant_;
  std::optional<Quat> estimate_;
  Vec3 rate_ = Vec3::Zero();          // the previous reading's angular velocity (body axes)
  std::optional<std::int64_t> time_;  // updateAt's previous t_ns
  ImuReading last_;                   // updateAt's previous result
};

/// The units of a flap-unit creature as its controller senses them.
struct FlapSensing {
  std::vector<Quat> orientations;  // per unit body, in the world
  std::vector<Vec3> rates;         // per unit body, its angular velocity in its own axes (rad/s)
  double altitude = 0.0;           // m: the root link frame's height, as the altimeter reads it
  /// Not a measurement but the task: the altitude to hold (m, the root link frame's); none:
  /// climb.
  std::optional<double> setpoint;
  /// m/s: the root link's velocity in its own axes (odometry's twist, a ground-speed
  /// sensor); none: not sensed.
  std::optional<Vec3> velocity;

  FlapSensing() = default;
  /// Orientations only (rates zero, altitude 0): enough for the paper's network.
  explicit FlapSensing(std::vector<Quat> bodies)
      : orientations(std::move(bodies)), rates(orientations.size(), Vec3::Zero()) {}
};

/// The bodies `body_links` (link indices of `model`) as sensed from the root's IMU reading
/// and the joint encoders: forward kinematics through the joints from the root to each body
/// (orientations, and angular velocities from the joint velocities). `joint_positions` and
/// `joint_velocities` hold one value per model joint (fixed joints' are ignored). Throws
/// InputError for a wrong count or a link index out of range.
FlapSensing unitSensing(const CreatureModel& model, const std::vector<int>& body_links,
                        const ImuReading& imu, const std::vector<double>& joint_positions,
                        const std::vector<double>& joint_velocities, double altitude);

}  // namespace flapsim
