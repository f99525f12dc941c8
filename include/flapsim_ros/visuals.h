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
#include "flapsim_ros/params.h"

namespace flapsim_ros {

/// Frame id of the view frame: the smoothed centroid of the creatures, axes of the world.
constexpr const char* kViewFrame = "flapsim/view";
/// Frame id of the camera of config/flapsim.rviz (rviz's FrameAligned view along its +x,
/// z up): it looks at the view frame from ViewParams' direction (cameraPose).
constexpr const char* kCameraFrame = "flapsim/camera";
/// rviz's vertical field of view (rad); the camera's distance keeps the creatures inside it.
constexpr double kCameraFieldOfView = 0.785398;
/// Width / height of the view the camera's distance is chosen for (rviz's default window).
constexpr double kCameraAspect = 4.0 / 3.0;
/// m kept between a link's origin and the edge of the view (a wing reaches past its link's
/// origin; the view frame lags a little).
constexpr double kCameraMargin = 0.4;
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

/// How far the camera stands from `target` (flapsim/view), looking at it from `view`'s
/// direction: `least`, or farther, so that every one of `points` lies inside rviz's view (its
/// vertical field of view kCameraFieldOfView, a 4:3 window), kCameraMargin from its edges.
double cameraDistance(const std::vector<flapsim::Vec3>& points, const flapsim::Vec3& target,
                      const ViewParams& view, double least);

/// The camera frame: at `distance` from `target` in the direction of `view` (yaw, pitch), its
/// +x axis pointing at `target`, its z axis up (in the vertical plane of the two).
flapsim::Pose cameraPose(const flapsim::Vec3& target, double distance, const ViewParams& view);

/// A readout for the corner of the view, in the camera frame (frame-locked text, namespace
/// "readout"): sim time and the height of `target` above the ground, e.g.
/// "t = 12.30 s   z = 30.4 m".
visualization_msgs::Marker viewReadout(const ros::Time& stamp, const flapsim::Vec3& target);

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
