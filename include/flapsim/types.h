// Small geometric value types shared by the core (no Bullet, no ROS).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <stdexcept>
#include <string>

namespace flapsim {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

/// A rigid transform: position and orientation of a frame in its parent frame.
struct Pose {
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();

  Vec3 apply(const Vec3& p) const { return position + orientation * p; }
  Pose operator*(const Pose& child) const {
    return Pose{apply(child.position), (orientation * child.orientation).normalized()};
  }
  Pose inverse() const {
    Quat inv = orientation.conjugate();
    return Pose{-(inv * position), inv};
  }
};

/// Builds a pose from URDF-style xyz and roll-pitch-yaw (fixed axes X, Y, Z).
Pose poseFromXyzRpy(const Vec3& xyz, const Vec3& rpy);

/// The bank of a body at `orientation`: asin(world_up . body_left), rad (> 0: its right side
/// low).
double bankAngle(const Quat& orientation);

/// Linear and angular velocity, both expressed in the world frame.
struct Twist {
  Vec3 linear = Vec3::Zero();
  Vec3 angular = Vec3::Zero();
};

/// Raised for a malformed or unsupported creature description (URDF).
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Raised for a bad request to a running world: unknown names, NaN, wrong
/// lengths, taken names. The world is unchanged when it is thrown.
class InputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

}  // namespace flapsim
