// What rviz draws of the world: each creature's geometry as markers in its link frames, and a
// view frame that follows the creatures. No node handles: pure functions and a small filter,
// tested without a master.
#pragma once

#include <geometry_msgs/TransformStamped.h>
#include <ros/time.h>
#include <visualization_msgs/Marker.h>

#include <string>
#include <vector>

#include "flapsim/creature_model.h"
#include "flapsim/types.h"
#include "flapsim/world.h"

namespace flapsim_ros {

/// Frame id of the view frame: the smoothed centroid of the creatures, axes of the world.
constexpr const char* kViewFrame = "flapsim/view";
/// Time constant (s of sim time) with which the view frame follows the creatures: slow enough
/// to hide the flapping, fast enough to keep a climbing unit in view.
constexpr double kViewTimeConstant = 0.5;

/// The visual geometry of a creature's URDF (boxes, cylinders, spheres; colours from its
/// materials, grey without one) as markers in the frames "<creature>/<link>", namespace
/// "<creature>", frame-locked and stamped 0 (rviz draws them at the latest transform, so they
/// are published once per spawn). A link without visuals is drawn from its collision
/// geometry. Throws flapsim::InputError if the URDF does not parse.
std::vector<visualization_msgs::Marker> creatureMarkers(const std::string& creature,
                                                        const std::string& urdf_xml,
                                                        const std::string& source);

/// The centre of mass of a creature in the world (mass-weighted link COMs; the mean link
/// origin if it has no mass).
flapsim::Vec3 centreOfMass(const flapsim::CreatureModel& model, const flapsim::CreatureState& s);

/// The transform `world_frame` -> kViewFrame at `position`, axes of the world.
geometry_msgs::TransformStamped viewTransform(const flapsim::Vec3& position, const ros::Time& stamp,
                                              const std::string& world_frame);

/// Double exponential smoothing of the creatures' centroid over sim time (s1 = EMA of the
/// samples, s2 = EMA of s1, position 2 s1 - s2): it hides the flapping yet follows a climb or
/// a fall at constant speed without lag. The first sample is taken as it is; going back in
/// time (a reset) starts afresh.
class ViewFollower {
 public:
  explicit ViewFollower(double time_constant) : time_constant_(time_constant) {}

  /// Feeds the centroid at sim time `t` (s); returns the smoothed position.
  const flapsim::Vec3& update(const flapsim::Vec3& centroid, double t);
  const flapsim::Vec3& position() const { return position_; }

 private:
  double time_constant_;
  bool started_ = false;
  double t_ = 0.0;
  flapsim::Vec3 s1_ = flapsim::Vec3::Zero(), s2_ = flapsim::Vec3::Zero();
  flapsim::Vec3 position_ = flapsim::Vec3::Zero();
};

}  // namespace flapsim_ros
